#include "tree_split.hpp"

#include <algorithm>
#include <numeric>

namespace velum {

namespace {

struct Bins {
  double load[2] = {0, 0};
  std::vector<int> roots[2];
};

// The subtrees at `frontier` into two groups, heaviest first, each to the lighter group.
Bins pack(std::vector<int> frontier, const std::vector<double>& subtree) {
  std::stable_sort(frontier.begin(), frontier.end(),
                   [&](int a, int b) { return subtree[a] > subtree[b]; });
  Bins bins;
  for (const int r : frontier) {
    const int g = bins.load[1] < bins.load[0] ? 1 : 0;
    bins.load[g] += subtree[r];
    bins.roots[g].push_back(r);
  }
  return bins;
}

}  // namespace

TreeSplit split_tree(const SupernodalStructure& st, double top_speedup) {
  const int ns = st.supernodes();
  // The parent of s owns s's first row below (rows ascend, the parent is the nearest ancestor).
  std::vector<int> parent(ns, -1);
  std::vector<std::vector<int>> children(ns);
  std::vector<double> own(ns), subtree(ns);
  std::vector<int> frontier;
  for (int s = 0; s < ns; ++s) {
    own[s] = st.cholesky_flops(s);
    subtree[s] += own[s];
    if (st.target_begin[s] < st.target_begin[s + 1]) {
      parent[s] = st.targets[st.target_begin[s]].supernode;
      subtree[parent[s]] += subtree[s];
      children[parent[s]].push_back(s);
    } else {
      frontier.push_back(s);
    }
  }
  // The frontier's heaviest subtree opened: its root leaves (for the top), its children join.
  auto open_heaviest = [&](std::vector<int>& f) {
    const auto heaviest =
        std::max_element(f.begin(), f.end(), [&](int a, int b) { return subtree[a] < subtree[b]; });
    const int r = *heaviest;
    f.erase(heaviest);
    f.insert(f.end(), children[r].begin(), children[r].end());
    return r;
  };
  // Open the heaviest subtree of the frontier, one at a time; remember the best time.
  double top = 0, best_time = 0;
  int best_opened = 0;
  {
    const Bins b = pack(frontier, subtree);
    best_time = std::max(b.load[0], b.load[1]);
  }
  std::vector<int> f = frontier;
  for (int opened = 1; opened <= 4096 && !f.empty(); ++opened) {
    top += own[open_heaviest(f)];
    const Bins b = pack(f, subtree);
    const double time = std::max(b.load[0], b.load[1]) + top / top_speedup;
    if (time < best_time) {
      best_time = time;
      best_opened = opened;
    }
    if (top / top_speedup > best_time) break;  // the top alone is already slower
  }
  // Replay the best split.
  TreeSplit split;
  split.group.assign(ns, TreeSplit::kTop);
  split.top_offset.assign(ns, -1);
  f = frontier;
  for (int opened = 0; opened < best_opened; ++opened) open_heaviest(f);
  const Bins b = pack(f, subtree);
  // A subtree's supernodes are contiguous in the postorder and end at its root.
  std::vector<int> first_of(ns);
  for (int s = 0; s < ns; ++s) first_of[s] = s;
  for (int s = 0; s < ns; ++s)
    if (parent[s] >= 0) first_of[parent[s]] = std::min(first_of[parent[s]], first_of[s]);
  for (int g = 0; g < 2; ++g)
    for (const int r : b.roots[g])
      for (int s = first_of[r]; s <= r; ++s) split.group[s] = g;
  for (int s = 0; s < ns; ++s) {
    const int g = split.group[s];
    split.flops[g] += own[s];
    if (g != TreeSplit::kTop) {
      split.members[g].push_back(s);
    } else {
      split.top.push_back(s);
      split.top_offset[s] = split.top_values;
      split.top_values += std::ptrdiff_t(st.width(s) + st.below(s)) * st.width(s);
    }
  }
  return split;
}

}  // namespace velum
