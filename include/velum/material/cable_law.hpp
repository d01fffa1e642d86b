// Axial law of a cable or truss (docs/theory.md): 2nd Piola-Kirchhoff force N = E A ε for the
// Green strain ε along the axis; a cable goes slack (N = 0) under compression unless it is a
// truss (`compression`). A prestress S0 adds to the elastic stress (N = E A ε + N0). Units are
// the user's.
#pragma once

namespace velum {

struct CableLaw {
  double E = 0;
  bool compression = false;
  double S0 = 0;  ///< prestress: axial 2nd PK stress at zero strain (section `prestress` / area)

  /// Axial 2nd PK stress for Green strain eps.
  double stress(double eps) const {
    const double s = E * eps + S0;
    return (s > 0 || compression) ? s : 0.0;
  }
  /// d stress / d eps; at zero stress the tension side (a taut, unstressed cable is stiff
  /// along its axis, so Newton can start from a straight cable at its unstressed length).
  double tangent(double eps) const { return (E * eps + S0 >= 0 || compression) ? E : 0.0; }
  /// Energy per unit reference volume, with d energy / d eps = stress.
  double energy(double eps) const {
    const double s = E * eps + S0;
    return (s > 0 || compression) ? 0.5 * E * eps * eps + S0 * eps : -0.5 * S0 * S0 / E;
  }
};

}  // namespace velum
