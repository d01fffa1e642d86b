// The symmetric 2x2 tensors of the hyperelastic sheet laws in Voigt order (11, 22, 12): what
// the compressible and the incompressible law (their .cpp files) share.
#pragma once

#include "velum/math/types.hpp"

namespace velum::voigt_pairs {

// Voigt rows of the symmetric 2x2 index pairs: (0,0), (1,1), (0,1).
inline constexpr int kI[3] = {0, 1, 0}, kJ[3] = {0, 1, 1};

inline Vec3 voigt(const Mat2& A) {
  return {A(0, 0), A(1, 1), A(0, 1)};
}

}  // namespace velum::voigt_pairs
