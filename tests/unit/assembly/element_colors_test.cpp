#include "assembly/element_colors.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "square_membrane.hpp"

namespace velum {
namespace {

// The colouring's promises (element_colors.hpp) on the square membrane's quad4 mesh, for every
// element and for a piece of them (every third dropped), with groups of 16 and of 5: each
// element once; each colour whole groups of consecutive listed elements, the short last group
// at its colour's end; the groups of one colour sharing no node.
TEST(ElementColors, GroupsOfOneColourShareNoNode) {
  const auto model = pressurised_square(23);
  const ElementBlock& b = *model->blocks[0];
  std::vector<int> all(static_cast<std::size_t>(b.size())), piece;
  for (int e = 0; e < b.size(); ++e) {
    all[e] = e;
    if (e % 3 != 0) piece.push_back(e);
  }
  for (const std::vector<int>* elems : {&all, &piece}) {
    for (const int group : {16, 5}) {
      const auto colors = color_element_groups(b, *elems, model->num_nodes(), group);
      ASSERT_GE(colors.size(), 2u);  // neighbouring groups share nodes
      EXPECT_LE(colors.size(), 8u);
      std::vector<int> seen;
      for (const auto& list : colors) {
        std::set<int> nodes;  // of this colour's groups so far
        for (std::size_t first = 0; first < list.size(); first += group) {
          const std::size_t count = std::min<std::size_t>(group, list.size() - first);
          // A group: consecutive entries of elems, from one that starts a group.
          const auto at = std::find(elems->begin(), elems->end(), list[first]);
          ASSERT_NE(at, elems->end());
          const std::size_t k = static_cast<std::size_t>(at - elems->begin());
          EXPECT_EQ(k % group, 0u);
          for (std::size_t i = 0; i < count; ++i) EXPECT_EQ(list[first + i], (*elems)[k + i]);
          // Short only as the last group of elems, and then the colour's last.
          if (count < static_cast<std::size_t>(group)) {
            EXPECT_EQ(k + count, elems->size());
            EXPECT_EQ(first + count, list.size());
          }
          std::set<int> mine;
          for (std::size_t i = 0; i < count; ++i)
            for (const int n : b.nodes(list[first + i])) mine.insert(n);
          for (const int n : mine) EXPECT_EQ(nodes.count(n), 0u) << "node " << n;
          nodes.insert(mine.begin(), mine.end());
          seen.insert(seen.end(), list.begin() + first, list.begin() + first + count);
        }
      }
      std::sort(seen.begin(), seen.end());
      EXPECT_EQ(seen, *elems);
    }
  }
}

}  // namespace
}  // namespace velum
