// How far a sheet law's derivatives are from central differences, as the law tests report it.
#pragma once

namespace velum {

/// Largest entry of |C - differences of S| over the largest entry of C (tangent), and of
/// |S - differences of the energy| over the largest entry of S (stress).
struct FdError {
  double tangent = 0, stress = 0;
};

}  // namespace velum
