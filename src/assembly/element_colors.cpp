#include "element_colors.hpp"

#include <algorithm>
#include <span>

namespace velum {

std::vector<std::vector<int>> color_element_groups(const ElementBlock& b,
                                                   const std::vector<int>& elems, int num_nodes,
                                                   int group) {
  std::vector<std::vector<int>> node_colors(static_cast<std::size_t>(num_nodes));
  std::vector<std::vector<int>> colors;
  std::vector<char> used;
  for (std::size_t first = 0; first < elems.size(); first += static_cast<std::size_t>(group)) {
    const std::span<const int> members(
        elems.data() + first, std::min(static_cast<std::size_t>(group), elems.size() - first));
    used.assign(colors.size() + 1, 0);
    for (const int e : members)
      for (const int n : b.nodes(e))
        for (const int c : node_colors[n]) used[c] = 1;
    const int c = static_cast<int>(std::find(used.begin(), used.end(), 0) - used.begin());
    if (c == static_cast<int>(colors.size())) colors.emplace_back();
    colors[c].insert(colors[c].end(), members.begin(), members.end());
    for (const int e : members)
      for (const int n : b.nodes(e))
        if (node_colors[n].empty() || node_colors[n].back() != c) node_colors[n].push_back(c);
  }
  return colors;
}

}  // namespace velum
