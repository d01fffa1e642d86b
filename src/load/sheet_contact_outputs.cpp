// Sheet contact's outputs: the nodes' areas, the contact area (history contact_area) and the
// point fields (contact_status, contact_pressure, contact_gap).
#include "sheet_contact_term.hpp"

namespace velum::sheet_contact {

std::vector<double> SheetContactTerm::node_areas(const NodePositions& x, int which) const {
  std::vector<double> area(static_cast<size_t>(x.cols()), 0.0);
  for (int w = 0; w < 2; ++w) {
    if (which >= 0 && w != which) continue;
    for (const Face& f : load_.faces[static_cast<size_t>(w)]) {
      const double A =
          (x.col(f.n[1]) - x.col(f.n[0])).cross(x.col(f.n[2]) - x.col(f.n[0])).norm() / 6;
      for (int n : f.n) area[static_cast<size_t>(n)] += A;
    }
  }
  return area;
}

double SheetContactTerm::contact_area(const NodePositions& x) const {
  // The first set's nodes that carry a contact force at the accepted state (as a node or as a
  // face's corner), each with its area; self contact touches with both layers: half of it.
  const std::vector<double> area = node_areas(x, 0);
  double sum = 0;
  for (int n : load_.passes[0].nodes)
    if (transmitted_[static_cast<size_t>(n)] > 0) sum += area[static_cast<size_t>(n)];
  return load_.self ? sum / 2 : sum;
}

bool SheetContactTerm::node_field(std::string_view name, double, const NodePositions& x,
                                  std::vector<double>& per_node) const {
  const bool pressure = name == "contact_pressure", status = name == "contact_status";
  if (!pressure && !status && name != "contact_gap") return false;
  const std::vector<double> area = pressure ? node_areas(x, -1) : std::vector<double>();
  for (size_t p = 0; p < load_.passes.size(); ++p)
    for (size_t i = 0; i < load_.passes[p].nodes.size(); ++i) {
      const size_t k = slot(p, i), n = static_cast<size_t>(load_.passes[p].nodes[i]);
      double& v = per_node[n];
      if (status) {
        // 0 open, 1 stick, 2 slip (frictionless pairs slide).
        const double s = node_status_[n];
        v = std::isnan(v) ? s : std::max(v, s);
      } else if (pressure) {
        // Once per node (self contact and shared nodes list a node in one pass only).
        v = (std::isnan(v) ? 0.0 : v) + (area[n] > 0 ? transmitted_[n] / area[n] : 0.0);
      } else if (!std::isnan(gap_accepted_[k])) {
        v = std::isnan(v) ? gap_accepted_[k] : std::min(v, gap_accepted_[k]);
      }
    }
  return true;
}

}  // namespace velum::sheet_contact
