#include "supernodes.hpp"

#include <algorithm>
#include <cassert>
#include <numeric>

namespace velum {
namespace {

// The strictly upper part of P (A + Aᵀ) Pᵀ by column: column c holds the rows r < c, sorted,
// each once (A's pattern may hold (i, j) without (j, i)).
struct UpperPattern {
  std::vector<int> begin, rows;
};

UpperPattern upper_pattern(const SparseMatrix& A, const std::vector<int>& pos) {
  const int n = static_cast<int>(A.cols());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  std::vector<int> count(n + 1, 0);
  for (int j = 0; j < n; ++j)
    for (int k = outer[j]; k < outer[j + 1]; ++k)
      if (const int r = pos[inner[k]], c = pos[j]; r != c) ++count[std::max(r, c) + 1];
  std::partial_sum(count.begin(), count.end(), count.begin());
  std::vector<int> rows(count[n]), next(count.begin(), count.end() - 1);
  for (int j = 0; j < n; ++j)
    for (int k = outer[j]; k < outer[j + 1]; ++k)
      if (const int r = pos[inner[k]], c = pos[j]; r != c)
        rows[next[std::max(r, c)]++] = std::min(r, c);
  UpperPattern up;
  up.begin.assign(n + 1, 0);
  int kept = 0;
  for (int c = 0; c < n; ++c) {
    const auto b = rows.begin() + count[c], e = rows.begin() + count[c + 1];
    std::sort(b, e);
    const auto u = std::unique(b, e);
    for (auto it = b; it != u; ++it) rows[kept++] = *it;
    up.begin[c + 1] = kept;
  }
  rows.resize(kept);
  up.rows = std::move(rows);
  return up;
}

// Elimination tree (Liu's algorithm with path compression).
std::vector<int> elimination_tree(const UpperPattern& up) {
  const int n = static_cast<int>(up.begin.size()) - 1;
  std::vector<int> parent(n, -1), ancestor(n, -1);
  for (int k = 0; k < n; ++k)
    for (int p = up.begin[k]; p < up.begin[k + 1]; ++p)
      for (int i = up.rows[p], next; i != -1 && i < k; i = next) {
        next = ancestor[i];
        ancestor[i] = k;
        if (next == -1) parent[i] = k;
      }
  return parent;
}

// post[k] = the node visited k-th by a depth-first walk of the forest, children in order.
std::vector<int> postorder(const std::vector<int>& parent) {
  const int n = static_cast<int>(parent.size());
  std::vector<int> head(n, -1), next(n, -1), stack, post;
  post.reserve(n);
  for (int j = n - 1; j >= 0; --j)
    if (parent[j] != -1) {
      next[j] = head[parent[j]];
      head[parent[j]] = j;
    }
  for (int root = 0; root < n; ++root) {
    if (parent[root] != -1) continue;
    stack.push_back(root);
    while (!stack.empty()) {
      const int p = stack.back();
      if (const int child = head[p]; child != -1) {
        head[p] = next[child];
        stack.push_back(child);
      } else {
        stack.pop_back();
        post.push_back(p);
      }
    }
  }
  return post;
}

// Walks the row subtrees of L (row i of L: the etree paths from the entries of row i of A up to
// i), calling visit(j, i) for every off-diagonal entry L(i, j), rows in ascending order.
template <class Visit>
void walk_rows(const UpperPattern& up, const std::vector<int>& parent, Visit&& visit) {
  const int n = static_cast<int>(parent.size());
  std::vector<int> mark(n, -1);
  for (int i = 0; i < n; ++i) {
    mark[i] = i;
    for (int p = up.begin[i]; p < up.begin[i + 1]; ++p)
      for (int j = up.rows[p]; mark[j] != i; j = parent[j]) {
        mark[j] = i;
        visit(j, i);
      }
  }
}

}  // namespace

SupernodalStructure analyse_supernodes(const SparseMatrix& A, const std::vector<int>& position,
                                       const Amalgamation& relax, Factor factor) {
  const bool lu = factor == Factor::kLu;
  SupernodalStructure st;
  const int n = st.n = static_cast<int>(A.cols());
  std::vector<int> pos = position;
  if (static_cast<int>(pos.size()) != n) {
    pos.resize(n);
    std::iota(pos.begin(), pos.end(), 0);
  }
  // A postorder of the elimination tree keeps the fill and numbers every subtree, so every
  // supernode with its parent, contiguously.
  {
    const std::vector<int> post = postorder(elimination_tree(upper_pattern(A, pos)));
    std::vector<int> rank(n);
    for (int k = 0; k < n; ++k) rank[post[k]] = k;
    for (int& p : pos) p = rank[p];
  }
  st.order.resize(n);
  for (int i = 0; i < n; ++i) st.order[pos[i]] = i;
  const UpperPattern up = upper_pattern(A, pos);
  const std::vector<int> parent = elimination_tree(up);
  std::vector<long> count(n, 1);  // entries in each column of L, the diagonal included
  walk_rows(up, parent, [&](int j, int) { ++count[j]; });

  // Fundamental supernodes: column j continues j − 1's when it is its parent and its structure
  // is the same less one row.
  std::vector<int> fund_first;
  for (int j = 0; j < n; ++j)
    if (j == 0 || parent[j - 1] != j || count[j - 1] != count[j] + 1) fund_first.push_back(j);
  const int nf = static_cast<int>(fund_first.size());
  fund_first.push_back(n);
  std::vector<int> fund_of(n);
  for (int s = 0; s < nf; ++s)
    for (int j = fund_first[s]; j < fund_first[s + 1]; ++j) fund_of[j] = s;

  // Relaxed amalgamation, from the root down: the group of fundamental supernodes that starts
  // at s + 1 absorbs s when s's parent is in it (s is then its last child, adjacent in the
  // postorder). Its rows: its columns, then the rows below its last column.
  std::vector<int> group_end(nf), width(nf);
  std::vector<long> below(nf);
  std::vector<double> nonzeros(nf);
  std::vector<char> starts(nf, 1);
  for (int s = 0; s < nf; ++s) {
    group_end[s] = s;
    width[s] = fund_first[s + 1] - fund_first[s];
    below[s] = count[fund_first[s + 1] - 1] - 1;
    for (int j = fund_first[s]; j < fund_first[s + 1]; ++j) nonzeros[s] += count[j];
  }
  for (int s = nf - 2; s >= 0; --s) {
    const int last = fund_first[s + 1] - 1;
    const int p = parent[last] == -1 ? -1 : fund_of[parent[last]];
    const int g = s + 1;
    if (p < g || p > group_end[g]) continue;
    const int w = width[s] + width[g];
    const double m = static_cast<double>(below[g]);
    const double panel = w * m + 0.5 * w * (w + 1.0);
    const double zeros = 1.0 - (nonzeros[s] + nonzeros[g]) / panel;
    const bool merge = w <= relax.widest &&
                       (w <= relax.always || (w <= relax.small && zeros < relax.small_zeros) ||
                        (w <= relax.medium && zeros < relax.medium_zeros) || zeros < relax.zeros);
    if (!merge) continue;
    group_end[s] = group_end[g];
    width[s] = w;
    below[s] = below[g];
    nonzeros[s] += nonzeros[g];
    starts[g] = 0;
  }
  std::vector<int> snode_of(n);
  for (int s = 0; s < nf; ++s)
    if (starts[s]) st.first.push_back(fund_first[s]);
  const int ns = static_cast<int>(st.first.size());
  st.first.push_back(n);
  for (int s = 0; s < ns; ++s)
    for (int j = st.first[s]; j < st.first[s + 1]; ++j) snode_of[j] = s;

  // Rows below each supernode: those of L's column at its last column.
  st.below_begin.assign(ns + 1, 0);
  for (int s = 0; s < ns; ++s)
    st.below_begin[s + 1] = st.below_begin[s] + static_cast<int>(count[st.first[s + 1] - 1] - 1);
  st.rows.resize(st.below_begin[ns]);
  {
    std::vector<int> next(st.below_begin.begin(), st.below_begin.end() - 1);
    walk_rows(up, parent, [&](int j, int i) {
      if (const int s = snode_of[j]; j == st.first[s + 1] - 1) st.rows[next[s]++] = i;
    });
  }

  // Panels, each supernode's L then Uᵀ (LU). Flops: the diagonal block's factorisation, the
  // triangular solve(s) of the rows below, the update (Cholesky: its lower triangle).
  st.l_panel.resize(ns);
  if (lu) st.u_panel.resize(ns);
  for (int s = 0; s < ns; ++s) {
    const std::ptrdiff_t w = st.width(s), m = st.below(s);
    st.l_panel[s] = st.values;
    if (lu) st.u_panel[s] = st.values + (w + m) * w;
    st.values += (lu ? 2 * m + w : m + w) * w;
    st.widest = std::max(st.widest, st.width(s));
    st.most_below = std::max(st.most_below, st.below(s));
    st.flops += lu ? 2.0 / 3.0 * w * w * w + 2.0 * m * w * w + 2.0 * double(m) * m * w
                   : st.cholesky_flops(s);
  }
  // Row position of global row r in supernode t's L panel.
  auto place = [&](int t, int r) -> int {
    if (r < st.first[t + 1]) return r - st.first[t];
    const auto b = st.rows.begin() + st.below_begin[t], e = st.rows.begin() + st.below_begin[t + 1];
    const auto it = std::lower_bound(b, e, r);
    assert(it != e && *it == r);
    return st.width(t) + static_cast<int>(it - b);
  };
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  st.entry.resize(A.nonZeros());
  st.entries = A.nonZeros();
  for (int j = 0; j < n; ++j)
    for (int k = outer[j]; k < outer[j + 1]; ++k) {
      const int r = pos[inner[k]], c = pos[j];
      if (r >= c || snode_of[r] == snode_of[c]) {
        const int t = snode_of[c];
        st.entry[k] = st.l_panel[t] + place(t, r) +
                      std::ptrdiff_t(c - st.first[t]) * (st.width(t) + st.below(t));
      } else if (!lu) {
        st.entry[k] = -1;
      } else {
        const int t = snode_of[r];
        st.entry[k] = st.u_panel[t] + (place(t, c) - st.width(t)) +
                      std::ptrdiff_t(r - st.first[t]) * st.below(t);
      }
    }
  // Update targets: the rows below s, in runs that fall in one supernode each.
  st.target_begin.assign(ns + 1, 0);
  for (int s = 0; s < ns; ++s) {
    const int* b = st.rows.data() + st.below_begin[s];
    const int m = st.below(s);
    for (int i = 0; i < m;) {
      const int t = snode_of[b[i]];
      int end = i;
      while (end < m && b[end] < st.first[t + 1]) ++end;
      st.targets.push_back({t, i, end, static_cast<std::ptrdiff_t>(st.relative.size())});
      for (int r = i; r < m; ++r) st.relative.push_back(place(t, b[r]));
      i = end;
    }
    st.target_begin[s + 1] = static_cast<int>(st.targets.size());
  }
  return st;
}

}  // namespace velum
