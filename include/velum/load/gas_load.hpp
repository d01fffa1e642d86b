// Gas enclosed by membrane elements together with the symmetry planes through `origin`
// (load type `gas`, docs/inflatables.md): absolute pressure p = initial_pressure
// (amount(t) V0 / V)^gamma, the sheet loaded by p − ambient as a follower pressure, with the
// rank-one Jacobian term of p(V). Units the user's.
#pragma once

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "velum/load/load.hpp"

namespace velum {

struct GasLoad {
  struct Part {
    int block = -1;
    std::vector<int> elements;  ///< indices into the block
  };
  std::vector<Part> parts;
  double initial_pressure = 0, ambient = 0, gamma = 1;
  int amount = -1;  ///< time function of the gas amount (relative to the initial), -1: 1
  Vec3 origin = Vec3::Zero();
  double V0 = 0;  ///< reference volume, set by set_up_gas_chamber

  /// Absolute pressure at volume V and amount m; NaN when V <= 0 (a chamber turned inside
  /// out has no pressure: the residual turns non-finite and the step is cut).
  double pressure(double V, double m) const {
    return V > 0 ? initial_pressure * std::pow(m * V0 / V, gamma)
                 : std::numeric_limits<double>::quiet_NaN();
  }
};

std::unique_ptr<Load> make_load(GasLoad p);

}  // namespace velum
