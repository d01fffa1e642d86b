// Time functions that scale loads and prescribed motions: constant (the default "step" = 1),
// ramp (linear from 0 at t = 0 to 1 at `duration`, then held) and table (piecewise linear,
// held constant outside the points).
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace velum {

struct TimeFunction {
  enum class Kind { kConstant, kRamp, kTable };
  Kind kind = Kind::kConstant;
  double value = 1.0;                             ///< kConstant
  double duration = 1.0;                          ///< kRamp
  std::vector<std::pair<double, double>> points;  ///< kTable, strictly increasing times
  std::string name = "step";

  double operator()(double t) const;
};

}  // namespace velum
