// The node-to-rigid-surface contact's outputs (docs/contact.md, "Outputs"): the history's
// contact force and area, a body's position, rotation and velocities, and the frames' contact
// pressure, gap and status.
#include "contact_term.hpp"

namespace velum::rigid_contact {

std::optional<double> ContactTerm::quantity_at(std::string_view name, double t,
                                               const NodePositions& x) const {
  // contact_force:body=NAME:c, contact_force:contact=I:c, rigid_position:NAME:c,
  // rigid_velocity:NAME:c (c = 0, 1, 2; 3: magnitude); contact_area:body=NAME,
  // contact_area:contact=I.
  if (name == fmt::format("contact_area:body={}", load_.body.name) ||
      name == fmt::format("contact_area:contact={}", load_.index)) {
    // The areas about the nodes that touch at the accepted state. On a process's piece the
    // areas at shared nodes lack the other processes' elements: not a number rather than a
    // wrong one (docs/scaling.md).
    if (site_.model.piece) return std::numeric_limits<double>::quiet_NaN();
    const std::vector<double> area = node_areas(x);
    double sum = 0;
    for (size_t i = 0; i < load_.nodes.size(); ++i)
      if (status_accepted_[i] != contact::Status::kOpen &&
          site_.assembler.keeps_node(load_.nodes[i]))
        sum += area[static_cast<size_t>(load_.nodes[i])];
    return sum;
  }
  const auto last = name.rfind(':');
  if (last == std::string_view::npos) return {};
  const int c = name[last + 1] - '0';
  const std::string_view key = name.substr(0, last);
  const double sf = site_.model.function_value(load_.body.function, t);
  auto pick = [&](const Vec3& v) { return c == 3 ? v.norm() : v[c]; };
  if (key == fmt::format("rigid_position:{}", load_.body.name))
    return pick(load_.body.position(sf));
  // The rotation vector (magnitude: its angle, in [0, π]) and the angular velocity: a rotating
  // free body's at the committed state, a moved body's s(t)·rotation and its rate.
  const bool rotation = key == fmt::format("rigid_rotation:{}", load_.body.name);
  if (rotation || key == fmt::format("rigid_angular_velocity:{}", load_.body.name)) {
    if (spin_)
      return pick(rotation ? rigid::rotation_vector(spin_->rot.orientation(t))
                           : spin_->rot.angular_velocity());
    if (rotation) return pick(Vec3(sf * load_.body.rotation));
    const BodyRate r = body_rate(t);
    return pick(Vec3((r.s1 - r.s0) / (2 * r.dt) * load_.body.rotation));
  }
  if (key == fmt::format("rigid_velocity:{}", load_.body.name)) {
    const BodyRate r = body_rate(t);
    return pick(Vec3((load_.body.position(r.s1) - load_.body.position(r.s0)) / (2 * r.dt)));
  }
  if (key != fmt::format("contact_force:body={}", load_.body.name) &&
      key != fmt::format("contact_force:contact={}", load_.index))
    return {};
  // The force the sheet exerts on the body: minus the contact forces on its nodes.
  Vec3 sum = Vec3::Zero();
  for (size_t i = 0; i < load_.nodes.size(); ++i)
    if (site_.assembler.keeps_node(load_.nodes[i])) sum -= accepted_force(i);
  return c == 3 ? sum.norm() : sum[c];  // a magnitude of one process's share: see the reader
}

std::vector<double> ContactTerm::node_areas(const NodePositions& x) const {
  // The forces of a unit follower pressure on the set's membranes (their current vector
  // area); a cable node's length instead. Empty parts on an MPI piece: no areas there.
  std::vector<double> area(static_cast<size_t>(x.cols()), 0.0), f;
  for (const ContactLoad::Part& part : load_.parts) {
    const ElementBlock& b = *site_.model.blocks[static_cast<size_t>(part.block)];
    f.assign(static_cast<size_t>(b.dofs_per_element()), 0.0);
    for (int e : part.elements) {
      if (!b.holds(e)) continue;
      const auto nodes = b.nodes(e);
      if (const SurfaceBlock* sb = b.surface()) {
        std::fill(f.begin(), f.end(), 0.0);
        sb->pressure(std::span<const int>(&e, 1), x, 1.0, f.data(), nullptr);
        for (size_t a = 0; a < nodes.size(); ++a)
          area[static_cast<size_t>(nodes[a])] += Eigen::Map<const Vec3>(&f[3 * a]).norm();
      } else {
        const double L = (x.col(nodes.back()) - x.col(nodes.front())).norm();
        for (int n : nodes) area[static_cast<size_t>(n)] += L / static_cast<double>(nodes.size());
      }
    }
  }
  return area;
}

bool ContactTerm::node_field(std::string_view name, double t, const NodePositions& x,
                             std::vector<double>& per_node) const {
  const bool pressure = name == "contact_pressure";
  if (name == "contact_status") {
    // 0 open, 1 stick, 2 slip (frictionless contact slides: 2); the most of the contacts.
    for (size_t i = 0; i < load_.nodes.size(); ++i) {
      double& v = per_node[static_cast<size_t>(load_.nodes[i])];
      const double s = static_cast<double>(status_accepted_[i]);
      v = std::isnan(v) ? s : std::max(v, s);
    }
    return true;
  }
  if (!pressure && name != "contact_gap") return false;
  if (pressure && site_.model.piece) return true;  // absent (NaN) on a piece: see contact_area
  const double sf = site_.model.function_value(load_.body.function, t);
  const std::vector<double> area = pressure ? node_areas(x) : std::vector<double>();
  const Frame fr = frame(t, x);
  for (size_t i = 0; i < load_.nodes.size(); ++i) {
    const int n = load_.nodes[i];
    const Vec3 y = to_body(fr, x.col(n));
    double& v = per_node[static_cast<size_t>(n)];
    if (pressure) {
      // The normal part of the accepted force (the tangential one is friction).
      Vec3 nn;
      Mat3 H;
      load_.body.gap(y, sf, nn, H);
      const double p = std::max(0.0, accepted_force(i).dot(fr.turned ? Vec3(fr.R * nn) : nn));
      const double a = area[static_cast<size_t>(n)];
      v = (std::isnan(v) ? 0.0 : v) + (a > 0 ? p / a : 0.0);
    } else {
      Vec3 nn;
      Mat3 H;
      const double g = load_.body.gap(y, sf, nn, H) - load_.node_thickness[i];
      v = std::isnan(v) ? g : std::min(v, g);
    }
  }
  return true;
}

}  // namespace velum::rigid_contact
