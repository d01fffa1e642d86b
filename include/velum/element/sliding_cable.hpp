// Sliding cable kernel (Zhou, Accorsi & Leonard 2004; docs/cables.md): one cable through a
// chain of nodes whose material slides freely over the interior ones, so one force acts
// along the whole chain, from the total current length against the reference length.
#pragma once

#include <Eigen/Core>
#include <span>

#include "velum/material/cable_law.hpp"
#include "velum/math/types.hpp"

namespace velum::sliding_cable {

/// Current positions of a chain's nodes, in order (3 x k), and its dofs' vectors/matrices.
using Chain = Eigen::Ref<const Eigen::Matrix<double, 3, Eigen::Dynamic>>;
using VectorMap = Eigen::Map<Eigen::VectorXd>;
using MatrixMap = Eigen::Map<Eigen::MatrixXd>;

/// Current length of the chain (the sum of its segments' lengths).
double length(const Chain& x);

/// Green strain of the whole chain, ε = ½ (l² / L0² − 1), l its current length.
inline double strain(double l, double L0) {
  return 0.5 * (l * l / (L0 * L0) - 1);
}

/// Internal forces r = T ∂l/∂x (T the true force A S λ, λ = l / L0) of a chain of reference
/// length L0 and area A, and (when K is non-null) the consistent tangent
/// K = (A / L0)(S' λ² + S) ∂l/∂x ⊗ ∂l/∂x + T ∂²l/∂x²: a rank-one term that couples every node
/// of the chain plus each segment's geometric term (I − e eᵀ) / l_j.
void force_tangent(const Chain& x, double L0, double area, const CableLaw& law, VectorMap r,
                   MatrixMap* K);

/// Strain energy A L0 W(ε).
double strain_energy(const Chain& x, double L0, double area, const CableLaw& law);

/// True (Cauchy) force A S λ.
double true_force(const Chain& x, double L0, double area, const CableLaw& law);

/// Form finding's chain (docs/fabric-structures.md): the prestress as one force along the chain,
/// A S0 λ (λ = l / L0, the sleeve: its points slide), plus a stabilizer per segment, each
/// segment's own Green strain ε_j against its reference length L0_j at modulus E (it holds the
/// sleeve points along the chain as the sheet's stabilizer holds the mesh in its plane, and
/// vanishes with the strains once the updates stop moving the shape). Internal forces r and
/// (when K is non-null) the tangent: the one-force chain's with S' = 0, plus each segment's
/// (A / L0_j) E (λ_j² + ε_j) e_j ⊗ e_j and geometric term. `L0j` holds the k − 1 segments'.
void stabilized_force_tangent(const Chain& x, std::span<const double> L0j, double area, double S0,
                              double E, VectorMap r, MatrixMap* K);

/// Its strain energy A (L0 S0 ε + Σ L0_j E ε_j² / 2) and its mean force (the prestress's plus
/// the segments' stabilizing forces weighted by their current lengths).
double stabilized_strain_energy(const Chain& x, std::span<const double> L0j, double area, double S0,
                                double E);
double stabilized_mean_force(const Chain& x, std::span<const double> L0j, double area, double S0,
                             double E);

}  // namespace velum::sliding_cable
