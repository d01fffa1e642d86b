#include "velum/model/time_function.hpp"

#include <algorithm>

namespace velum {

double TimeFunction::operator()(double t) const {
  switch (kind) {
    case Kind::kConstant:
      return value;
    case Kind::kRamp:
      return std::clamp(t / duration, 0.0, 1.0);
    case Kind::kTable: {
      if (points.empty()) return 0.0;
      if (t <= points.front().first) return points.front().second;
      if (t >= points.back().first) return points.back().second;
      const auto it = std::upper_bound(points.begin(), points.end(), t,
                                       [](double v, const auto& p) { return v < p.first; });
      const auto& [t1, v1] = *(it - 1);
      const auto& [t2, v2] = *it;
      return v1 + (v2 - v1) * (t - t1) / (t2 - t1);
    }
  }
  return 0.0;
}

}  // namespace velum
