// The contact benchmarks' sheet (bench/contact_search_bench.cpp, contact_search_libraries.cpp):
// a wavy sheet of n x n quads split in two (2 n² triangles), each face's box grown by the
// contact reach, and one node per quad a little above the sheet; `shift` moves the wave (the
// sheet of the next evaluation).
#pragma once

#include <cmath>
#include <vector>

#include "load/face_tree.hpp"

namespace velum::bench {

struct WavySheet {
  std::vector<contact::Box> boxes;
  std::vector<Vec3> points;
};

inline WavySheet wavy_sheet(long faces, double shift = 0) {
  const int n = static_cast<int>(std::sqrt(static_cast<double>(faces) / 2.0));
  const double h = 1.0 / n, reach = 0.5 * h;
  auto at = [&](int i, int j) {
    const double x = i * h, y = j * h;
    return Vec3(x, y, 0.05 * std::sin(6 * x + shift) * std::cos(5 * y));
  };
  WavySheet s;
  s.boxes.reserve(2 * static_cast<size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      for (int t = 0; t < 2; ++t) {
        contact::Box b(at(i, j));
        b.extend(t ? at(i + 1, j + 1) : at(i + 1, j));
        b.extend(t ? at(i, j + 1) : at(i + 1, j + 1));
        b.min().array() -= reach;
        b.max().array() += reach;
        s.boxes.push_back(b);
      }
      s.points.push_back(at(i, j) + Vec3(0.3 * h, 0.3 * h, 0.2 * h));
    }
  return s;
}

}  // namespace velum::bench
