#include "velum/assembly/element_scatter.hpp"

#include <algorithm>
#include <array>

#include "velum/assembly/assembler.hpp"

namespace velum {
namespace {

constexpr int kMostNodes = 9;  // the largest element (quad9)

}  // namespace

ElementScatter::ElementScatter(const ElementBlock& b, std::span<const int> elements,
                               const DofMap& dofs, const SparseMatrix& A)
    : nn_(b.nodes_per_element()), nd_(b.dofs_per_element()) {
  // A longer element (a sliding cable's chain) takes the full map: its blocks are not searched.
  const bool compact = nn_ <= kMostNodes;
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  auto position = [&](int row, int col) {
    const int* at = std::lower_bound(inner + outer[col], inner + outer[col + 1], row);
    return at != inner + outer[col + 1] && *at == row ? static_cast<int>(at - inner) : -1;
  };
  const std::size_t count = elements.size(), per = static_cast<std::size_t>(nn_ * nn_ + nn_);
  start_.assign(count * per, -1);
  irregular_.assign(count, -1);
  // Compact where every node has three consecutive equations or none, and every block's
  // nine positions are where the compact form puts them (checked, not assumed).
#pragma omp parallel for schedule(static) if (count * per > kParallelMatrixEntries)
  for (std::size_t k = 0; k < count; ++k) {
    const auto nodes = b.nodes(elements[k]);
    int* s = start_.data() + k * per;
    int* L = s + nn_ * nn_;
    bool regular = compact;
    std::array<int, kMostNodes> first{};  // a node's first equation
    for (int a = 0; a < nn_ && regular; ++a) {
      const int e0 = dofs.equation(nodes[a], 0), e1 = dofs.equation(nodes[a], 1),
                e2 = dofs.equation(nodes[a], 2);
      const bool none = e0 < 0 && e1 < 0 && e2 < 0;
      regular = none || (e0 >= 0 && e1 == e0 + 1 && e2 == e0 + 2);
      first[a] = none ? -1 : e0;
      L[a] = regular && !none ? outer[e0 + 1] - outer[e0] : 0;
    }
    // One search per block; its nine places then checked where the compact form puts them
    // (the row there, in the column that holds it).
    for (int bn = 0; bn < nn_ && regular; ++bn)
      for (int a = 0; a < nn_ && regular; ++a) {
        if (first[a] < 0 || first[bn] < 0) continue;
        const int at = position(first[a], first[bn]);
        for (int d = 0; d < 3 && regular; ++d)
          for (int e = 0; e < 3 && regular; ++e) {
            const int col = first[bn] + d, k = at + d * L[bn] + e;
            regular = at >= 0 && k >= outer[col] && k < outer[col + 1] && inner[k] == first[a] + e;
          }
        s[bn * nn_ + a] = at;
      }
    if (!regular) irregular_[k] = 0;  // its full map below
  }
  std::vector<int> eqs(static_cast<std::size_t>(nd_));
  for (std::size_t k = 0; k < count; ++k) {
    if (irregular_[k] < 0) continue;
    irregular_[k] = static_cast<int>(full_.size());
    const auto nodes = b.nodes(elements[k]);
    for (int a = 0; a < nn_; ++a)
      for (int c = 0; c < 3; ++c) eqs[3 * a + c] = dofs.equation(nodes[a], c);
    for (int j = 0; j < nd_; ++j)
      for (int i = 0; i < nd_; ++i)
        full_.push_back(eqs[i] >= 0 && eqs[j] >= 0 ? position(eqs[i], eqs[j]) : -1);
  }
}

int ElementScatter::position(int k, int i, int j) const {
  if (irregular_[k] >= 0) return full_[irregular_[k] + j * nd_ + i];
  const int* s = start_.data() + static_cast<std::size_t>(k) * (nn_ * nn_ + nn_);
  const int at = s[(j / 3) * nn_ + i / 3];
  return at < 0 ? -1 : at + (j % 3) * s[nn_ * nn_ + j / 3] + i % 3;
}

}  // namespace velum
