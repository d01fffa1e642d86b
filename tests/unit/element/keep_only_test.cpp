// ElementBlock::keep_only (docs/parallel.md, "Element data"): a block that keeps the section
// data of some elements only computes them exactly as before (the same bits: the data is
// moved, not recomputed), and says which it holds.
#include <gtest/gtest.h>

#include <vector>

#include "velum/model/element_block.hpp"

namespace velum {
namespace {

// A strip of three quads (nodes (i, j), i = 0..3, j = 0..1) and three cables along j = 0,
// reference and current positions (stretched, lifted, sheared).
struct Strip {
  NodePositions X{3, 8}, x{3, 8};
  std::vector<int> quads{0, 1, 5, 4, 1, 2, 6, 5, 2, 3, 7, 6}, cables{0, 1, 1, 2, 2, 3};
  Strip() {
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 4; ++i) {
        const int n = 4 * j + i;
        X.col(n) = Vec3(i, 0.7 * j, 0);
        x.col(n) = Vec3(1.1 * i + 0.05 * j, 0.75 * j, 0.02 * i * i - 0.03 * j);
      }
  }
};

std::vector<double> everything(const ElementBlock& b, const std::vector<int>& elems,
                               const NodePositions& X, const NodePositions& x) {
  const int nd = b.dofs_per_element(), nn = b.nodes_per_element();
  // Aligned: the blocks write element matrices through fixed-size Eigen references.
  std::vector<double, Eigen::aligned_allocator<double>> r(elems.size() * nd),
      K(elems.size() * nd * nd), M(nn * nn);
  std::vector<double> out;
  b.internal(elems, x, r.data(), K.data());
  out.insert(out.end(), r.begin(), r.end());
  out.insert(out.end(), K.begin(), K.end());
  out.push_back(b.strain_energy(elems, x));
  out.push_back(b.first_inverted(elems, X, x));
  for (int e : elems) {
    b.mass(e, M.data());
    out.insert(out.end(), M.begin(), M.end());
    out.push_back(b.measure(e));
    const ElementOutput o = b.output(e, x);
    out.insert(out.end(), {o.cable_force, o.stress.max, o.stress.min, o.stress.sheet[0],
                           o.stress.sheet[1], o.stress.sheet[2]});
  }
  if (b.kind() == ElementKind::kMembrane) {
    b.pressure(elems, x, 3.0, r.data(), K.data());
    out.insert(out.end(), r.begin(), r.end());
    out.insert(out.end(), K.begin(), K.end());
    for (int e : elems) out.push_back(b.output_at(e, {0.3, -0.2}, x).max);
  }
  return out;
}

TEST(KeepOnly, KeptElementsComputeTheSameBits) {
  const Strip s;
  BlockSetupReport report;
  const SheetLaw law = SheetLaw(PlaneStressLaw::orthotropic("fabric", 2e5, 1.2e5, 0.3, 4e4, false))
                           .with_prestress(Vec3(200, 150, 0));
  std::vector<std::unique_ptr<ElementBlock>> blocks;
  blocks.push_back(make_membrane_block("quad4", "sheet", s.quads, s.X, law, 0.5, 0.01, nullptr,
                                       shape::Integration::kGauss, report));
  blocks.push_back(make_cable_block("cable2", "lines", s.cables, s.X, CableLaw{.E = 5e6}, 2.0, 1e-4,
                                    shape::Integration::kGauss, report));
  const std::vector<int> kept{0, 2};
  for (auto& b : blocks) {
    const std::vector<double> before = everything(*b, kept, s.X, s.x);
    EXPECT_TRUE(b->holds(1));
    b->keep_only(kept);
    EXPECT_TRUE(b->holds(0));
    EXPECT_FALSE(b->holds(1));
    EXPECT_TRUE(b->holds(2));
    EXPECT_EQ(everything(*b, kept, s.X, s.x), before) << b->type_name();
    // Kept again (a subset of the kept): still the same element's data.
    const std::vector<int> last{2};
    const std::vector<double> one = everything(*b, last, s.X, s.x);
    b->keep_only(last);
    EXPECT_FALSE(b->holds(0));
    EXPECT_EQ(everything(*b, last, s.X, s.x), one) << b->type_name();
  }
}

// ElementBlock::keep_piece (docs/parallel.md, "The piece"): an element kept on a process's
// piece, its nodes renumbered, computes the same bits from the piece's positions; the others
// have no nodes; set up on a new reference (form finding), the piece's block holds the same
// element with the data a whole block would give it.
TEST(KeepPiece, RenumberedElementsComputeTheSameBitsAndMoveTheirReference) {
  const Strip s;
  BlockSetupReport report;
  const SheetLaw law = SheetLaw(PlaneStressLaw::orthotropic("fabric", 2e5, 1.2e5, 0.3, 4e4, false))
                           .with_prestress(Vec3(200, 150, 0));
  auto make = [&](bool membrane) {
    return membrane ? make_membrane_block("quad4", "sheet", s.quads, s.X, law, 0.5, 0.01, nullptr,
                                          shape::Integration::kGauss, report)
                    : make_cable_block("cable2", "lines", s.cables, s.X,
                                       CableLaw{.E = 5e6, .compression = false, .S0 = 40}, 2.0,
                                       1e-4, shape::Integration::kGauss, report);
  };
  // The piece of the middle quad and the middle cable: nodes 1, 2, 5, 6 of the strip.
  const std::vector<int> global_node{1, 2, 5, 6}, kept{1};
  std::vector<int> local_of(8, -1);
  NodePositions Xp(3, 4), xp(3, 4);
  for (int i = 0; i < 4; ++i) {
    local_of[global_node[i]] = i;
    Xp.col(i) = s.X.col(global_node[i]);
    xp.col(i) = s.x.col(global_node[i]);
  }
  for (const bool membrane : {true, false}) {
    auto whole = make(membrane), piece = make(membrane);
    const std::vector<double> before = everything(*whole, kept, s.X, s.x);
    piece->keep_piece(kept, local_of);
    EXPECT_EQ(everything(*piece, kept, Xp, xp), before) << piece->type_name();
    for (int n : piece->nodes(0)) EXPECT_EQ(n, -1);
    std::vector<int> mine;
    for (int n : piece->nodes(1)) mine.push_back(global_node[n]);
    const auto nodes = whole->nodes(1);
    EXPECT_EQ(mine, std::vector<int>(nodes.begin(), nodes.end()));
    // A new reference (and the form-finding law) for both: the same element, the same bits.
    const auto moved_whole = whole->on_reference(s.x, 10.0);
    const auto moved_piece = piece->on_reference(xp, 10.0);
    EXPECT_TRUE(moved_piece->holds(1));
    EXPECT_FALSE(moved_piece->holds(0));
    EXPECT_EQ(everything(*moved_piece, kept, xp, Xp), everything(*moved_whole, kept, s.x, s.X))
        << piece->type_name();
  }
}

}  // namespace
}  // namespace velum
