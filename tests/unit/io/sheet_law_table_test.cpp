// The model file's sheet-law table: each row's parser builds the law its factory builds, a
// bad value is reported (no law), and an unknown type has no row.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "io/model/sheet_law_table.hpp"

namespace velum::io::model_file {
namespace {

std::optional<SheetLaw> parse(ReaderContext& r, const std::string& yaml) {
  const Node m = YAML::Load(yaml);
  const SheetLawEntry* row = find_sheet_law(m["type"].Scalar());
  if (!row) throw std::logic_error("no row for " + yaml);
  return row->parse(r, m, "mat", "materials.mat");
}

TEST(SheetLawTable, RowsBuildTheirLaws) {
  ReaderContext r("test", ".");
  const auto iso = parse(r, "{type: isotropic, E: 1000, nu: 0.3, density: 1}");
  ASSERT_TRUE(iso);
  EXPECT_EQ(iso->reference_stiffness(), PlaneStressLaw::isotropic("mat", 1000, 0.3).Q());
  EXPECT_EQ(iso->name(), "mat");
  EXPECT_TRUE(iso->affine());
  const auto ortho = parse(r, "{type: orthotropic, E1: 2000, E2: 700, nu12: 0.35, G12: 300}");
  ASSERT_TRUE(ortho);
  EXPECT_EQ(ortho->reference_stiffness(),
            PlaneStressLaw::orthotropic("mat", 2000, 700, 0.35, 300, false).Q());
  const auto fib = parse(r, "{type: fibers, fibers: [{E: 100, angle: 0}, {E: 50, angle: 90}]}");
  ASSERT_TRUE(fib);
  EXPECT_EQ(fib->reference_stiffness(), PlaneStressLaw::fibers("mat", {{100, 0}, {50, 90}}).Q());
  const auto mat = parse(r, "{type: matrix, Q: [[3, 1, 0], [1, 2, 0], [0, 0, 1]]}");
  ASSERT_TRUE(mat);
  EXPECT_EQ(mat->reference_stiffness()(0, 1), 1.0);
  EXPECT_FALSE(parse(r, "{type: isotropic, E: -1, nu: 0.3}"));
  const auto nh = parse(r, "{type: neo_hookean, mu: 3.0e5, density: 1100}");
  ASSERT_TRUE(nh);
  EXPECT_EQ(nh->reference_stiffness()(2, 2), 3.0e5);  // the shear modulus
  EXPECT_FALSE(nh->affine());
  const auto mr = parse(r, "{type: mooney_rivlin, C1: 1.0e5, C2: 0.5e5, density: 1100}");
  ASSERT_TRUE(mr);
  EXPECT_EQ(mr->reference_stiffness()(2, 2), 3.0e5);
  EXPECT_FALSE(parse(r, "{type: neo_hookean, mu: 0}"));
  EXPECT_FALSE(parse(r, "{type: mooney_rivlin, C1: 1.0e5, C2: -0.2e5}"));
  EXPECT_FALSE(parse(r, "{type: mooney_rivlin, C1: -1.0e5, C2: 0.5e5}"));
  const auto ep = parse(r,
                        "{type: elastoplastic, E: 1.1e9, nu: 0.45, yield_stress: 16e6, "
                        "hardening_modulus: 6e7}");
  ASSERT_TRUE(ep);
  EXPECT_EQ(ep->state_size(), 4);
  EXPECT_EQ(ep->reference_stiffness(), PlaneStressLaw::isotropic("mat", 1.1e9, 0.45).Q());
  EXPECT_TRUE(parse(r,
                    "{type: elastoplastic, E: 1.1e9, nu: 0.45, "
                    "hardening_curve: [[0, 16e6], [0.05, 23e6]]}"));
  EXPECT_FALSE(parse(r, "{type: elastoplastic, E: 1.1e9, nu: 0.45}"));
  EXPECT_EQ(find_sheet_law("cable"), nullptr);  // not a sheet law
  EXPECT_EQ(find_sheet_law("neo-hookean"), nullptr);
  for (const auto& row : sheet_law_table()) EXPECT_EQ(find_sheet_law(row.type), &row);
}

}  // namespace
}  // namespace velum::io::model_file
