#include "supernodes.hpp"

#include "ordering.hpp"

#include <algorithm>
#include <cassert>
#include <limits>
#include <numeric>

namespace velum {
namespace {

// A symmetric pattern by column: column c holds rows[begin[c] .. begin[c + 1]).
struct Pattern {
  std::vector<int> begin, rows;
};

// The strictly upper part of P (G + Gᵀ) Pᵀ by column, for the pattern G of m columns given by
// (outer, inner) and P: column c holds the rows r < c, each once (G may hold (i, j) without
// (j, i)).
Pattern upper_pattern(const int* outer, const int* inner, int m, const std::vector<int>& pos) {
  std::vector<int> count(m + 1, 0);
  for (int j = 0; j < m; ++j)
    for (int k = outer[j]; k < outer[j + 1]; ++k)
      if (const int r = pos[inner[k]], c = pos[j]; r != c) ++count[std::max(r, c) + 1];
  std::partial_sum(count.begin(), count.end(), count.begin());
  std::vector<int> rows(count[m]), next(count.begin(), count.end() - 1);
  for (int j = 0; j < m; ++j)
    for (int k = outer[j]; k < outer[j + 1]; ++k)
      if (const int r = pos[inner[k]], c = pos[j]; r != c)
        rows[next[std::max(r, c)]++] = std::min(r, c);
  Pattern up;
  up.begin.assign(m + 1, 0);
  int kept = 0;
  for (int c = 0; c < m; ++c) {
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

// The same upper pattern with its columns and rows renumbered by rank, when rank keeps every
// row before its column (a postorder of the elimination tree does: the column is an
// ancestor of the row). Rows within a column are not sorted again: no one needs them sorted.
Pattern relabel(const Pattern& up, const std::vector<int>& rank) {
  const int m = static_cast<int>(rank.size());
  Pattern out;
  out.begin.assign(m + 1, 0);
  for (int c = 0; c < m; ++c) out.begin[rank[c] + 1] = up.begin[c + 1] - up.begin[c];
  std::partial_sum(out.begin.begin(), out.begin.end(), out.begin.begin());
  out.rows.resize(up.rows.size());
  for (int c = 0; c < m; ++c) {
    int* to = out.rows.data() + out.begin[rank[c]];
    for (int p = up.begin[c]; p < up.begin[c + 1]; ++p) *to++ = rank[up.rows[p]];
  }
  return out;
}

// Elimination tree (Liu's algorithm with path compression).
std::vector<int> elimination_tree(const Pattern& up) {
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
void walk_rows(const Pattern& up, const std::vector<int>& parent, Visit&& visit) {
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

// The nodes of A: runs of consecutive columns with the same pattern in A and consecutive
// positions (a membrane node's three equations), when every block of A between two nodes is
// dense or empty and every node's own block dense; then the pattern of A + Aᵀ is that of the
// node graph's, each node a clique, and the elimination tree, the postorder and the column
// counts of L follow from the node graph's (a ninth of the edges for 3 x 3 blocks). Empty
// when A has no such nodes (each column is then its own node).
struct Nodes {
  std::vector<int> first;  ///< columns of node g: [first[g], first[g + 1])
  Pattern graph;           ///< the node graph by column, from A's (not symmetrised)
};

Nodes find_nodes(const SparseMatrix& A, const std::vector<int>& pos) {
  const int n = static_cast<int>(A.cols());
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  Nodes nodes;
  std::vector<int> node_of(n);
  nodes.first.push_back(0);
  for (int j = 0; j < n; ++j) {
    if (j > nodes.first.back() && !(pos[j] == pos[j - 1] + 1 && same_rows(A, j - 1, j)))
      nodes.first.push_back(j);
    node_of[j] = static_cast<int>(nodes.first.size()) - 1;
  }
  const int m = static_cast<int>(nodes.first.size());
  nodes.first.push_back(n);
  if (m == n) return {};
  Pattern& g = nodes.graph;
  g.begin.assign(m + 1, 0);
  g.rows.reserve(static_cast<std::size_t>(A.nonZeros()) / (n / m) + m);
  for (int h = 0; h < m; ++h) {
    const int j = nodes.first[h];
    int covered = 0;  // A's rows in the nodes met: all of them when the blocks are dense
    bool own = nodes.first[h + 1] - j == 1;
    for (int k = outer[j]; k < outer[j + 1]; ++k)
      if (const int r = node_of[inner[k]];
          g.rows.size() == std::size_t(g.begin[h]) || g.rows.back() != r) {  // inner is sorted
        g.rows.push_back(r);
        covered += nodes.first[r + 1] - nodes.first[r];
        own = own || r == h;
      }
    if (covered != outer[j + 1] - outer[j] || !own) return {};
    g.begin[h + 1] = static_cast<int>(g.rows.size());
  }
  return nodes;
}

// L's elimination tree by column, the count of each column of L with its diagonal, and the
// node graph's upper pattern, tree and columns (A's own, a node per column, when A has no
// nodes), all in the elimination order that elimination() leaves in pos.
struct Tree {
  std::vector<int> parent;
  std::vector<long> count;
  Pattern up;                    ///< of the nodes, in elimination order
  std::vector<int> node_parent;  ///< the nodes' elimination tree
  std::vector<int> node_first;   ///< columns of the k-th node in elimination order
};

// pos: the given order, replaced by a postorder of its elimination tree (which keeps the fill
// and numbers every subtree, so every supernode with its parent, contiguously).
Tree elimination(const SparseMatrix& A, std::vector<int>& pos, bool by_nodes) {
  const int n = static_cast<int>(A.cols());
  Tree tree;
  Nodes nodes = by_nodes ? find_nodes(A, pos) : Nodes{};
  const bool scalar = nodes.first.empty();
  const int m = scalar ? n : static_cast<int>(nodes.first.size()) - 1;
  // The nodes' positions among the nodes, and sizes.
  std::vector<int> npos(m), size(m, 1);
  if (scalar) {
    npos = pos;
  } else {
    std::vector<int> at(n, -1);
    for (int g = 0; g < m; ++g) at[pos[nodes.first[g]]] = g;
    for (int p = 0, k = 0; p < n; ++p)
      if (at[p] >= 0) npos[at[p]] = k++;
    for (int g = 0; g < m; ++g) size[g] = nodes.first[g + 1] - nodes.first[g];
  }
  const Pattern first_up =
      scalar ? upper_pattern(A.outerIndexPtr(), A.innerIndexPtr(), n, npos)
             : upper_pattern(nodes.graph.begin.data(), nodes.graph.rows.data(), m, npos);
  nodes.graph = {};
  std::vector<int> parent = elimination_tree(first_up);
  std::vector<int> rank(m);
  {
    const std::vector<int> post = postorder(parent);
    for (int k = 0; k < m; ++k) rank[post[k]] = k;
  }
  tree.up = relabel(first_up, rank);
  std::vector<int> node_parent(m);
  for (int k = 0; k < m; ++k) node_parent[rank[k]] = parent[k] == -1 ? -1 : rank[parent[k]];
  std::vector<int> node_at(m);  // node_at[k] = the node eliminated k-th
  for (int g = 0; g < m; ++g) node_at[rank[npos[g]]] = g;
  tree.node_first.assign(m + 1, 0);
  for (int k = 0; k < m; ++k) tree.node_first[k + 1] = tree.node_first[k] + size[node_at[k]];
  if (scalar) {
    for (int& p : pos) p = rank[p];
  } else {
    for (int g = 0; g < m; ++g)
      for (int j = nodes.first[g]; j < nodes.first[g + 1]; ++j)
        pos[j] = tree.node_first[rank[npos[g]]] + (j - nodes.first[g]);
  }
  // Each node's columns are a chain; its last column's count from the node graph's row
  // subtrees, the node's rows counted by their columns.
  std::vector<long> below(m, 0);
  walk_rows(tree.up, node_parent,
            [&](int j, int i) { below[j] += tree.node_first[i + 1] - tree.node_first[i]; });
  tree.parent.resize(n);
  tree.count.resize(n);
  for (int k = 0; k < m; ++k) {
    const int b = tree.node_first[k], e = tree.node_first[k + 1];
    for (int c = b; c < e; ++c) {
      tree.parent[c] = c + 1;
      tree.count[c] = below[k] + e - c;
    }
    tree.parent[e - 1] = node_parent[k] == -1 ? -1 : tree.node_first[node_parent[k]];
  }
  tree.node_parent = std::move(node_parent);
  return tree;
}

}  // namespace

SupernodalStructure analyse_supernodes(const SparseMatrix& A, const std::vector<int>& position,
                                       const Amalgamation& relax, Factor factor, bool by_nodes) {
  const bool lu = factor == Factor::kLu;
  SupernodalStructure st;
  const int n = st.n = static_cast<int>(A.cols());
  std::vector<int> pos = position;
  if (static_cast<int>(pos.size()) != n) {
    pos.resize(n);
    std::iota(pos.begin(), pos.end(), 0);
  }
  const Tree tree = elimination(A, pos, by_nodes);
  const std::vector<int>& parent = tree.parent;
  const std::vector<long>& count = tree.count;  // entries in each column of L, with the diagonal
  st.order.resize(n);
  for (int i = 0; i < n; ++i) st.order[pos[i]] = i;

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
    // A supernode ends with a node (its columns are a chain of one fundamental supernode):
    // the rows below it are the columns of the nodes in its last node's row subtrees.
    std::vector<int> next(st.below_begin.begin(), st.below_begin.end() - 1);
    const std::vector<int>& nf = tree.node_first;
    walk_rows(tree.up, tree.node_parent, [&](int j, int i) {
      if (const int s = snode_of[nf[j]]; nf[j + 1] == st.first[s + 1])
        for (int r = nf[i]; r < nf[i + 1]; ++r) st.rows[next[s]++] = r;
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
  // where[r] = place(t, r) for the rows r of the supernode t at hand: filled supernode by
  // supernode, each entry of A and each update row found without a search.
  std::vector<int> where(n);
  auto rows_of = [&](int t) {
    for (int r = st.first[t]; r < st.first[t + 1]; ++r) where[r] = r - st.first[t];
    for (int k = st.below_begin[t]; k < st.below_begin[t + 1]; ++k)
      where[st.rows[k]] = st.width(t) + (k - st.below_begin[t]);
  };
  // A's entries by the supernode of their column (in L) or row (U, above the diagonal blocks).
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  st.entries = A.nonZeros();
  bool loads = !lu;  // Cholesky: each panel's list, when every panel's places fit in an int
  for (int t = 0; t < ns && loads; ++t)
    loads = std::ptrdiff_t(st.width(t) + st.below(t)) * st.width(t) <=
            std::ptrdiff_t(std::numeric_limits<int>::max()) + 1;
  if (lu) st.entry.resize(A.nonZeros());
  // Cholesky: the loads read A's lower triangle, stored apart (half of A's bytes, and exactly
  // symmetric): column j's rows at or below j are the last of its stored ones (rows sorted),
  // lower_begin[j] .. [j + 1] there. Each entry of the permuted matrix's lower triangle is
  // loaded once (the dense kernels read the diagonal blocks' lower triangles only), from its
  // place there or, where the order put it below the diagonal from above, from its
  // transposed place; a pattern without that place is not symmetric: no loads.
  std::vector<int> lower_first;  // A's position of column j's first row at or below j
  if (loads) {
    lower_first.resize(n);
    st.lower_begin.assign(n + 1, 0);
    for (int j = 0; j < n; ++j) {
      lower_first[j] =
          static_cast<int>(std::lower_bound(inner + outer[j], inner + outer[j + 1], j) - inner);
      st.lower_begin[j + 1] = st.lower_begin[j] + (outer[j + 1] - lower_first[j]);
    }
  }
  auto lower_place = [&](int k, int i, int j) {
    if (i >= j) return st.lower_begin[j] + (k - lower_first[j]);
    const int* end = inner + outer[i + 1];
    const int* at = std::lower_bound(inner + lower_first[i], end, j);
    return at != end && *at == j ? st.lower_begin[i] + static_cast<int>(at - inner - lower_first[i])
                                 : -1;
  };
  if (loads) {
    st.load_begin.assign(ns + 1, 0);
    st.loads.reserve(static_cast<std::size_t>(A.nonZeros() + n) / 2);
  }
  for (int t = 0; t < ns; ++t) {
    rows_of(t);
    const std::ptrdiff_t ld = st.width(t) + st.below(t);
    for (int c = st.first[t]; c < st.first[t + 1]; ++c) {
      const int j = st.order[c];
      for (int k = outer[j]; k < outer[j + 1]; ++k) {
        const int r = pos[inner[k]];
        if (!lu) {
          if (loads && r >= c) {
            const int a = lower_place(k, inner[k], j);
            if (a < 0) {
              loads = false;
              break;
            }
            st.loads.push_back(
                {a, static_cast<int>(where[r] + std::ptrdiff_t(c - st.first[t]) * ld)});
          }
        } else if (r >= c || snode_of[r] == t) {
          st.entry[k] = st.l_panel[t] + where[r] + std::ptrdiff_t(c - st.first[t]) * ld;
        } else {
          const int u = snode_of[r];
          st.entry[k] = st.u_panel[u] + (place(u, c) - st.width(u)) +
                        std::ptrdiff_t(r - st.first[u]) * st.below(u);
        }
      }
    }
    if (loads) st.load_begin[t + 1] = static_cast<int>(st.loads.size());
  }
  if (!loads) {
    st.load_begin = {};
    st.loads = {};
    st.lower_begin = {};
  }
  // Update targets: the rows below s, in runs that fall in one supernode each; their places
  // in each target found target by target.
  st.target_begin.assign(ns + 1, 0);
  std::vector<int> source;
  std::ptrdiff_t relatives = 0;
  for (int s = 0; s < ns; ++s) {
    const int* b = st.rows.data() + st.below_begin[s];
    const int m = st.below(s);
    for (int i = 0; i < m;) {
      const int t = snode_of[b[i]];
      int end = i;
      while (end < m && b[end] < st.first[t + 1]) ++end;
      st.targets.push_back({t, i, end, relatives});
      source.push_back(s);
      relatives += m - i;
      i = end;
    }
    st.target_begin[s + 1] = static_cast<int>(st.targets.size());
  }
  const int nt = static_cast<int>(st.targets.size());
  std::vector<int> reaching_begin(ns + 1, 0), reaching(nt);
  for (const auto& g : st.targets) ++reaching_begin[g.supernode + 1];
  std::partial_sum(reaching_begin.begin(), reaching_begin.end(), reaching_begin.begin());
  {
    std::vector<int> next(reaching_begin.begin(), reaching_begin.end() - 1);
    for (int g = 0; g < nt; ++g) reaching[next[st.targets[g].supernode]++] = g;
  }
  st.relative.resize(relatives);
  for (int t = 0; t < ns; ++t) {
    if (reaching_begin[t] == reaching_begin[t + 1]) continue;
    rows_of(t);
    for (int q = reaching_begin[t]; q < reaching_begin[t + 1]; ++q) {
      const SupernodalStructure::Target& g = st.targets[reaching[q]];
      const int s = source[reaching[q]];
      const int* b = st.rows.data() + st.below_begin[s];
      int* to = st.relative.data() + g.rel;
      for (int r = g.begin; r < st.below(s); ++r) *to++ = where[b[r]];
    }
  }
  return st;
}

}  // namespace velum
