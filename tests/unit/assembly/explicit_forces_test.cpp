// The explicit step's force pass (Assembler::explicit_forces, each surface block's fast path
// with the prestress term Aᵀ S0 stored per point) gives the forces of the general pass
// (Assembler::internal with the blocks' follower pressure) to round-off, on a prestressed
// anisotropic sheet with axes off the element edges, moved to a curved, sheared state, for
// tri3 and quad4, with and without pressure.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../support.hpp"
#include "velum/assembly/assembler.hpp"
#include "velum/assembly/dof_map.hpp"
#include "velum/model/model.hpp"

namespace velum {
namespace {

std::unique_ptr<Model> prestressed_sheet(const std::string& kind, int n) {
  auto m = std::make_unique<Model>();
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m->add_node(1 + j * (n + 1) + i, Vec3(1.0 * i / n, 0.8 * j / n, 0));
  std::vector<int> conn;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      if (kind == "quad4") {
        for (int k : {a, b, c, d}) conn.push_back(k);
      } else {
        for (int k : {a, b, c, a, c, d}) conn.push_back(k);
      }
    }
  AnisotropicConstants ac;
  ac.E1 = 2000.0, ac.E2 = 1000.0, ac.nu12 = 0.3, ac.G12 = 400.0, ac.eta1 = 0.25, ac.eta2 = -0.15;
  const SheetLaw law =
      SheetLaw(PlaneStressLaw::anisotropic("aniso", ac)).with_prestress(Vec3(40, 25, 6));
  const SheetAxes axes = test::axes_at(27.0, Mat3::Identity());
  BlockSetupReport report;
  m->blocks.push_back(make_membrane_block(kind, "sheet", conn, m->X, law, 1.0, 1e-3, &axes,
                                          shape::Integration::kGauss, report));
  return m;
}

TEST(ExplicitForces, EqualTheGeneralPassToRoundOff) {
  test::Random rnd(3);
  for (const std::string kind : {"tri3", "quad4"}) {
    auto m = prestressed_sheet(kind, 8);
    const DofMap dofs(*m);
    const Assembler assembler(*m, dofs);
    NodePositions x = m->X;
    for (int k = 0; k < x.cols(); ++k) {
      const Vec3 X = m->X.col(k);
      x.col(k) = Vec3(1.03 * X.x() + 0.02 * X.y(), 0.98 * X.y(), 0.1 * X.x() * X.y()) +
                 1e-3 * rnd.vec3(-1, 1);
    }
    for (const double p : {0.0, 250.0}) {
      const std::vector<double> pressure{p};
      NodePositions F, Fp, G, Gp;
      assembler.internal(x, F, nullptr, pressure, Fp);
      assembler.explicit_forces(x, G, pressure, Gp);
      const double scale = F.cwiseAbs().maxCoeff();
      ASSERT_GT(scale, 0) << kind;
      EXPECT_LT((F - G).cwiseAbs().maxCoeff(), 1e-12 * scale) << kind << " p " << p;
      if (p != 0) {
        const double pscale = Fp.cwiseAbs().maxCoeff();
        ASSERT_GT(pscale, 0) << kind;
        EXPECT_LT((Fp - Gp).cwiseAbs().maxCoeff(), 1e-12 * pscale) << kind;
      }
    }
  }
}

}  // namespace
}  // namespace velum
