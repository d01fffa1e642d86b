// Node-to-rigid-surface contact (docs/contact.md): every node of the set against the body, the
// law of contact_law.hpp at each, the 3 x 3 block of its derivative into the node's diagonal
// block of K; the multipliers and friction anchors move on at accepted steps only. A free body
// that rotates has one rotation, shared by the contact entries it takes part in (Spin).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>

#include "contact_law.hpp"
#include "rigid_rotation.hpp"
#include "sheet_contact.hpp"
#include "velum/assembly/assembler.hpp"
#include "velum/load/contact_load.hpp"
#include "velum/model/model.hpp"
#include "velum/parallel/processes.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum {
namespace {

class Contact final : public Load, public ContactLoad {
 public:
  explicit Contact(ContactLoad p) : ContactLoad(std::move(p)) {}
  std::string_view kind() const override { return "contact"; }
  LoadOrder order() const override { return LoadOrder::kContact; }
  std::string_view counted_as() const override { return {}; }
  std::unique_ptr<Load> clone() const override { return std::make_unique<Contact>(*this); }
  std::unique_ptr<Load> held(double t, const Model& owner, Model&) const override {
    // A later step goes on with the body where it is at t.
    auto h = std::make_unique<Contact>(*this);
    const double s = owner.function_value(body.function, t);
    h->body.displacement = s * body.displacement;
    h->body.rotation = s * body.rotation;
    h->body.function = -1;
    return h;
  }
  void set_up(const Model& model, const ElementNamer&) override;
  bool keep_piece(const Model&, const std::vector<std::vector<int>>&,
                  const std::vector<int>& local_of) override {
    if (body_node >= 0)
      throw std::invalid_argument(fmt::format(
          "contact {}: a free rigid body ({}) runs on one process only", index, body.name));
    std::vector<int> kept;
    std::vector<double> t, h;
    for (size_t i = 0; i < nodes.size(); ++i)
      if (const int l = local_of[static_cast<size_t>(nodes[i])]; l >= 0) {
        kept.push_back(l);
        t.push_back(node_thickness[i]);
        h.push_back(node_size[i]);
      }
    nodes = std::move(kept), node_thickness = std::move(t), node_size = std::move(h);
    parts.clear();  // the areas of the contact pressure come from the whole set only
    return !nodes.empty();
  }
  std::string summary(int) const override {
    return fmt::format("contact {}: {} nodes against {}{}", index, nodes.size(), body.name,
                       friction > 0 ? fmt::format(", friction {}", friction) : "");
  }
  std::unique_ptr<LoadTerm> bind(const LoadSite& site) const override;

  std::vector<double> node_thickness;  // contact thickness per node
  std::vector<double> node_size;       // element size about the node (penetration tolerance)
};

void Contact::set_up(const Model& model, const ElementNamer&) {
  const int N = model.num_nodes();
  std::vector<double> t(static_cast<size_t>(N), -1.0), h(static_cast<size_t>(N), 0.0);
  for (const Part& part : parts) {
    const ElementBlock& b = *model.blocks[static_cast<size_t>(part.block)];
    for (int e : part.elements) {
      if (!b.holds(e)) continue;
      const double half = b.surface() ? 0.5 * b.output(e, model.X).thickness : 0.0;
      const double size = b.surface() ? std::sqrt(b.measure(e)) : b.measure(e);
      for (int n : b.nodes(e)) {
        t[static_cast<size_t>(n)] = std::max(t[static_cast<size_t>(n)], half);
        h[static_cast<size_t>(n)] = std::max(h[static_cast<size_t>(n)], size);
      }
    }
  }
  nodes.clear(), node_thickness.clear(), node_size.clear();
  for (int n = 0; n < N; ++n)
    if (t[static_cast<size_t>(n)] >= 0) {
      nodes.push_back(n);
      node_thickness.push_back(thickness >= 0 ? thickness : t[static_cast<size_t>(n)]);
      node_size.push_back(h[static_cast<size_t>(n)]);
    }
}

class ContactTerm final : public LoadTerm {
 public:
  ContactTerm(const Contact& load, const LoadSite& site);
  // The entries of the same rotating body share the first one's rotation.
  void connect(std::span<LoadTerm* const> all, int self) override {
    if (!spin_) return;
    for (int i = 0; i < self; ++i)
      if (auto* c = dynamic_cast<ContactTerm*>(all[static_cast<size_t>(i)]);
          c && c->spin_ && c->owner_ && c->load_.body_node == load_.body_node) {
        spin_ = c->spin_;
        ++spin_->entries;
        owner_ = false;
        return;
      }
  }

  void add(const LoadState& s, LoadOutput& out) override {
    const double sf = site_.model.function_value(load_.body.function, s.t);
    const bool share = site_.assembler.local_share();
    const int b = load_.body_node;
    const Frame fr = frame(s.t, s.x);
    // A free body: its node takes the opposite forces; its coupling with the contact nodes
    // (outside the mesh's pattern) is the low-rank part U Wᵀ = Σ P_i D_i P_bᵀ + P_b D_i P_iᵀ.
    MatX* U = b >= 0 && out.K && out.low_rank ? &out.low_rank->U : nullptr;
    MatX* W = U ? &out.low_rank->W : nullptr;
    if (U)
      for (int c = 0; c < 6; ++c)
        U->col(out.column + c).setZero(), W->col(out.column + c).setZero();
    for (size_t i = 0; i < load_.nodes.size(); ++i) {
      const int n = load_.nodes[i];
      if (share && !site_.assembler.keeps_node(n)) continue;
      contact::NodeResult r = evaluate(i, to_body(fr, s.x.col(n)), sf, out.K != nullptr);
      if (r.status == contact::Status::kOpen) continue;
      if (fr.turned) {  // the law in the body's axes: back to the global ones
        r.f = fr.R * r.f;
        r.D = fr.R * r.D * fr.R.transpose();
      }
      out.F.col(n) += r.f;
      if (out.K) add_block(n, r.D, *out.K);
      if (b < 0) continue;
      out.F.col(b) -= r.f;
      if (out.K) add_block(b, r.D, *out.K);  // f_b = −f(x_n − x_b): ∂f_b/∂x_b = D
      if (U)
        for (int c = 0; c < 3; ++c) {
          put(n, r.D.col(c), U->col(out.column + c));
          put(n, r.D.row(c).transpose(), W->col(out.column + 3 + c));
        }
    }
    if (U)
      for (int c = 0; c < 3; ++c) {
        put(b, Vec3::Unit(c), W->col(out.column + c));
        put(b, Vec3::Unit(c), U->col(out.column + 3 + c));
      }
  }
  int low_rank_columns() const override { return load_.body_node >= 0 ? 6 : 0; }
  // A rotating free body: the rotation's kinetic energy and the contact moment's work on it.
  double kinetic_energy() const override { return owner_ ? spin_->rot.kinetic_energy() : 0.0; }
  double state_work() const override { return owner_ ? spin_->rot.last_work() : 0.0; }

  void start(const LoadState& s) override {
    if (owner_) spin_->rot.start(s.t, Vec3::Zero());  // the orientation at s.t: the committed one
    move_on(s, false, true);
  }
  void commit(const LoadState& s) override { move_on(s, load_.augmented, false); }
  void save_state(std::vector<double>& out) const override {
    out.push_back(static_cast<double>(lambda_.size()));
    for (size_t i = 0; i < lambda_.size(); ++i) {
      out.push_back(lambda_[i]);
      out.insert(out.end(), anchor_[i].data(), anchor_[i].data() + 3);
    }
    if (owner_) spin_->rot.save(out);
  }
  size_t restore_state(const std::vector<double>& in, size_t at) override {
    const size_t rotation = owner_ ? rigid::Rotation::kSaved : 0;
    if (at >= in.size() || in[at] != static_cast<double>(lambda_.size()) ||
        in.size() < at + 1 + 4 * lambda_.size() + rotation)
      throw std::invalid_argument("the contact's saved state does not fit its nodes");
    ++at;
    for (size_t i = 0; i < lambda_.size(); ++i, at += 4) {
      lambda_[i] = in[at];
      anchor_[i] = Vec3(in[at + 1], in[at + 2], in[at + 3]);
    }
    if (owner_) at = spin_->rot.restore(in, at);
    return at;
  }

  std::optional<double> quantity(std::string_view name) const override {
    if (name.starts_with("contact_force") || name.starts_with("contact_area") ||
        name.starts_with("rigid_"))
      return 0.0;
    return {};
  }
  std::optional<double> quantity_at(std::string_view name, double t,
                                    const NodePositions& x) const override;
  bool node_field(std::string_view name, double t, const NodePositions& x,
                  std::vector<double>& per_node) const override;
  double max_stiffness_over_mass(std::span<const double> node_mass) const override {
    double most = 0;
    for (size_t i = 0; i < load_.nodes.size(); ++i)
      if (const double m = node_mass[static_cast<size_t>(load_.nodes[i])]; m > 0)
        most = std::max(most, k_[i] * (1 + load_.friction) / m);
    // A rotating body: a node's penalty at the body's reach turns it (k r² over its least
    // principal inertia).
    if (spin_)
      for (size_t i = 0; i < load_.nodes.size(); ++i) {
        const double r = load_.body.reach + load_.node_thickness[i];
        most = std::max(most, k_[i] * (1 + load_.friction) * r * r / spin_->rot.least_inertia());
      }
    return most;
  }
  // Contact not kept: past its tolerance a warning; past the contact thickness the sheet is
  // through the body.
  std::string end_check(const std::function<void(std::string)>& warn) const override {
    if (owner_ && spin_->step_ratio > 1)
      warn(fmt::format(
          "contact {}: the rotation of '{}' is advanced explicitly and a step was {:.3g} times "
          "its stable length for the contact's stiffness (take shorter steps)",
          load_.index, load_.body.name, spin_->step_ratio));
    return contact::penetration_check(
        processes::max(penetration_ratio_),
        fmt::format("contact {} with '{}'", load_.index, load_.body.name),
        "inside the body, through the contact thickness", warn);
  }
  std::string account_json() const override {
    return fmt::format(
        "{{\"contact\": {}, \"body\": \"{}\", \"penalty\": [{:.6g}, {:.6g}], "
        "\"max_penetration_ratio\": {:.6g}, \"kept\": {}}}",
        load_.index, load_.body.name, k_min_, k_max_, penetration_ratio_,
        penetration_ratio_ <= 1 ? "true" : "false");
  }

 private:
  contact::NodeResult evaluate(size_t i, const Vec3& x, double sf, bool tangent) const {
    contact::NodeInput in;
    in.g = load_.body.gap(x, sf, in.n, in.H) - load_.node_thickness[i];
    in.w = x - load_.body.moved(anchor_[i], sf);
    in.lambda = lambda_[i];
    in.k = k_[i];
    in.mu = load_.friction;
    return contact::node_force(in, tangent);
  }
  // K −= ∂f/∂x in the node's equations (its frame where it has one).
  void add_block(int n, const Mat3& D, SparseMatrix& K) const {
    const int f = site_.dofs.frame(n);
    const Mat3 A =
        f < 0 ? Mat3(-D) : Mat3(-site_.dofs.rotation(f) * D * site_.dofs.rotation(f).transpose());
    for (int j = 0; j < 3; ++j) {
      const int cj = site_.dofs.equation(n, j);
      if (cj < 0) continue;
      for (int i = 0; i < 3; ++i)
        if (const int ri = site_.dofs.equation(n, i); ri >= 0 && A(i, j) != 0)
          K.coeffRef(ri, cj) += A(i, j);
    }
  }
  void move_on(const LoadState& s, bool update_multipliers, bool starting);
  // A free body's translation at positions x (0 for a fixed or moved one).
  Vec3 translation(const NodePositions& x) const {
    const int b = load_.body_node;
    return b >= 0 ? Vec3(x.col(b) - site_.model.X.col(b)) : Vec3::Zero();
  }
  // Where a free body is at (t, x): its translation d, and when it rotates its orientation R,
  // its centre c now and C0 at the start. The contact law is evaluated in the body's axes
  // at t = 0 (to_body), where its surfaces are given.
  struct Frame {
    bool turned = false;
    Vec3 d = Vec3::Zero(), c = Vec3::Zero(), C0 = Vec3::Zero();
    Mat3 R = Mat3::Identity();
  };
  Frame frame(double t, const NodePositions& x) const {
    Frame f;
    f.d = translation(x);
    if (spin_) {
      const int b = load_.body_node;
      f.turned = true;
      f.R = spin_->rot.orientation(t);
      f.c = x.col(b);
      f.C0 = site_.model.X.col(b);
    }
    return f;
  }
  static Vec3 to_body(const Frame& f, const Vec3& x) {
    return f.turned ? Vec3(f.C0 + f.R.transpose() * (x - f.c)) : Vec3(x - f.d);
  }
  // Adds the global vector v at node n into the equation vector `to` (in n's frame).
  template <class Column>
  void put(int n, const Vec3& v, Column&& to) const {
    const Vec3 l = site_.dofs.to_local(n, v);
    for (int c = 0; c < 3; ++c)
      if (const int eq = site_.dofs.equation(n, c); eq >= 0) to[eq] += l[c];
  }
  // The outputs (history, fields) at the state accepted last: its forces as the residual
  // had them (before the multipliers moved on).
  Vec3 accepted_force(size_t i) const { return f_accepted_[i]; }
  // The area about each node of the set (per model node) at positions x.
  std::vector<double> node_areas(const NodePositions& x) const;

  const Contact& load_;
  LoadSite site_;
  std::vector<double> k_, lambda_;
  std::vector<Vec3> anchor_;      // friction: the body's point (at s = 0) each node sticks to
  std::vector<Vec3> f_accepted_;  // the force on each node at the state accepted last
  std::vector<contact::Status> status_accepted_;  // and its status there
  double k_min_ = 0, k_max_ = 0;
  double penetration_ratio_ = 0;  // the largest penetration / tolerance at the last accepted step
  std::shared_ptr<rigid::Spin> spin_;  // a free body that rotates: its rotation (shared)
  bool owner_ = false;                 // the first of the body's entries: it saves the rotation
};

ContactTerm::ContactTerm(const Contact& load, const LoadSite& site) : load_(load), site_(site) {
  // The automatic penalty: the largest diagonal entry of the node's block of the reference
  // tangent (the sheet's in-plane stiffness, E t for a membrane), times penalty_scale.
  SparseMatrix K;
  site.assembler.make_matrix(K);
  NodePositions F;
  site.assembler.internal(site.model.X, F, &K);
  const size_t N = load.nodes.size();
  k_.assign(N, 0.0);
  double sum = 0;
  int count = 0;
  for (size_t i = 0; i < N; ++i) {
    for (int c = 0; c < 3; ++c)
      if (const int eq = site.dofs.equation(load.nodes[i], c); eq >= 0)
        k_[i] = std::max(k_[i], K.coeff(eq, eq));
    if (k_[i] > 0) sum += k_[i], ++count;
  }
  const double mean = count ? sum / count : 0.0;
  if (N && mean <= 0)
    throw std::invalid_argument(
        fmt::format("contact {}: the set has no stiffness at its reference to scale the penalty on",
                    load.index));
  for (double& k : k_) k = load.penalty_scale * (k > 0 ? k : mean);
  if (N) {
    k_min_ = *std::min_element(k_.begin(), k_.end());
    k_max_ = *std::max_element(k_.begin(), k_.end());
  }
  lambda_.assign(N, 0.0);
  anchor_.resize(N);
  f_accepted_.assign(N, Vec3::Zero());
  status_accepted_.assign(N, contact::Status::kOpen);
  for (size_t i = 0; i < N; ++i) anchor_[i] = site.model.X.col(load.nodes[i]);
  if (load.body_node >= 0 && load.body.inertia != Mat3::Zero())
    spin_ = std::make_shared<rigid::Spin>(load.body.inertia, load.body.angular_velocity),
    owner_ = true;
}

void ContactTerm::move_on(const LoadState& s, bool update_multipliers, bool starting) {
  const double sf = site_.model.function_value(load_.body.function, s.t);
  penetration_ratio_ = 0;
  const Frame fr = frame(s.t, s.x);
  Vec3 moment = Vec3::Zero();  // of the forces on a rotating body, about its centre
  double turning = 0;          // Σ k r²: the contact's stiffness against its rotation
  for (size_t i = 0; i < load_.nodes.size(); ++i) {
    const Vec3 x = to_body(fr, s.x.col(load_.nodes[i]));  // relative to a free body
    const contact::NodeResult r = evaluate(i, x, sf, false);
    f_accepted_[i] = fr.turned ? Vec3(fr.R * r.f) : r.f;
    status_accepted_[i] = r.status;
    if (fr.turned && r.status != contact::Status::kOpen) {
      const Vec3 arm = s.x.col(load_.nodes[i]) - fr.c;
      moment -= arm.cross(f_accepted_[i]);
      turning += k_[i] * (1 + load_.friction) * arm.squaredNorm();
    }
    if (r.status == contact::Status::kOpen) {
      if (update_multipliers) lambda_[i] = 0;
      anchor_[i] = load_.body.unmoved(x, sf);
      continue;
    }
    Vec3 n;
    Mat3 H;
    const double g = load_.body.gap(x, sf, n, H) - load_.node_thickness[i];
    const double tol = std::max(0.01 * 2 * load_.node_thickness[i], 1e-3 * load_.node_size[i]);
    if (tol > 0) penetration_ratio_ = std::max(penetration_ratio_, -g / tol);
    if (update_multipliers) lambda_[i] = r.p;
    anchor_[i] = load_.body.unmoved(x - r.slip, sf);
  }
  if (!spin_) return;
  // The body's other entries at the same state (connect): the last one moves it on.
  rigid::Spin& sp = *spin_;
  sp.moment += moment, sp.turning += turning;
  if (++sp.added < sp.entries) return;
  if (starting) {
    sp.rot.start(s.t, sp.moment);
  } else {
    const double tau = s.t - sp.rot.time();
    sp.step_ratio =
        std::max(sp.step_ratio, 0.5 * tau * std::sqrt(sp.turning / sp.rot.least_inertia()));
    sp.rot.commit(s.t, fr.R, sp.moment);
  }
  sp.moment.setZero(), sp.turning = 0, sp.added = 0;
}

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
    const double dt = 1e-6 * std::max(1.0, std::abs(t));
    const double rate = (site_.model.function_value(load_.body.function, t + dt) -
                         site_.model.function_value(load_.body.function, t - dt)) /
                        (2 * dt);
    return pick(Vec3(rate * load_.body.rotation));
  }
  if (key == fmt::format("rigid_velocity:{}", load_.body.name)) {
    const double dt = 1e-6 * std::max(1.0, std::abs(t));
    const double s1 = site_.model.function_value(load_.body.function, t + dt);
    const double s0 = site_.model.function_value(load_.body.function, t - dt);
    return pick(Vec3((load_.body.position(s1) - load_.body.position(s0)) / (2 * dt)));
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

std::unique_ptr<LoadTerm> Contact::bind(const LoadSite& site) const {
  return std::make_unique<ContactTerm>(*this, site);
}

}  // namespace

std::unique_ptr<Load> make_load(ContactLoad p) {
  if (p.friction < 0) throw std::invalid_argument("a friction coefficient below 0");
  if (p.self || !p.other.empty()) return make_sheet_contact(std::move(p));
  return std::make_unique<Contact>(std::move(p));
}

}  // namespace velum
