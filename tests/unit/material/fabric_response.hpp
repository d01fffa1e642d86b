// A fabric-like stress response for the stress-map law's tests: stiffening in its own
// direction, coupled to the other (S11 and S22 over the strains e1, e2).
#pragma once

namespace velum::fabric_response {

inline double s11(double e1, double e2) {
  return 600 * e1 + 9000 * e1 * e1 * e1 + 150 * e2 + 4000 * e1 * e2 * e2;
}
inline double s22(double e1, double e2) {
  return 400 * e2 + 20000 * e2 * e2 * e2 + 150 * e1 + 3000 * e1 * e1 * e2;
}

}  // namespace velum::fabric_response
