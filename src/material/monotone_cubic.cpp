#include "velum/material/monotone_cubic.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace velum {

namespace {

/// The end slope from the first two intervals (h0, h1) and secants (d0, d1), kept of the
/// sign of d0 and at most 3 d0 where the secants change sign (no overshoot at the end).
double end_slope(double h0, double h1, double d0, double d1) {
  const double d = ((2 * h0 + h1) * d0 - h0 * d1) / (h0 + h1);
  if (d * d0 <= 0) return 0;
  if (d0 * d1 <= 0 && std::abs(d) > std::abs(3 * d0)) return 3 * d0;
  return d;
}

}  // namespace

std::vector<double> monotone_slopes(std::span<const double> x, std::span<const double> y) {
  const size_t n = x.size();
  if (n < 2 || y.size() != n) throw std::invalid_argument("monotone_slopes: needs two points");
  std::vector<double> h(n - 1), del(n - 1), d(n);
  for (size_t k = 0; k + 1 < n; ++k) {
    h[k] = x[k + 1] - x[k];
    del[k] = (y[k + 1] - y[k]) / h[k];
  }
  if (n == 2) {
    d[0] = d[1] = del[0];
    return d;
  }
  for (size_t k = 1; k + 1 < n; ++k) {
    if (del[k - 1] * del[k] <= 0) {
      d[k] = 0;
    } else {
      const double w1 = 2 * h[k] + h[k - 1], w2 = h[k] + 2 * h[k - 1];
      d[k] = (w1 + w2) / (w1 / del[k - 1] + w2 / del[k]);
    }
  }
  d[0] = end_slope(h[0], h[1], del[0], del[1]);
  d[n - 1] = end_slope(h[n - 2], h[n - 3], del[n - 2], del[n - 3]);
  return d;
}

HermiteWeights hermite_weights(std::span<const double> x, double t) {
  HermiteWeights hw;
  const int n = static_cast<int>(x.size());
  const auto it = std::upper_bound(x.begin(), x.end(), t);
  hw.i = std::clamp(static_cast<int>(it - x.begin()) - 1, 0, n - 2);
  const double x0 = x[hw.i], h = x[hw.i + 1] - x0;
  // Beyond an end the tangent line there: weights of the value and slope at that end.
  if (t < x0) {
    hw.w[0] = 1, hw.w[2] = t - x0, hw.dw[2] = 1;
    return hw;
  }
  if (t > x0 + h) {
    hw.w[1] = 1, hw.w[3] = t - (x0 + h), hw.dw[3] = 1;
    return hw;
  }
  const double s = (t - x0) / h, s2 = s * s, s3 = s2 * s;
  hw.w[0] = 2 * s3 - 3 * s2 + 1;
  hw.w[1] = -2 * s3 + 3 * s2;
  hw.w[2] = (s3 - 2 * s2 + s) * h;
  hw.w[3] = (s3 - s2) * h;
  hw.dw[0] = (6 * s2 - 6 * s) / h;
  hw.dw[1] = (-6 * s2 + 6 * s) / h;
  hw.dw[2] = 3 * s2 - 4 * s + 1;
  hw.dw[3] = 3 * s2 - 2 * s;
  return hw;
}

MonotoneCubic::MonotoneCubic(std::vector<double> x, std::vector<double> y)
    : x_(std::move(x)), y_(std::move(y)), d_(monotone_slopes(x_, y_)) {}

double MonotoneCubic::operator()(double t, double* dy) const {
  const HermiteWeights hw = hermite_weights(x_, t);
  const int i = hw.i;
  const double v[4] = {y_[i], y_[i + 1], d_[i], d_[i + 1]};
  double f = 0, df = 0;
  for (int a = 0; a < 4; ++a) f += hw.w[a] * v[a], df += hw.dw[a] * v[a];
  if (dy) *dy = df;
  return f;
}

}  // namespace velum
