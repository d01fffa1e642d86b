// Monotone piecewise-cubic Hermite interpolation (Fritsch-Carlson / Fritsch-Butland slopes, as
// PCHIP): C1, through every data point, monotone wherever the data are, and linear beyond the
// ends with the end slopes (still C1). Used by the tabulated sheet laws (stress maps).
#pragma once

#include <span>
#include <vector>

namespace velum {

/// The PCHIP slopes at the points (x strictly increasing, at least two points): zero where
/// the secants change sign, their weighted harmonic mean elsewhere, the shape-preserving
/// three-point formula at the ends.
std::vector<double> monotone_slopes(std::span<const double> x, std::span<const double> y);

/// The weights of one axis of a cubic Hermite interpolant at t: the interval [x[i], x[i+1]]
/// holding t (the first or last beyond the ends) and the weights of (y_i, y_i+1, y'_i, y'_i+1)
/// in the value (w) and in its derivative (dw). Beyond the ends the cubic is continued by its
/// tangent line, so the interpolant stays C1.
struct HermiteWeights {
  int i = 0;
  double w[4] = {0, 0, 0, 0};
  double dw[4] = {0, 0, 0, 0};
};
HermiteWeights hermite_weights(std::span<const double> x, double t);

/// A 1D monotone cubic through (x, y): value and derivative at t.
class MonotoneCubic {
 public:
  MonotoneCubic() = default;
  MonotoneCubic(std::vector<double> x, std::vector<double> y);
  double operator()(double t, double* dy = nullptr) const;
  const std::vector<double>& x() const { return x_; }
  const std::vector<double>& y() const { return y_; }
  const std::vector<double>& slopes() const { return d_; }

 private:
  std::vector<double> x_, y_, d_;
};

}  // namespace velum
