// Form finding with edge cables in sleeves (docs/cables.md, docs/fabric-structures.md): a flat
// square membrane of isotropic prestress n whose four edges run through sliding_cable chains
// of prescribed force S. The membrane pulls every edge normal to itself with n per length, the
// sleeve carries one force S along its chain, so each edge becomes a circular arc of radius
// R = S / n between the pinned corners, its nodes spaced evenly (a node's tangential balance).
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "velum/analysis/form_finding.hpp"

namespace velum {
namespace {

struct SleeveSquare {
  Model m;
  int n = 0;
  int node(int i, int j) const { return j * (n + 1) + i; }
  // The four edges' chains, corner to corner (south, east, north, west).
  std::array<std::vector<int>, 4> chains;
};

// A square a x a in the plane z = 0, n x n quad4, prestress nfab; edge chains of force S
// (friction μ on their section: form finding leaves it out, the found state sticks).
SleeveSquare sleeve_square(double a, int n, double nfab, double S, double mu) {
  SleeveSquare q;
  q.n = n;
  Model& m = q.m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) m.add_node(1 + q.node(i, j), Vec3(a * i / n, a * j / n, 0));
  std::vector<int> conn;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      for (int k : {q.node(i, j), q.node(i + 1, j), q.node(i + 1, j + 1), q.node(i, j + 1)})
        conn.push_back(k);
  BlockSetupReport report;
  const SheetLaw law =
      SheetLaw(PlaneStressLaw::isotropic("film", 1.0, 0.0)).with_prestress(Vec3(nfab, nfab, 0));
  m.blocks.push_back(make_membrane_block("quad4", "film", std::move(conn), m.X, law, 1.0, 1.0,
                                         nullptr, shape::Integration::kGauss, report));
  std::vector<int> chain_conn;
  for (int k = 0; k <= n; ++k) {
    q.chains[0].push_back(q.node(k, 0));
    q.chains[1].push_back(q.node(n, k));
    q.chains[2].push_back(q.node(n - k, n));
    q.chains[3].push_back(q.node(0, n - k));
  }
  for (const auto& c : q.chains) chain_conn.insert(chain_conn.end(), c.begin(), c.end());
  const double area = 1e-4;
  SlidingCableSection section;
  section.friction = mu;
  m.blocks.push_back(make_sliding_cable_block("sleeve", n + 1, chain_conn, m.X,
                                              CableLaw{.E = 1e9, .S0 = S / area}, 1.0, area, report,
                                              section));
  m.fixed.push_back({.nodes = {q.node(0, 0), q.node(n, 0), q.node(n, n), q.node(0, n)},
                     .fix = {true, true, true}});
  return q;
}

AnalysisSettings form_finding_settings() {
  AnalysisSettings s;
  s.type = AnalysisSettings::Type::kFormFinding;
  s.time.t_end = 1, s.time.step = 1;
  s.form_finding.tolerance = 1e-5;
  s.form_finding.max_updates = 100;
  return s;
}

// The discrete arc: n equal chords on a circle through the corners a apart, each turning the
// cable by φ; a node's balance 2 S sin(φ/2) = n (the membrane's half chords' pull, n R sin φ)
// gives R cos(φ/2) = S / n, and the corners 2 R sin(n φ / 2) = a. Solved by bisection on φ.
double discrete_radius(double a, int n, double nfab, double S) {
  double lo = 1e-12, hi = 3.0 / n;
  for (int k = 0; k < 200; ++k) {
    const double phi = 0.5 * (lo + hi);
    const double R = S / (nfab * std::cos(phi / 2));
    (2 * R * std::sin(n * phi / 2) > a ? hi : lo) = phi;
  }
  return S / (nfab * std::cos(0.25 * (lo + hi)));
}

void check_arcs(double mu) {
  const double a = 10, nfab = 1.0, S = 20.0;
  const int n = 20;
  SleeveSquare q = sleeve_square(a, n, nfab, S, mu);
  Model& m = q.m;
  MechanicalSystem view(m);
  FormFindingReport rep;
  const AnalysisResult res = run_form_finding(m, view, form_finding_settings(), {}, {}, &rep);
  ASSERT_TRUE(res.loop.completed) << res.loop.reason;
  const double R = S / nfab, Rd = discrete_radius(a, n, nfab, S);
  const double d = std::sqrt(Rd * Rd - a * a / 4);  // the centre's distance from the chord
  // Centres outside the square (the arcs bulge inwards): south, east, north, west.
  const std::array<Vec3, 4> centres = {Vec3(a / 2, -d, 0), Vec3(a + d, a / 2, 0),
                                       Vec3(a / 2, a + d, 0), Vec3(-d, a / 2, 0)};
  double radius_err = 0, spacing_err = 0, flat = 0;
  for (int c = 0; c < 4; ++c) {
    const auto& chain = q.chains[static_cast<size_t>(c)];
    const double chord = 2 * Rd * std::sin(std::asin(a / (2 * Rd)) / n);
    for (size_t k = 0; k < chain.size(); ++k) {
      const Vec3 p = rep.shape.col(chain[k]);
      radius_err =
          std::max(radius_err, std::abs((p - centres[static_cast<size_t>(c)]).norm() - Rd));
      flat = std::max(flat, std::abs(p.z()));
      if (k > 0)
        spacing_err =
            std::max(spacing_err, std::abs((p - rep.shape.col(chain[k - 1])).norm() - chord));
    }
  }
  // The chain's force on the found shape: one value S, and (with friction) each segment's.
  const ElementBlock& sleeve = *m.blocks[1];
  double force_err = 0, slip = 0;
  for (int e = 0; e < 4; ++e) {
    force_err = std::max(force_err, std::abs(sleeve.output(e, rep.shape).cable_force / S - 1));
    if (mu > 0)
      for (int j = 1; j < n; ++j)
        slip = std::max(slip, std::abs(sleeve.sliding()->slip(e, j, rep.shape)));
  }
  const double sag = rep.shape(1, q.node(n / 2, 0));
  std::cout << "sleeve form finding (friction " << mu << "): " << rep.updates
            << " updates, residual " << rep.residual << "; node off the discrete arc of radius "
            << Rd << " (S/n = " << R << ", " << Rd / R - 1 << " off) by " << radius_err
            << ", chords unequal by " << spacing_err << ", out of plane " << flat
            << "; force off S by " << force_err << "; mid-edge sag " << sag << " (circle "
            << R - std::sqrt(R * R - a * a / 4) << ")\n";
  // The nodes' spacing along the arc is held by the fabric's tangential pull alone, weak on a
  // nearly straight edge (n Δl φ / 4): it converges far more slowly than the arc, which is
  // what is checked.
  EXPECT_LT(radius_err, 1e-5 * R);
  EXPECT_LT(spacing_err, 0.1 * a / n);
  EXPECT_LT(std::abs(Rd / R - 1), 1e-4);  // the discrete arc tends to the circle S / n
  EXPECT_LT(force_err, 1e-12);
  EXPECT_LT(flat, 1e-12);
  EXPECT_EQ(slip, 0.0);  // nothing has slipped in the sleeves of the found shape
}

TEST(SleeveFormFinding, EdgeCablesInSleevesBecomeArcsOfRadiusSOverN) {
  check_arcs(0.0);
}

// With friction in the sleeves: form finding lays the cable in its sleeve at the found shape
// (nothing has slipped yet), so the shape is the frictionless one and every segment carries S.
TEST(SleeveFormFinding, FrictionPlaysNoPartInTheFoundShape) {
  check_arcs(0.3);
}

}  // namespace
}  // namespace velum
