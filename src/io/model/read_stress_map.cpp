#include "read_stress_map.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string_view>

#include "velum/material/stress_map_sheet_law.hpp"

namespace velum::io::model_file {
namespace {

/// The numeric rows of a CSV file with a header naming `columns` (in this order; case and
/// surrounding blanks ignored); '#' starts a comment line. Problems go to r under `key`.
struct CsvTable {
  std::vector<std::vector<double>> rows;
  std::vector<int> lines;  ///< 1-based line of each row
};

std::string trim(std::string s) {
  const auto ws = [](unsigned char c) { return std::isspace(c) != 0; };
  s.erase(s.begin(), std::find_if_not(s.begin(), s.end(), ws));
  s.erase(std::find_if_not(s.rbegin(), s.rend(), ws).base(), s.end());
  return s;
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  size_t start = 0;
  for (;;) {
    const size_t c = line.find(',', start);
    out.push_back(trim(line.substr(start, c == std::string::npos ? c : c - start)));
    if (c == std::string::npos) return out;
    start = c + 1;
  }
}

std::optional<CsvTable> read_csv(ReaderContext& r, const std::string& file, const std::string& key,
                                 const std::vector<std::string>& columns) {
  std::ifstream in(file);
  if (!in) {
    r.error_in_file(file, 0, key, "cannot open the file");
    return std::nullopt;
  }
  CsvTable t;
  bool header = false, ok = true;
  std::string line;
  for (int ln = 1; std::getline(in, line); ++ln) {
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    auto cells = split(line);
    if (!header) {
      for (auto& c : cells)
        std::transform(c.begin(), c.end(), c.begin(),
                       [](unsigned char ch) { return std::tolower(ch); });
      if (cells != columns) {
        r.error_in_file(file, ln, key,
                        fmt::format("expected the header '{}'", fmt::join(columns, ",")));
        return std::nullopt;
      }
      header = true;
      continue;
    }
    if (cells.size() != columns.size()) {
      r.error_in_file(file, ln, key,
                      fmt::format("expected {} values, got {}", columns.size(), cells.size()));
      ok = false;
      continue;
    }
    std::vector<double> row;
    for (size_t c = 0; c < cells.size(); ++c) {
      char* end = nullptr;
      const double v = std::strtod(cells[c].c_str(), &end);
      if (cells[c].empty() || *end != '\0' || !std::isfinite(v)) {
        r.error_in_file(file, ln, key,
                        fmt::format("{}: '{}' is not a finite number", columns[c], cells[c]));
        ok = false;
        break;
      }
      row.push_back(v);
    }
    if (row.size() == columns.size()) {
      t.rows.push_back(std::move(row));
      t.lines.push_back(ln);
    }
  }
  if (!header) {
    r.error_in_file(file, 0, key,
                    fmt::format("empty file (expected the header '{}')", fmt::join(columns, ",")));
    return std::nullopt;
  }
  if (!ok) return std::nullopt;
  return t;
}

/// The grid file: one row per grid point, sorted by strain_fill, then strain_warp; every
/// strain_fill block holds the same strain_warp values (no holes).
bool read_grid(ReaderContext& r, const std::string& file, const std::string& key,
               StressMapData& d) {
  const auto t =
      read_csv(r, file, key, {"strain_warp", "strain_fill", "stress_warp", "stress_fill"});
  if (!t) return false;
  if (t->rows.empty()) {
    r.error_in_file(file, 0, key, "no grid points");
    return false;
  }
  const auto& rows = t->rows;
  const auto& ln = t->lines;
  // The warp axis from the first block of equal strain_fill.
  size_t n1 = 0;
  while (n1 < rows.size() && rows[n1][1] == rows[0][1]) ++n1;
  for (size_t k = 0; k < rows.size(); ++k) {
    const size_t i = k % n1, j = k / n1;
    if (i == 0) {
      if (j > 0 && !(rows[k][1] > rows[k - 1][1])) {
        r.error_in_file(file, ln[k], key,
                        rows[k][1] == rows[k - 1][1]
                            ? fmt::format("strain_fill = {} has more points than the first "
                                          "block ({}): each strain_fill needs the same "
                                          "strain_warp values",
                                          rows[k][1], n1)
                            : fmt::format("strain_fill must increase from block to block (rows "
                                          "sorted by strain_fill, then strain_warp; got {} "
                                          "after {})",
                                          rows[k][1], rows[k - 1][1]));
        return false;
      }
      d.e2.push_back(rows[k][1]);
    } else if (rows[k][1] != rows[k - 1][1]) {
      r.error_in_file(file, ln[k], key,
                      fmt::format("the grid has a hole: strain_fill = {} lacks strain_warp = {} "
                                  "(every strain_fill needs the same {} strain_warp values)",
                                  rows[k - 1][1], d.e1[i], n1));
      return false;
    }
    if (j == 0) {
      if (i > 0 && !(rows[k][0] > rows[k - 1][0])) {
        r.error_in_file(file, ln[k], key,
                        fmt::format("strain_warp must increase within a strain_fill block (got "
                                    "{} after {})",
                                    rows[k][0], rows[k - 1][0]));
        return false;
      }
      d.e1.push_back(rows[k][0]);
    } else if (rows[k][0] != d.e1[i]) {
      r.error_in_file(file, ln[k], key,
                      fmt::format("strain_warp = {} where the grid has {} (every strain_fill "
                                  "needs the same strain_warp values, a hole or an extra point)",
                                  rows[k][0], d.e1[i]));
      return false;
    }
    d.S11.push_back(rows[k][2]);
    d.S22.push_back(rows[k][3]);
  }
  if (rows.size() % n1 != 0) {
    r.error_in_file(file, ln.back(), key,
                    fmt::format("the last strain_fill block has {} points, the others {}",
                                rows.size() % n1, n1));
    return false;
  }
  // Monotone where the law needs it, named at the offending row.
  for (size_t k = 0; k < rows.size(); ++k) {
    if (k % n1 > 0 && !(rows[k][2] > rows[k - 1][2])) {
      r.error_in_file(
          file, ln[k], key,
          fmt::format("stress_warp must increase with strain_warp (at strain_fill = "
                      "{}: {} at strain_warp {} after {} at {})",
                      rows[k][1], rows[k][2], rows[k][0], rows[k - 1][2], rows[k - 1][0]));
      return false;
    }
    if (k >= n1 && !(rows[k][3] > rows[k - n1][3])) {
      r.error_in_file(
          file, ln[k], key,
          fmt::format("stress_fill must increase with strain_fill (at strain_warp = "
                      "{}: {} at strain_fill {} after {} at {})",
                      rows[k][0], rows[k][3], rows[k][1], rows[k - n1][3], rows[k - n1][1]));
      return false;
    }
  }
  if (d.e1.size() < 2 || d.e2.size() < 2) {
    r.error_in_file(file, ln.back(), key,
                    fmt::format("the grid needs at least two strain_warp and two strain_fill "
                                "values (got {} x {})",
                                d.e1.size(), d.e2.size()));
    return false;
  }
  return true;
}

bool read_shear(ReaderContext& r, const std::string& file, const std::string& key,
                StressMapData& d) {
  const auto t = read_csv(r, file, key, {"shear_strain", "shear_stress"});
  if (!t) return false;
  const auto& rows = t->rows;
  if (rows.size() < 2 || rows[0][0] != 0 || rows[0][1] != 0) {
    r.error_in_file(file, rows.empty() ? 0 : t->lines[0], key,
                    "the shear curve starts at shear_strain = 0, shear_stress = 0 and has at "
                    "least two points");
    return false;
  }
  for (size_t k = 1; k < rows.size(); ++k) {
    if (!(rows[k][0] > rows[k - 1][0])) {
      r.error_in_file(
          file, t->lines[k], key,
          fmt::format("shear_strain must increase (got {} after {})", rows[k][0], rows[k - 1][0]));
      return false;
    }
    if (!(rows[k][1] > rows[k - 1][1])) {
      r.error_in_file(file, t->lines[k], key,
                      fmt::format("shear_stress must increase with shear_strain (got {} at {} "
                                  "after {} at {})",
                                  rows[k][1], rows[k][0], rows[k - 1][1], rows[k - 1][0]));
      return false;
    }
    d.gamma.push_back(rows[k - 1][0]);
    d.S12.push_back(rows[k - 1][1]);
  }
  d.gamma.push_back(rows.back()[0]);
  d.S12.push_back(rows.back()[1]);
  return true;
}

}  // namespace

std::optional<SheetLaw> parse_stress_map(ReaderContext& r, const Node& m, const std::string& name,
                                         const std::string& p) {
  r.check_map(m, p, {"type", "map", "shear", "G12", "unloading_modulus", "density"});
  const auto file = [&](const char* key) -> std::optional<std::string> {
    auto f = r.text(m, key, p, false);
    if (!f) return std::nullopt;
    std::filesystem::path path(*f);
    if (path.is_relative()) path = r.base_dir() / path;
    return path.string();
  };
  StressMapData d;
  bool ok = r.require(m, "map", p);
  if (ok) {
    if (auto f = file("map"))
      ok = read_grid(r, *f, ReaderContext::sub(p, "map"), d);
    else
      ok = false;
  }
  const bool curve = r.has(m, "shear"), modulus = r.has(m, "G12");
  if (curve == modulus) {
    r.error(m, p, "give the shear response as either `shear: FILE.csv` or `G12: modulus`");
    return std::nullopt;
  }
  if (curve) {
    auto f = file("shear");
    ok = f && read_shear(r, *f, ReaderContext::sub(p, "shear"), d) && ok;
  } else if (auto G = r.positive(m, "G12", p, true, "the shear modulus G12")) {
    d.G12 = *G;
  } else {
    ok = false;
  }
  const bool has_unloading = r.has(m, "unloading_modulus");
  if (has_unloading) {
    // [warp, fill], 0 where that direction unloads along the map; one number for both.
    const Node u = m["unloading_modulus"];
    const std::string up = ReaderContext::sub(p, "unloading_modulus");
    const bool pair = u.IsSequence() && u.size() == 2;
    if (!pair && !u.IsScalar()) {
      r.error(u, up, "expected [warp, fill] unloading moduli (or one number for both)");
      return std::nullopt;
    }
    for (int c = 0; c < 2; ++c) {
      const auto K = r.number(pair ? u[static_cast<size_t>(c)] : u, up);
      if (!K) return std::nullopt;
      if (*K < 0) {
        r.error(u, up, fmt::format("an unloading modulus must not be negative (got {})", *K));
        return std::nullopt;
      }
      d.unloading[c] = *K;
    }
  }
  if (!ok) return std::nullopt;
  try {
    return SheetLaw(StressMapSheetLaw(name, std::move(d)));
  } catch (const MaterialError& e) {
    // The unloading moduli are checked against the map; such a problem is the moduli's key's.
    const char* key =
        std::string_view(e.what()).find("unloading") != std::string_view::npos && has_unloading
            ? "unloading_modulus"
            : "map";
    r.error(m[key], ReaderContext::sub(p, key), e.what());
  }
  return std::nullopt;
}

}  // namespace velum::io::model_file
