// Sliding cable with friction at its interior nodes (docs/cables.md): each segment carries its
// own force, from the material it holds; the material slips through an interior node only
// where the two sides' forces differ by the capstan ratio e^(μθ) (θ the wrap angle there),
// and sticks below it. Lengths and slips in the chain's reference (unreefed) units.
#pragma once

#include <span>
#include <vector>

#include "velum/element/sliding_cable.hpp"

namespace velum::sliding_cable {

/// A chain's material, for friction: the reference length of each segment (k − 1), the slips
/// committed at the last accepted state at its interior nodes (k − 2; slip i: material moved
/// through interior node i + 1 from the segment before it to the one after it), the friction
/// coefficient and the reefing factor g (the material's length is g times its reference).
struct FrictionChain {
  std::span<const double> L0;
  std::span<const double> committed;
  double mu = 0;
  double g = 1;
};

/// Scratch space of the friction solve: grows to the longest chain once, then reused (hot
/// loops allocate nothing after that).
struct FrictionWork {
  std::vector<double> s, s_old, s_from, step, T, a, h, lj, c, theta, F, lo, di, up, w, D;
  std::vector<int> mode;
  std::vector<double> e;  // unit vectors of the segments, 3 each
};

/// Solves the slips at positions x, a return map from the committed ones: at each interior
/// node either it sticks (slip as committed, the forces within the capstan ratio) or the
/// material slips with the forces in the ratio e^(μθ), the larger on the side it moves to.
/// Writes the slips (k − 2) and returns false when the solve does not converge.
bool solve_slips(const Chain& x, const FrictionChain& c, double area, const CableLaw& law,
                 std::span<double> slips, FrictionWork& w);

/// Internal forces r = Σ T_j ∂l_j/∂x at x with the slips solved (written to `slips`), and when
/// K is non-null the consistent tangent: each segment's ∂l_j/∂x ⊗ dT_j/dx + T_j ∂²l_j/∂x²,
/// dT_j/dx through its length and through the slips' change with x where they slip (the
/// linearised capstan conditions, unsymmetric). Returns false when the slips do not converge
/// (r is then NaN).
bool friction_force_tangent(const Chain& x, const FrictionChain& c, double area,
                            const CableLaw& law, VectorMap r, MatrixMap* K, std::span<double> slips,
                            FrictionWork& w);

/// Strain energy Σ A L_j W(ε_j) and the mean force Σ T_j l_j / Σ l_j at x, with the slips
/// solved.
double friction_strain_energy(const Chain& x, const FrictionChain& c, double area,
                              const CableLaw& law, FrictionWork& w);
double friction_mean_force(const Chain& x, const FrictionChain& c, double area, const CableLaw& law,
                           FrictionWork& w);

/// The slips of a chain without friction (one force: every segment stretched alike), k − 2.
void frictionless_slips(const Chain& x, std::span<const double> L0, std::span<double> slips);

}  // namespace velum::sliding_cable
