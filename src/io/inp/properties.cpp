// *MATERIAL (*ELASTIC, *DENSITY, *NO COMPRESSION), *ORIENTATION, *MEMBRANE SECTION and
// *SOLID SECTION.

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "model.hpp"

namespace velum::io::inp {
namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;

/// All numbers of a block's data lines, in order.
std::optional<std::vector<double>> values(const Keyword& k, Diagnostics& diag) {
  std::vector<double> v;
  bool ok = true;
  for (const auto& d : k.data)
    for (size_t i = 0; i < d.fields.size(); ++i) {
      auto x =
          diag.number(k, d, i, d.fields[i].empty() ? std::optional<double>(0.0) : std::nullopt);
      if (!x)
        ok = false;
      else
        v.push_back(*x);
    }
  if (!ok) return std::nullopt;
  return v;
}

/// The plane-stress stiffness (σ33 = σ13 = σ23 = 0) of a 3-D stiffness in Abaqus's Voigt order
/// 11 22 33 12 13 23 with engineering shear strains: the in-plane block of the compliance,
/// inverted.
std::optional<Mat3> plane_stress(const Mat6& D) {
  Eigen::LLT<Mat6> llt(D);
  if (llt.info() != Eigen::Success) return std::nullopt;
  const Mat6 S = llt.solve(Mat6::Identity());
  const int in_plane[3] = {0, 1, 3};
  Mat3 s;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) s(i, j) = S(in_plane[i], in_plane[j]);
  Mat3 Q = s.inverse();
  return Mat3(0.5 * (Q + Q.transpose()));
}

void read_elastic(const Keyword& k, Material& m, Diagnostics& diag) {
  diag.check_options(k, {"TYPE"});
  const std::string type = k.has("TYPE") ? canonical(k.options.at("TYPE")) : "ISOTROPIC";
  m.elastic_type = type;
  m.elastic_line = k.line;
  auto v = values(k, diag);
  if (!v) return;
  // counts: without and with the temperature column
  auto count = [&](size_t n) {
    if (v->size() == n || v->size() == n + 1) return true;
    diag.error(k, fmt::format("TYPE={} takes {} constants on its data lines (and an optional "
                              "temperature), got {} values{}",
                              type, n, v->size(),
                              v->size() > n + 1 ? ": temperature-dependent elasticity is not "
                                                  "supported"
                                                : ""));
    return false;
  };
  const auto& c = *v;
  if (type == "ISO" || type == "ISOTROPIC") {
    if (!count(2)) return;
    m.law = Material::Law::kIsotropic;
    m.E = c[0], m.nu = c[1];
  } else if (type == "ENGINEERING CONSTANTS" || type == "LAMINA") {
    // E1 E2 E3 nu12 nu13 nu23 G12 G13 G23 | E1 E2 nu12 G12 G13 G23: the plane-stress law of
    // a sheet in its 1-2 plane needs E1 E2 nu12 G12 only.
    const bool lamina = type == "LAMINA";
    if (!count(lamina ? 6 : 9)) return;
    m.law = Material::Law::kOrthotropic;
    m.E1 = c[0], m.E2 = c[1];
    m.nu12 = lamina ? c[2] : c[3];
    m.G12 = lamina ? c[3] : c[6];
  } else if (type == "ORTHO" || type == "ORTHOTROPIC" || type == "ANISO" || type == "ANISOTROPIC") {
    const bool ortho = type == "ORTHO" || type == "ORTHOTROPIC";
    if (!count(ortho ? 9 : 21)) return;
    Mat6 D = Mat6::Zero();
    if (ortho) {  // D1111 D1122 D2222 D1133 D2233 D3333 D1212 D1313 D2323
      D(0, 0) = c[0], D(0, 1) = c[1], D(1, 1) = c[2], D(0, 2) = c[3], D(1, 2) = c[4];
      D(2, 2) = c[5], D(3, 3) = c[6], D(4, 4) = c[7], D(5, 5) = c[8];
    } else {  // the upper triangle, column by column
      size_t n = 0;
      for (int j = 0; j < 6; ++j)
        for (int i = 0; i <= j; ++i) D(i, j) = c[n++];
    }
    D = D.selfadjointView<Eigen::Upper>();
    auto Q = plane_stress(D);
    if (!Q) {
      diag.error(k, "the elasticity matrix is not positive definite: no plane-stress law");
      return;
    }
    m.law = Material::Law::kMatrix;
    m.Q = *Q;
  } else {
    diag.error(k, fmt::format("TYPE={} is not supported (ISOTROPIC, ENGINEERING CONSTANTS, "
                              "LAMINA, ORTHOTROPIC, ANISOTROPIC)",
                              type));
  }
}

void read_orientation(const Keyword& k, Properties& p, Diagnostics& diag) {
  diag.check_options(k, {"NAME", "SYSTEM", "DEFINITION"});
  auto name = diag.required(k, "NAME");
  if (!name) return;
  Orientation o;
  o.name = *name;
  o.file = k.file, o.line = k.line;
  if (k.has("SYSTEM")) {
    const std::string s = canonical(k.options.at("SYSTEM"));
    if (s != "RECTANGULAR" && s != "R") {
      diag.error(k, fmt::format("SYSTEM={} is not supported: only RECTANGULAR maps to Velum's "
                                "sheet axes",
                                s));
      return;
    }
  }
  if (k.has("DEFINITION")) {
    const std::string d = canonical(k.options.at("DEFINITION"));
    if (d == "NODES")
      o.by_nodes = true;
    else if (d != "COORDINATES") {
      diag.error(k, fmt::format("DEFINITION={} is not supported (COORDINATES or NODES)", d));
      return;
    }
  }
  if (k.data.empty() || k.data.size() > 2) {
    diag.error(k, "expected one or two data lines (the points a, b [, c]; then axis, angle)");
    return;
  }
  const DataLine& d = k.data[0];
  if (o.by_nodes) {
    auto a = diag.integer(k, d, 0), b = diag.integer(k, d, 1), c = diag.integer(k, d, 2, 0L);
    if (!a || !b || !c) return;
    o.na = *a, o.nb = *b, o.nc = *c;
  } else {
    if (d.fields.size() != 6 && d.fields.size() != 9) {
      diag.error(k, d, "expected a1, a2, a3, b1, b2, b3 [, c1, c2, c3]");
      return;
    }
    double x[9] = {};
    for (size_t i = 0; i < d.fields.size(); ++i) {
      auto v = diag.number(k, d, i);
      if (!v) return;
      x[i] = *v;
    }
    o.a = Vec3(x[0], x[1], x[2]), o.b = Vec3(x[3], x[4], x[5]), o.c = Vec3(x[6], x[7], x[8]);
  }
  if (k.data.size() == 2) {
    const DataLine& r = k.data[1];
    auto axis = diag.integer(k, r, 0, 3L);
    auto angle = diag.number(k, r, 1, 0.0);
    if (!axis || !angle) return;
    if (*angle != 0 && *axis != 3) {
      diag.error(k, r,
                 "a sheet's axes turn about its normal: the additional rotation's axis "
                 "must be 3");
      return;
    }
    o.angle = *angle;
  }
  const std::string key = canonical(*name);
  if (p.orientation_at.count(key)) {
    diag.error(k, fmt::format("orientation '{}' is defined twice", *name));
    return;
  }
  p.orientation_at[key] = p.orientations.size();
  p.orientations.push_back(o);
}

void read_section(const Keyword& k, Properties& p, Diagnostics& diag) {
  const bool membrane = k.name == "MEMBRANE SECTION";
  diag.check_options(k, membrane ? std::vector<std::string>{"ELSET", "MATERIAL", "ORIENTATION"}
                                 : std::vector<std::string>{"ELSET", "MATERIAL"});
  auto elset = diag.required(k, "ELSET");
  auto mat = diag.required(k, "MATERIAL");
  if (!elset || !mat) return;
  Section s;
  s.membrane = membrane;
  s.elset = canonical(*elset);
  s.material = canonical(*mat);
  s.file = k.file, s.line = k.line;
  if (k.has("ORIENTATION")) s.orientation = canonical(k.options.at("ORIENTATION"));
  if (k.data.size() > 1) {
    diag.error(k, "expected one data line (the thickness or the cross-section area)");
    return;
  }
  if (!k.data.empty()) {
    const DataLine& d = k.data[0];
    if (d.fields.size() > 1 && !membrane) {
      diag.error(k, d, "a truss section takes its cross-section area only");
      return;
    }
    auto v = diag.number(k, d, 0, 1.0);
    if (!v) return;
    if (*v <= 0) {
      diag.error(k, d,
                 fmt::format("the {} must be positive (got {})",
                             membrane ? "thickness" : "cross-section area", *v));
      return;
    }
    s.size = *v;
  }
  p.sections.push_back(s);
}

}  // namespace

Properties read_properties(const std::vector<Keyword>& keywords, std::vector<bool>& used,
                           Diagnostics& diag) {
  Properties p;
  long current = -1;  // the material whose options follow
  for (size_t i = 0; i < keywords.size(); ++i) {
    const Keyword& k = keywords[i];
    const bool option = k.name == "ELASTIC" || k.name == "DENSITY" || k.name == "NO COMPRESSION";
    if (k.name == "MATERIAL") {
      used[i] = true;
      current = -1;
      diag.check_options(k, {"NAME"});
      auto name = diag.required(k, "NAME");
      if (!name) continue;
      const std::string key = canonical(*name);
      if (p.material_at.count(key)) {
        diag.error(k, fmt::format("material '{}' is defined twice", *name));
        continue;
      }
      current = static_cast<long>(p.materials.size());
      p.material_at[key] = p.materials.size();
      Material m;
      m.name = *name;
      m.file = k.file, m.line = k.line;
      p.materials.push_back(m);
    } else if (option) {
      used[i] = true;
      if (current < 0) {
        diag.error(k, "a material option outside a *MATERIAL block");
        continue;
      }
      Material& m = p.materials[static_cast<size_t>(current)];
      if (k.name == "ELASTIC") {
        if (m.law != Material::Law::kNone) diag.error(k, "the material has an *ELASTIC already");
        read_elastic(k, m, diag);
      } else if (k.name == "DENSITY") {
        diag.check_options(k, {});
        auto v = values(k, diag);
        if (v && (v->empty() || v->size() > 2))
          diag.error(k, "expected the density (and an optional temperature) on one data line");
        else if (v && (*v)[0] < 0)
          diag.error(k, fmt::format("the density must not be negative (got {})", (*v)[0]));
        else if (v)
          m.density = (*v)[0];
      } else {
        diag.check_options(k, {});
        if (!k.data.empty()) diag.error(k, "*NO COMPRESSION takes no data lines");
        m.no_compression = true;
      }
    } else {
      current = -1;
      if (k.name == "ORIENTATION") {
        used[i] = true;
        read_orientation(k, p, diag);
      } else if (k.name == "MEMBRANE SECTION" || k.name == "SOLID SECTION") {
        used[i] = true;
        read_section(k, p, diag);
      }
    }
  }
  return p;
}

}  // namespace velum::io::inp
