// Output quantities of a membrane point (docs/theory.md): true (Cauchy) stress σ = (1/J) F S Fᵀ
// with the thickness held (t = t0, so J is the area stretch; t0 σ is then the force per current
// length whatever the thickness does), its principal values and 3-D directions, its components
// in the deformed sheet axes, the Green-Lagrange strain in the reference sheet axes and the
// principal stretches, the deformed sheet axes and fibre directions, and the change of the
// angle between the material directions F m1 and F m2.
#pragma once

#include "velum/math/types.hpp"

namespace velum {

struct MembraneStress {
  double max = 0, min = 0;                              ///< principal true stresses, max >= min
  Vec3 dir_max = Vec3::Zero(), dir_min = Vec3::Zero();  ///< unit principal directions
  Vec3 sheet = Vec3::Zero();      ///< σ11, σ22, σ12 in the deformed sheet axes (F m1 and normal)
  Mat3 sigma = Mat3::Zero();      ///< Cartesian true stress (in the tangent plane)
  double fiber_angle_change = 0;  ///< angle(F m1, F m2) − angle(m1, m2), radians
  int wrinkle_state = 0;          ///< 0 taut, 1 wrinkled, 2 slack (WrinkleState)
  Vec3 wrinkle_dir = Vec3::Zero();  ///< wrinkled: unit vector along the wrinkles, as deformed
  Vec3 strain = Vec3::Zero();  ///< Green-Lagrange E11, E22, E12 (tensor) in the reference m1, m2
  double stretch_max = 1, stretch_min = 1;  ///< principal in-plane stretches, max >= min
  Vec3 axis1 = Vec3::Zero();                ///< deformed sheet axis a1 = F m1 / |F m1| (= fibre 1)
  Vec3 axis2 = Vec3::Zero();                ///< a2 = n x a1 (in the deformed tangent plane)
  Vec3 normal = Vec3::Zero();               ///< deformed unit normal n = g1 x g2 / |g1 x g2|
  Vec3 fiber2 = Vec3::Zero();               ///< F m2 / |F m2| (not orthogonal to a1 once sheared)
};

/// g: current tangent basis (g1, g2); S: contravariant 2nd PK [S11, S22, S12];
/// Gmetric: reference metric [G11, G22, G12]; T(a,α) = m_a · G^α.
MembraneStress membrane_stress(const Eigen::Matrix<double, 3, 2>& g, const Vec3& S,
                               const Vec3& Gmetric, const Mat2& T);

}  // namespace velum
