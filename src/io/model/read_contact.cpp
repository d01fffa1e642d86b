// The model's `rigid_bodies:` and `contact:` (docs/contact.md), and the history entries
// `contact_force`, `rigid_position` and `rigid_velocity`: each contact entry becomes a
// contact load (load/contact_load.hpp) holding its body.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <map>
#include <optional>

#include <Eigen/Eigenvalues>

#include "reader.hpp"
#include "velum/io/mesh_data.hpp"
#include "velum/load/contact_load.hpp"

namespace velum::io::model_file {

std::optional<Mat3> Reader::read_inertia(const Node& n, const std::string& p) {
  // A number (a sphere's I), three principal values along the global axes, or the 3 x 3
  // tensor in the global axes at t = 0: about the centre of mass, symmetric, positive, and a
  // body's (each principal value at most the sum of the other two).
  const char* expected =
      "expected a number, three principal values [Ixx, Iyy, Izz] or a 3 x 3 symmetric tensor "
      "[[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]] (kg m^2, about the centre of mass)";
  Mat3 J = Mat3::Zero();
  if (n.IsScalar()) {
    auto v = number(n, p);
    if (!v) return std::nullopt;
    J = *v * Mat3::Identity();
  } else if (n.IsSequence() && n.size() == 3 && n[0].IsScalar()) {
    auto v = vec3(n, p);
    if (!v) return std::nullopt;
    J = v->asDiagonal();
  } else if (n.IsSequence() && n.size() == 3) {
    for (int r = 0; r < 3; ++r) {
      auto row = n[r].IsSequence() ? vec3(n[r], item(p, static_cast<size_t>(r))) : std::nullopt;
      if (!row) {
        if (!n[r].IsSequence()) error(n, p, expected);
        return std::nullopt;
      }
      J.row(r) = row->transpose();
    }
    if ((J - J.transpose()).norm() > 1e-9 * J.norm()) {
      error(n, p, "the inertia tensor is not symmetric");
      return std::nullopt;
    }
    J = 0.5 * (J + J.transpose());
  } else {
    error(n, p, expected);
    return std::nullopt;
  }
  const Vec3 l = Eigen::SelfAdjointEigenSolver<Mat3>(J, Eigen::EigenvaluesOnly).eigenvalues();
  if (!(l[0] > 0)) {
    error(n, p,
          fmt::format("the inertia must be positive (principal values {:.6g}, {:.6g}, {:.6g})",
                      l[0], l[1], l[2]));
    return std::nullopt;
  }
  if (l[2] > (l[0] + l[1]) * (1 + 1e-9)) {
    error(n, p,
          fmt::format("no body has these principal moments ({:.6g}, {:.6g}, {:.6g}): the largest "
                      "exceeds the sum of the other two",
                      l[0], l[1], l[2]));
    return std::nullopt;
  }
  return J;
}

void Reader::parse_rigid_bodies(const Node& bs) {
  if (!bs.IsSequence()) {
    error(bs, "rigid_bodies", "expected a list of {name, shape: plane | sphere | cylinder, ...}");
    return;
  }
  struct Read {
    std::string name;
    Node at;
    std::string path;
  };
  std::vector<Read> read;
  for (size_t i = 0; i < bs.size(); ++i) {
    const Node b = bs[i];
    const std::string p = item("rigid_bodies", i);
    if (!check_map(b, p,
                   {"name", "shape", "point", "normal", "center", "axis", "radius", "motion",
                    "mass", "velocity", "inertia", "file", "angular_velocity", "center_of_mass"}))
      continue;
    RigidBody body;
    bool ok = true;
    auto name = text(b, "name", p, true);
    auto shape = text(b, "shape", p, true);
    if (!name || !shape) continue;
    body.name = *name;
    if (rigid_bodies_.count(*name)) {
      error(b["name"], sub(p, "name"), fmt::format("duplicate rigid body '{}'", *name));
      continue;
    }
    auto unit = [&](const char* key) -> std::optional<Vec3> {
      auto v = vec3(b, key, p, true);
      if (v && v->norm() == 0) {
        error(b[key], sub(p, key), "expected a non-zero vector");
        return std::nullopt;
      }
      if (v) v->normalize();
      return v;
    };
    if (*shape == "plane") {
      body.shape = RigidBody::Shape::kPlane;
      auto pt = vec3(b, "point", p, true);
      auto n = unit("normal");
      ok = pt && n;
      if (ok) body.point = *pt, body.direction = *n;
    } else if (*shape == "sphere") {
      body.shape = RigidBody::Shape::kSphere;
      auto c = vec3(b, "center", p, true);
      auto r = positive(b, "radius", p, true, "the radius");
      ok = c && r;
      if (ok) body.point = *c, body.radius = *r;
    } else if (*shape == "cylinder") {
      body.shape = RigidBody::Shape::kCylinder;
      auto pt = vec3(b, "point", p, true);
      auto a = unit("axis");
      auto r = positive(b, "radius", p, true, "the radius");
      ok = pt && a && r;
      if (ok) body.point = *pt, body.direction = *a, body.radius = *r;
    } else if (*shape == "mesh") {
      body.shape = RigidBody::Shape::kMesh;
      ok = read_rigid_mesh(b, p, body);
    } else {
      error(b["shape"], sub(p, "shape"),
            fmt::format("unknown shape '{}'{}", *shape,
                        suggestion(*shape, {"plane", "sphere", "cylinder", "mesh"})));
      continue;
    }
    std::optional<double> mass;
    if (ok && body.shape == RigidBody::Shape::kSphere) body.reach = body.radius;
    Vec3 centre = body.point;  // of mass: the free body's node
    if (has(b, "center_of_mass")) {
      auto c = vec3(b, "center_of_mass", p, true);
      if (!has(b, "mass")) {
        error(b["center_of_mass"], sub(p, "center_of_mass"),
              "a centre of mass needs a 'mass' (a free body)");
        ok = false;
      } else if (c) {
        centre = *c;
        body.reach += (centre - body.point).norm();
      } else {
        ok = false;
      }
    }
    if (has(b, "inertia")) {
      if (!has(b, "mass")) {
        error(b["inertia"], sub(p, "inertia"), "an inertia needs a 'mass' (a free body)");
        ok = false;
      } else if (ok && body.shape != RigidBody::Shape::kSphere &&
                 body.shape != RigidBody::Shape::kMesh) {
        error(b["inertia"], sub(p, "inertia"),
              "only a sphere or a mesh turns: a plane or a cylinder is unbounded");
        ok = false;
      } else if (auto J = read_inertia(b["inertia"], sub(p, "inertia"))) {
        body.inertia = *J;
      } else {
        ok = false;
      }
    }
    if (has(b, "angular_velocity")) {
      auto w = vec3(b, "angular_velocity", p, true);
      if (!has(b, "inertia")) {
        error(b["angular_velocity"], sub(p, "angular_velocity"),
              "an initial angular velocity needs an 'inertia' (a body that rotates)");
        ok = false;
      } else if (w) {
        body.angular_velocity = *w;
      } else {
        ok = false;
      }
    }
    if (has(b, "mass")) {
      mass = positive(b, "mass", p, true, "the mass");
      ok = ok && mass.has_value();
      if (has(b, "motion")) {
        error(b["motion"], sub(p, "motion"), "a body is free (mass) or moved (motion), not both");
        ok = false;
      }
    } else if (has(b, "velocity")) {
      error(b["velocity"], sub(p, "velocity"),
            "a free rigid body needs a 'mass' (an initial velocity without one moves nothing)");
      ok = false;
    }
    std::optional<Vec3> velocity;
    if (has(b, "velocity")) {
      velocity = vec3(b, "velocity", p, true);
      ok = ok && velocity.has_value();
    }
    if (has(b, "motion")) {
      const Node m = b["motion"];
      const std::string mp = sub(p, "motion");
      if (check_map(m, mp, {"displacement", "function", "rotation", "point"})) {
        if (auto d = vec3(m, "displacement", mp, false)) body.displacement = *d;
        if (auto r = vec3(m, "rotation", mp, false)) body.rotation = *r;
        body.pivot = body.point;
        if (auto c = vec3(m, "point", mp, false)) body.pivot = *c;
        body.function = function_ref(m, mp);
      } else {
        ok = false;
      }
    }
    if (!ok) continue;
    rigid_bodies_.emplace(*name, body);
    read.push_back({*name, b["name"], sub(p, "name")});
    if (mass && mesh_ok_) {
      // A free body is a node of its own at its point, with its mass: its displacement is the
      // body's translation, moved by the contact forces, gravity and its initial velocity.
      long id = 0;
      for (long i : in_.model.node_ids) id = std::max(id, i);
      const int node = in_.model.add_node(id + 1, centre);
      in_.model.masses.push_back({node, *mass});
      if (velocity) in_.model.initial_velocities.push_back({{node}, *velocity});
      free_bodies_[*name] = {node, b["mass"], sub(p, "mass")};
    }
  }
  // A body wholly inside another at the start: no sheet can reach it (a misplaced body).
  for (const Read& inner : read)
    for (const Read& outer : read)
      if (inner.name != outer.name &&
          rigid_bodies_.at(inner.name).lies_inside(rigid_bodies_.at(outer.name))) {
        error(inner.at, inner.path,
              fmt::format("rigid body '{}' lies inside rigid body '{}' at the start: no sheet "
                          "can reach it (move it out of '{}')",
                          inner.name, outer.name, outer.name));
        break;
      }
}

bool Reader::read_rigid_mesh(const Node& b, const std::string& p, RigidBody& body) {
  auto f = text(b, "file", p, true);
  if (!f) return false;
  std::filesystem::path path = *f;
  if (path.is_relative()) path = base_dir_ / path;
  try {
    const MeshData m = read_gmsh(path);
    std::map<long, int> index;
    std::vector<Vec3> vertices;
    for (const MeshNode& n : m.nodes) index.emplace(n.id, static_cast<int>(index.size()));
    vertices.reserve(m.nodes.size());
    for (const MeshNode& n : m.nodes) vertices.push_back(n.x);
    std::vector<std::array<int, 3>> triangles;
    std::vector<bool> used(vertices.size(), false);
    for (const ElementGroup& g : m.groups) {
      const bool tri = g.type == "tri3" || g.type == "tri6";
      const bool quad = g.type == "quad4" || g.type == "quad8" || g.type == "quad9";
      if (!tri && !quad) continue;  // lines and points: not a surface
      const size_t per = g.node_ids.size() / std::max<size_t>(1, g.ids.size());
      for (size_t e = 0; e < g.ids.size(); ++e) {
        std::array<int, 4> c{};
        for (size_t k = 0; k < (tri ? 3u : 4u); ++k) {
          const auto it = index.find(g.node_ids[e * per + k]);
          if (it == index.end())
            throw MeshFileError(
                fmt::format("{}: element {} names node {}, which the file does not define",
                            path.string(), g.ids[e], g.node_ids[e * per + k]));
          c[k] = it->second;
          used[static_cast<size_t>(it->second)] = true;
        }
        triangles.push_back({c[0], c[1], c[2]});
        if (quad) triangles.push_back({c[0], c[2], c[3]});
      }
    }
    if (triangles.empty()) {
      error(
          b["file"], sub(p, "file"),
          fmt::format("{} holds no triangles or quads: a rigid mesh is a surface", path.string()));
      return false;
    }
    // The body's point: `point`, else the centroid of the surface's vertices.
    Vec3 sum = Vec3::Zero();
    int count = 0;
    for (size_t v = 0; v < vertices.size(); ++v)
      if (used[v]) sum += vertices[v], ++count;
    body.point = sum / count;
    if (has(b, "point")) {
      auto pt = vec3(b, "point", p, true);
      if (!pt) return false;
      body.point = *pt;
    }
    for (size_t v = 0; v < vertices.size(); ++v)
      if (used[v]) body.reach = std::max(body.reach, (vertices[v] - body.point).norm());
    body.mesh = make_rigid_mesh(std::move(vertices), std::move(triangles));
    return true;
  } catch (const MeshFileError& e) {
    error(b["file"], sub(p, "file"), e.what());
  } catch (const std::invalid_argument& e) {
    error(b["file"], sub(p, "file"), fmt::format("{}: {}", path.string(), e.what()));
  }
  return false;
}

void Reader::parse_contact(const Node& cs) {
  if (!cs.IsSequence()) {
    error(cs, "contact", "expected a list of {surfaces: [set, body], friction, ...}");
    return;
  }
  contact_count_ = static_cast<int>(cs.size());
  for (size_t i = 0; i < cs.size(); ++i) {
    const Node c = cs[i];
    const std::string p = item("contact", i);
    if (!check_map(c, p,
                   {"surfaces", "self", "friction", "thickness", "penalty_scale", "augmented",
                    "relax_steps", "edges", "damping"}))
      continue;
    ContactLoad load;
    load.index = static_cast<int>(i);
    bool ok = true;
    if (!require(c, "surfaces", p)) continue;
    const Node s = c["surfaces"];
    const std::string sp = sub(p, "surfaces");
    if (!s.IsSequence() || s.size() < 1 || s.size() > 2 || !s[0].IsScalar() ||
        (s.size() == 2 && !s[1].IsScalar())) {
      error(s, sp, "expected [element set, rigid body], [element set, element set] or [set]");
      continue;
    }
    const auto self = boolean(c, "self", p);
    load.self = self && *self;
    if (load.self != (s.size() == 1)) {
      error(s, sp,
            load.self ? "self contact takes one element set: surfaces: [set], self: true"
                      : "one element set in contact with itself needs self: true; else give "
                        "[element set, rigid body] or [element set, element set]");
      continue;
    }
    // An element set's parts; a set without membranes has no faces to touch.
    auto parts_of = [&](const Node& at, const std::string& name, bool faces,
                        std::vector<ContactLoad::Part>& to) {
      if (!element_sets_.count(name)) {
        if (mesh_ok_)
          error(at, sp,
                fmt::format("undefined element set '{}'{}", name,
                            suggestion(name, keys_of(element_sets_))));
        return false;
      }
      bool surface = false;
      for (int b : set_blocks_[name]) {
        surface = surface || in_.model.blocks[b]->surface() != nullptr;
        ContactLoad::Part part{b,
                               std::vector<int>(static_cast<size_t>(in_.model.blocks[b]->size()))};
        for (size_t e = 0; e < part.elements.size(); ++e) part.elements[e] = static_cast<int>(e);
        to.push_back(std::move(part));
      }
      if (faces && !surface) {
        error(at, sp,
              fmt::format("element set '{}' has no membranes: contact between sets (or self "
                          "contact) needs surfaces",
                          name));
        return false;
      }
      return true;
    };
    const std::string set = s[0].as<std::string>();
    const std::string body = s.size() == 2 ? s[1].as<std::string>() : std::string();
    const bool sheets = load.self || (!rigid_bodies_.count(body) && element_sets_.count(body));
    ok = parts_of(s[0], set, sheets, load.parts);
    if (sheets) {
      if (!load.self) ok = parts_of(s[1], body, true, load.other) && ok;
    } else if (auto bit = rigid_bodies_.find(body); bit == rigid_bodies_.end()) {
      error(s[1], sp,
            fmt::format("undefined rigid body '{}'{}", body,
                        suggestion(body, keys_of(rigid_bodies_))));
      ok = false;
    } else {
      load.body = bit->second;
      contact_bodies_.insert(body);
      if (auto f = free_bodies_.find(body); f != free_bodies_.end())
        load.body_node = f->second.node;
    }
    if (has(c, "edges")) {
      if (!sheets && load.body.shape != RigidBody::Shape::kMesh) {
        error(c["edges"], sub(p, "edges"),
              "edges applies to contact between element sets (or self contact) and with a rigid "
              "mesh");
        ok = false;
      } else if (auto e = boolean(c, "edges", p)) {
        load.edges = *e;
      } else {
        ok = false;
      }
    }
    if (has(c, "relax_steps")) {
      if (auto n = integer(c["relax_steps"], sub(p, "relax_steps"), "a number of steps");
          n && *n >= 0) {
        load.relax_steps = static_cast<int>(*n);
      } else {
        if (n) error(c["relax_steps"], sub(p, "relax_steps"), "expected a number of steps >= 0");
        ok = false;
      }
    }
    if (has(c, "friction")) {
      if (auto mu = non_negative(c, "friction", p, "the friction coefficient"))
        load.friction = *mu;
      else
        ok = false;
    }
    if (has(c, "thickness")) {
      if (auto t = non_negative(c, "thickness", p, "the contact thickness"))
        load.thickness = *t;
      else
        ok = false;
    }
    if (has(c, "penalty_scale")) {
      if (auto k = positive(c, "penalty_scale", p, true, "the penalty scale"))
        load.penalty_scale = *k;
      else
        ok = false;
    }
    if (has(c, "damping")) {
      const auto z = non_negative(c, "damping", p, "the fraction of critical damping");
      if (sheets) {
        error(c["damping"], sub(p, "damping"),
              "damping applies to contact with a rigid body (not yet between element sets)");
        ok = false;
      } else if (z && *z > 1) {
        error(c["damping"], sub(p, "damping"),
              fmt::format("expected a fraction of critical damping from 0 to 1, got {}", *z));
        ok = false;
      } else if (z) {
        load.damping = *z;
      } else {
        ok = false;
      }
    }
    if (auto a = boolean(c, "augmented", p))
      load.augmented = *a, contact_augmented_.insert(load.index);
    if (ok) add_load(make_load(std::move(load)), c, p);
  }
}

void Reader::check_free_bodies() {
  if (in_.analysis.equilibrium())
    for (const auto& [name, f] : free_bodies_)
      error(f.at, f.path,
            fmt::format("rigid body '{}' is free (mass): it needs a dynamic analysis (in a "
                        "static one nothing holds it)",
                        name));
}

bool Reader::parse_contact_history(const Node& e, const std::string& p, HistoryEntry& he) {
  using Q = HistoryEntry::Quantity;
  const bool area = he.quantity == Q::kContactArea;  // one value: no component
  const bool turn = he.quantity == Q::kRigidRotation || he.quantity == Q::kRigidAngularVelocity;
  const char* what = he.quantity == Q::kContactForce           ? "contact_force"
                     : area                                    ? "contact_area"
                     : he.quantity == Q::kRigidPosition        ? "rigid_position"
                     : he.quantity == Q::kRigidRotation        ? "rigid_rotation"
                     : he.quantity == Q::kRigidAngularVelocity ? "rigid_angular_velocity"
                                                               : "rigid_velocity";
  auto c = area ? std::optional<std::string>("magnitude") : text(e, "component", p, true);
  if (!c) return false;
  const std::vector<std::string> components = {"x", "y", "z", "magnitude"};
  const auto ci = std::find(components.begin(), components.end(), *c) - components.begin();
  if (ci == static_cast<long>(components.size())) {
    error(e["component"], sub(p, "component"),
          fmt::format("unknown component '{}'{}", *c, suggestion(*c, components)));
    return false;
  }
  if (area && has(e, "component")) {
    error(e["component"], sub(p, "component"), "contact_area has no component");
    return false;
  }
  const auto name = [&](const std::string& which) {
    return area ? fmt::format("{}:{}", what, which) : fmt::format("{}:{}:{}", what, which, ci);
  };
  if ((he.quantity == Q::kContactForce || area) && has(e, "contact")) {
    auto k = integer(e["contact"], sub(p, "contact"), "a contact index");
    if (!k) return false;
    if (*k < 0 || *k >= contact_count_) {
      error(e["contact"], sub(p, "contact"),
            fmt::format("no contact {} (the model has {}, counted from 0)", *k, contact_count_));
      return false;
    }
    he.flow = name(fmt::format("contact={}", *k));
    return true;
  }
  auto body = text(e, "body", p, true);
  if (!body) return false;
  if (!rigid_bodies_.count(*body)) {
    error(e["body"], sub(p, "body"),
          fmt::format("undefined rigid body '{}'{}", *body,
                      suggestion(*body, keys_of(rigid_bodies_))));
    return false;
  }
  if (!contact_bodies_.count(*body)) {
    error(e["body"], sub(p, "body"), fmt::format("rigid body '{}' is in no contact entry", *body));
    return false;
  }
  if (auto f = free_bodies_.find(*body);
      f != free_bodies_.end() && he.quantity != Q::kContactForce && !area && !turn) {
    // A free body's motion is its node's.
    if (ci == 3) {
      error(e["component"], sub(p, "component"),
            "a free body's position and velocity have components x, y and z");
      return false;
    }
    he.quantity = he.quantity == Q::kRigidPosition ? Q::kPosition : Q::kVelocity;
    he.node = f->second.node, he.component = static_cast<int>(ci);
    return true;
  }
  he.flow = he.quantity == Q::kContactForce || area ? name(fmt::format("body={}", *body))
                                                    : fmt::format("{}:{}:{}", what, *body, ci);
  return true;
}

}  // namespace velum::io::model_file
