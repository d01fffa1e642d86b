#include "velum/io/pattern_writer.hpp"

#include <fmt/format.h>

#include <fstream>
#include <stdexcept>

#include "velum/io/json_text.hpp"

namespace velum::io {
namespace {

double signed_area(const std::vector<Vec2>& poly) {
  double a = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec2& p = poly[i];
    const Vec2& q = poly[(i + 1) % poly.size()];
    a += p.x() * q.y() - q.x() * p.y();
  }
  return a / 2;
}

void write_text(const std::filesystem::path& file, const std::string& text) {
  std::ofstream out(file, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) throw std::runtime_error(fmt::format("{}: cannot write", file.string()));
}

std::string dxf_polyline(const std::vector<Vec2>& poly, const char* layer) {
  std::string s =
      fmt::format("0\nPOLYLINE\n8\n{}\n66\n1\n70\n1\n10\n0.0\n20\n0.0\n30\n0.0\n", layer);
  for (const Vec2& q : poly)
    s += fmt::format("0\nVERTEX\n8\n{}\n10\n{:.9g}\n20\n{:.9g}\n30\n0.0\n", layer, q.x(), q.y());
  return s + fmt::format("0\nSEQEND\n8\n{}\n", layer);
}

std::string svg_path(const std::vector<Vec2>& poly, double top) {
  std::string d;
  for (size_t i = 0; i < poly.size(); ++i)
    d += fmt::format("{}{:.6g},{:.6g} ", i ? "L" : "M", poly[i].x(), top - poly[i].y());
  return d + "Z";
}

}  // namespace

void outline_panel(PatternPanel& p, double warp, double fill, double allowance) {
  p.seam.clear();
  for (int k : p.flat.outline) {
    const Vec2& q = p.flat.uv[k];
    p.seam.emplace_back(q.x() * (1 - warp), q.y() * (1 - fill));
  }
  // Counter-clockwise, so that the outward normal of an edge d is (d.y, -d.x).
  if (signed_area(p.seam) < 0) std::reverse(p.seam.begin(), p.seam.end());
  p.cut = p.seam;
  if (allowance <= 0) return;
  const size_t n = p.seam.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = p.seam[(i + n - 1) % n], b = p.seam[i], c = p.seam[(i + 1) % n];
    const Vec2 d1 = (b - a).normalized(), d2 = (c - b).normalized();
    const Vec2 n1(d1.y(), -d1.x()), n2(d2.y(), -d2.x());
    Vec2 m = n1 + n2;
    // The mitre: the offset lines' meeting point, capped at sharp corners.
    const double cosine = m.norm() / 2;
    m = m.normalized() / std::max(cosine, 0.25);
    p.cut[i] = b + allowance * m;
  }
}

std::string panel_dxf(const PatternPanel& p) {
  std::string s =
      "0\nSECTION\n2\nHEADER\n9\n$ACADVER\n1\nAC1009\n0\nENDSEC\n"
      "0\nSECTION\n2\nTABLES\n0\nTABLE\n2\nLAYER\n70\n3\n";
  const std::pair<const char*, int> layers[] = {{"CUT", 7}, {"SEAM", 1}, {"TEXT", 3}};
  for (const auto& [name, colour] : layers)
    s += fmt::format("0\nLAYER\n2\n{}\n70\n0\n62\n{}\n6\nCONTINUOUS\n", name, colour);
  s += "0\nENDTAB\n0\nENDSEC\n0\nSECTION\n2\nENTITIES\n";
  s += dxf_polyline(p.cut, "CUT");
  s += dxf_polyline(p.seam, "SEAM");
  Vec2 c = Vec2::Zero();
  for (const Vec2& q : p.seam) c += q;
  c /= static_cast<double>(std::max<size_t>(1, p.seam.size()));
  const double h = 0.02 * std::sqrt(std::abs(signed_area(p.seam)));
  s += fmt::format(
      "0\nTEXT\n8\nTEXT\n10\n{:.9g}\n20\n{:.9g}\n30\n0.0\n40\n{:.6g}\n1\n{} area {:.6g}\n", c.x(),
      c.y(), h, p.name, std::abs(signed_area(p.seam)));
  return s + "0\nENDSEC\n0\nEOF\n";
}

void write_patterns(const std::filesystem::path& dir, const std::vector<PatternPanel>& panels,
                    const NodePositions& x, double warp, double fill, double allowance) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  std::string json = fmt::format(
      "{{\n  \"compensation\": [{:.17g}, {:.17g}],\n  \"seam_allowance\": {:.17g},\n  \"panels\": "
      "[",
      warp, fill, allowance);
  for (size_t i = 0; i < panels.size(); ++i) {
    const PatternPanel& p = panels[i];
    std::string nodes;
    for (size_t k = 0; k < p.flat.nodes.size(); ++k)
      nodes += fmt::format("{}[{}, {:.17g}, {:.17g}]", k ? ", " : "", p.node_ids[k],
                           p.flat.uv[k].x(), p.flat.uv[k].y());
    std::string outline;
    for (size_t k = 0; k < p.flat.outline.size(); ++k)
      outline += fmt::format("{}{}", k ? ", " : "", p.node_ids[p.flat.outline[k]]);
    json += fmt::format(
        "{}\n    {{\"name\": {}, \"area_3d\": {:.17g}, \"area_flat\": {:.17g}, "
        "\"area_cut\": {:.17g}, \"max_strain\": {:.17g}, \"iterations\": {},\n     \"outline\": "
        "[{}],\n"
        "     \"nodes\": [{}]}}",
        i ? "," : "", json_string(p.name), p.flat.area_3d, p.flat.area_flat,
        std::abs(signed_area(p.cut)), p.flat.max_strain, p.flat.iterations, outline, nodes);
    write_text(dir / (p.name + ".dxf"), panel_dxf(p));
    Vec2 lo = Vec2::Constant(1e300), hi = Vec2::Constant(-1e300);
    for (const Vec2& q : p.cut) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    const Vec2 size = hi - lo;
    const double pad = 0.05 * size.maxCoeff();
    write_text(
        dir / (p.name + ".svg"),
        fmt::format(
            "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"{:.6g} {:.6g} {:.6g} "
            "{:.6g}\" width=\"800\">\n"
            "<path d=\"{}\" fill=\"none\" stroke=\"black\" stroke-width=\"{:.3g}\"/>\n"
            "<path d=\"{}\" fill=\"none\" stroke=\"red\" stroke-dasharray=\"{:.3g}\" "
            "stroke-width=\"{:.3g}\"/>\n"
            "<text x=\"{:.6g}\" y=\"{:.6g}\" font-size=\"{:.3g}\">{} area {:.6g}</text>\n</svg>\n",
            lo.x() - pad, -hi.y() - pad, size.x() + 2 * pad, size.y() + 2 * pad, svg_path(p.cut, 0),
            0.003 * size.maxCoeff(), svg_path(p.seam, 0), 0.02 * size.maxCoeff(),
            0.003 * size.maxCoeff(), lo.x() + 0.5 * pad, -(lo.y() + hi.y()) / 2,
            0.04 * size.maxCoeff(), p.name, std::abs(signed_area(p.cut))));
  }
  json += "\n  ]\n}\n";
  write_text(dir / "patterns.json", json);

  // The 3-D shape with the strain flattening left, one cell per triangle.
  std::string pts, conn, offs, types, strain, panel;
  for (int n = 0; n < x.cols(); ++n)
    pts += fmt::format("{:.9g} {:.9g} {:.9g}\n", x(0, n), x(1, n), x(2, n));
  long cells = 0;
  for (size_t i = 0; i < panels.size(); ++i) {
    const FlatPanel& f = panels[i].flat;
    for (size_t t = 0; t < f.triangles.size(); ++t) {
      const auto& tri = f.triangles[t];
      conn += fmt::format("{} {} {}\n", f.nodes[tri[0]], f.nodes[tri[1]], f.nodes[tri[2]]);
      offs += fmt::format("{}\n", 3 * ++cells);
      types += "5\n";
      strain += fmt::format("{:.9g}\n", f.strain[t]);
      panel += fmt::format("{}\n", i);
    }
  }
  write_text(
      dir / "flattening.vtu",
      fmt::format(
          "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\">\n"
          "<UnstructuredGrid><Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n"
          "<Points><DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n{}"
          "</DataArray></Points>\n<Cells>\n"
          "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n{}</DataArray>\n"
          "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n{}</DataArray>\n"
          "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n{}</DataArray>\n"
          "</Cells>\n<CellData Scalars=\"flattening_strain\">\n"
          "<DataArray type=\"Float64\" Name=\"flattening_strain\" "
          "format=\"ascii\">\n{}</DataArray>\n"
          "<DataArray type=\"Int32\" Name=\"panel\" format=\"ascii\">\n{}</DataArray>\n"
          "</CellData>\n</Piece></UnstructuredGrid>\n</VTKFile>\n",
          x.cols(), cells, pts, conn, offs, types, strain, panel));
}

}  // namespace velum::io
