// Axial law of a cable or truss (THEORY §6): 2nd Piola-Kirchhoff force N = E A ε for the
// Green strain ε along the axis; a cable goes slack (N = 0) under compression unless it is a
// truss (`compression`). Units are the user's.
#pragma once

namespace velum {

struct CableLaw {
  double E = 0;
  bool compression = false;

  /// Axial 2nd PK stress for Green strain eps.
  double stress(double eps) const { return (eps > 0 || compression) ? E * eps : 0.0; }
  /// d stress / d eps; at eps = 0 the tension side (a taut, unstressed cable is stiff along
  /// its axis, so Newton can start from a straight cable at its unstressed length).
  double tangent(double eps) const { return (eps >= 0 || compression) ? E : 0.0; }
};

}  // namespace velum
