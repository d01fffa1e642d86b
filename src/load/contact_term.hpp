// The node-to-rigid-surface contact's load and its term (contact_load.cpp: set-up, forces and
// state; contact_outputs.cpp: history and frame fields; docs/contact.md). Private to src/load.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <stdexcept>
#include <utility>

#include "contact_law.hpp"
#include "face_contact.hpp"
#include "face_tree.hpp"
#include "initial_penetrations.hpp"
#include "node_blocks.hpp"
#include "rigid_mesh.hpp"
#include "rigid_rotation.hpp"
#include "sheet_contact.hpp"
#include "velum/assembly/assembler.hpp"
#include "velum/load/contact_load.hpp"
#include "velum/model/model.hpp"
#include "velum/parallel/processes.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum::rigid_contact {

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
    h->relax_steps = 0;  // a later step starts from the state the first one left
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
          "contact {}: a free rigid body ({}) runs on one process only (its node takes the "
          "contact forces of the nodes of every process): run the model without mpirun, or "
          "give the body a motion instead of a mass",
          index, body.name));
    if (edges)
      throw std::invalid_argument(
          fmt::format("contact {}: edge contact with a rigid mesh ({}) runs on one process only",
                      index, body.name));
    std::vector<int> kept;
    std::vector<double> t, h, k, m;
    for (size_t i = 0; i < nodes.size(); ++i)
      if (const int l = local_of[static_cast<size_t>(nodes[i])]; l >= 0) {
        kept.push_back(l);
        t.push_back(node_thickness[i]);
        h.push_back(node_size[i]);
        k.push_back(node_stiffness[i]);
        m.push_back(node_mass[i]);
      }
    nodes = std::move(kept), node_thickness = std::move(t), node_size = std::move(h);
    node_stiffness = std::move(k), node_mass = std::move(m);
    parts.clear();  // the areas of the contact pressure come from the whole set only
    return !nodes.empty();
  }
  std::string summary(int) const override {
    return fmt::format("contact {}: {} nodes against {}{}{}", index, nodes.size(), body.name,
                       friction > 0 ? fmt::format(", friction {}", friction) : "",
                       damping > 0 ? fmt::format(", damping {} of critical", damping) : "");
  }
  std::unique_ptr<LoadTerm> bind(const LoadSite& site) const override;

  std::vector<double> node_thickness;  // contact thickness per node
  std::vector<double> node_size;       // element size about the node (penetration tolerance)
  // The node's largest diagonal entry of the elements' tangent at the reference, unconstrained
  // (reference_diagonal.hpp), summed over every element at the node: the penalty's scale.
  std::vector<double> node_stiffness;
  std::vector<double> node_mass;  // its lumped mass, point masses included (the damping's scale)
  std::vector<std::pair<int, int>> sheet_edges;  // edges: true: the membranes' sides (model nodes)
};

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
    const BodyRate rate = damping_rate(s.t);
    if (out.K) damping_blocks_.clear();
    for (size_t i = 0; i < load_.nodes.size(); ++i) {
      const int n = load_.nodes[i];
      if (share && !site_.assembler.keeps_node(n)) continue;
      const Vec3 y = to_body(fr, s.x.col(n));
      contact::NodeResult r =
          evaluate(i, y, sf, out.K != nullptr,
                   c_.empty() ? Vec3::Zero() : relative_velocity(s, fr, rate, n, y));
      if (r.status == contact::Status::kOpen) continue;
      if (fr.turned) {  // the law in the body's axes: back to the global ones
        r.f = fr.R * r.f;
        r.D = fr.R * r.D * fr.R.transpose();
        r.Dv = fr.R * r.Dv * fr.R.transpose();
      }
      if (out.K && !c_.empty()) damping_blocks_.push_back({n, r.Dv});
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
    if (!load_.sheet_edges.empty()) add_edges(s, fr, sf, out, U, W);
    if (U)
      for (int c = 0; c < 3; ++c) {
        put(b, Vec3::Unit(c), W->col(out.column + c));
        put(b, Vec3::Unit(c), U->col(out.column + 3 + c));
      }
  }
  int low_rank_columns() const override { return load_.body_node >= 0 ? 6 : 0; }
  bool uses_velocity() const override { return !c_.empty(); }
  // cv ∂(−f)/∂v at the nodes in touch of the last add() with a Jacobian, and the same block at
  // a free body's node (f_b = −f of v_n − v_b). The coupling between a node and the body is
  // left out (outside the mesh's pattern; the stiffness's goes into the low-rank part): Newton
  // still converges, at a rate of about the damping fraction.
  void add_velocity_jacobian(const NodePositions&, double cv, SparseMatrix& J) const override {
    for (const auto& [n, Dv] : damping_blocks_) {
      add_block(n, cv * Dv, J);
      if (load_.body_node >= 0) add_block(load_.body_node, cv * Dv, J);
    }
  }
  // A rotating free body: the rotation's kinetic energy and the contact moment's work on it.
  double kinetic_energy() const override { return owner_ ? spin_->rot.kinetic_energy() : 0.0; }
  double state_work() const override { return owner_ ? spin_->rot.last_work() : 0.0; }

  void start(const LoadState& s) override {
    if (owner_) spin_->rot.start(s.t, Vec3::Zero());  // the orientation at s.t: the committed one
    if (!started_) find_initial_penetrations(s);
    move_on(s, false, true);
  }
  void commit(const LoadState& s) override {
    move_on(s, load_.augmented, false);
    initial_.commit();
  }
  void save_state(std::vector<double>& out) const override {
    out.push_back(static_cast<double>(lambda_.size()));
    for (size_t i = 0; i < lambda_.size(); ++i) {
      out.push_back(lambda_[i]);
      out.insert(out.end(), anchor_[i].data(), anchor_[i].data() + 3);
    }
    if (owner_) spin_->rot.save(out);
    if (edge_friction()) save_edges(out);
    initial_.save(out);
    peak_.save(out);
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
    if (edge_friction()) at = restore_edges(in, at);
    at = initial_.restore(in, at);
    at = peak_.restore(in, at);
    started_ = true;  // the state is the saved one, not a new start's
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
    // A damped oscillator's central-difference limit is (√(1 + ζ²) − ζ) 2/ω: the penalty's ω²
    // is counted that much larger.
    const double z = load_.damping, shorter = std::sqrt(1 + z * z) - z;
    return stiffness_over_mass(node_mass) / (shorter * shorter);
  }
  // Contact not kept: past its tolerance a warning; past the contact thickness the sheet is
  // through the body.
  std::string end_check(const std::function<void(std::string)>& warn) const override {
    initial_.warn(fmt::format("contact {} with '{}'", load_.index, load_.body.name),
                  load_.relax_steps, warn);
    if (owner_ && spin_->step_ratio > 1)
      warn(fmt::format(
          "contact {}: the rotation of '{}' is advanced explicitly and a step was {:.3g} times "
          "its stable length for the contact's stiffness (take shorter steps)",
          load_.index, load_.body.name, spin_->step_ratio));
    const double peak = processes::max(peak_.ratio);
    return contact::penetration_check(
        processes::max(penetration_ratio_), {peak, peak_.ratio == peak ? peak_.time : NAN},
        fmt::format("contact {} with '{}'", load_.index, load_.body.name),
        "inside the body, through the contact thickness", warn);
  }
  std::string account_json() const override {
    // Over every process's nodes (under mpirun each process's writer asks at the same
    // outputs, ResultsWriter::write); the peak's time that of the process holding it.
    const double ratio = processes::max(penetration_ratio_), peak = processes::max(peak_.ratio);
    const double peak_time = processes::max(peak_.ratio == peak ? peak_.time : -INFINITY);
    return fmt::format(
        "{{\"contact\": {}, \"body\": \"{}\", \"penalty\": [{:.6g}, {:.6g}], "
        "\"max_penetration_ratio\": {:.6g}, \"kept\": {}, \"initial_penetrations\": {}, "
        "\"initial_max_depth\": {:.6g}, \"peak_penetration_ratio\": {:.6g}, "
        "\"peak_penetration_time\": {:.6g}}}",
        load_.index, load_.body.name, k_min_, k_max_, ratio, ratio <= 1 ? "true" : "false",
        initial_.count(), initial_.depth(), peak, peak_time);
  }

 private:
  // The largest penalty over its node's mass (undamped), over the nodes that move (a node held
  // in all three directions has no mode for its penalty to stiffen).
  double stiffness_over_mass(std::span<const double> node_mass) const {
    double most = 0;
    // With edges a node may also take an edge pair's penalty (at most the node's own).
    const double pairs = load_.sheet_edges.empty() ? 1.0 : 2.0;
    for (size_t i = 0; i < load_.nodes.size(); ++i)
      if (const double m = node_mass[static_cast<size_t>(load_.nodes[i])]; m > 0 && moves_[i])
        most = std::max(most, pairs * k_[i] * (1 + load_.friction) / m);
    // A rotating body: a node's penalty at the body's reach turns it (k r² over its least
    // principal inertia).
    if (spin_)
      for (size_t i = 0; i < load_.nodes.size(); ++i) {
        const double r = load_.body.reach + load_.node_thickness[i];
        most = std::max(most, k_[i] * (1 + load_.friction) * r * r / spin_->rot.least_inertia());
      }
    return most;
  }
  contact::NodeResult evaluate(size_t i, const Vec3& x, double sf, bool tangent,
                               const Vec3& v = Vec3::Zero()) const {
    contact::NodeInput in;
    in.g = load_.body.gap(x, sf, in.n, in.H) - load_.node_thickness[i] + relaxed(i);
    in.w = x - load_.body.moved(anchor_[i], sf);
    in.lambda = lambda_[i];
    in.k = k_[i];
    in.mu = load_.friction;
    if (!c_.empty()) in.c = c_[i], in.v = v;
    return contact::node_force(in, tangent);
  }
  // K −= ∂f/∂x in the node's equations (its frame where it has one).
  void add_block(int n, const Mat3& D, SparseMatrix& K) const {
    subtract_node_block(site_.dofs, n, n, D, K);
  }
  void move_on(const LoadState& s, bool update_multipliers, bool starting);
  // The nodes inside the contact distance at the start, noted in initial_.
  void find_initial_penetrations(const LoadState& s);
  double relaxed(size_t i) const { return initial_.relaxed(i, load_.relax_steps); }
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
  // A prescribed motion's function at t ± dt, for the velocity of the body's points by a
  // central difference (the damping's, and the rigid_velocity and rigid_angular_velocity
  // outputs of a moved body).
  struct BodyRate {
    double s0 = 0, s1 = 0, dt = 0;
  };
  // The rate the damping needs: a moved body's (none without damping; a free body has its
  // own velocity).
  BodyRate damping_rate(double t) const {
    return c_.empty() || load_.body_node >= 0 ? BodyRate{} : body_rate(t);
  }
  BodyRate body_rate(double t) const {
    const double dt = 1e-6 * std::max(1.0, std::abs(t));
    return {site_.model.function_value(load_.body.function, t - dt),
            site_.model.function_value(load_.body.function, t + dt), dt};
  }
  // Node n's velocity relative to the body's point at it, in the frame the law is evaluated in
  // (y: the node's position there).
  Vec3 relative_velocity(const LoadState& s, const Frame& fr, const BodyRate& rate, int n,
                         const Vec3& y) const {
    const int b = load_.body_node;
    if (b < 0) {
      const Vec3 Y = load_.body.unmoved(y, 0.5 * (rate.s0 + rate.s1));
      return Vec3(s.V.col(n)) -
             (load_.body.moved(Y, rate.s1) - load_.body.moved(Y, rate.s0)) / (2 * rate.dt);
    }
    Vec3 v = s.V.col(n) - s.V.col(b);
    if (!fr.turned) return v;
    v -= spin_->rot.angular_velocity().cross(Vec3(s.x.col(n) - fr.c));
    return fr.R.transpose() * v;
  }
  // Edge contact with a rigid mesh (contact_edges.cpp). The map from global positions to the
  // mesh's own at s = 0 (to_body, then the motion undone): affine, Y = o + L x.
  struct BodyMap {
    Vec3 o = Vec3::Zero();
    Mat3 L = Mat3::Identity();
  };
  BodyMap body_map(const Frame& fr, double sf) const;
  // Calls found(e, j, ia, ib, X, side, half) for every side e (load_.sheet_edges[e], nodes
  // load_.nodes[ia], [ib]) of the set crossing a sharp edge j of the mesh within reach, X the
  // four corners in the mesh's frame.
  template <class Found>
  void scan_edges(const NodePositions& x, const BodyMap& m, Found&& found) const;
  // The pair of side e and ridge j at X (the mesh's frame): its normal force and, with
  // friction, the Coulomb return on the anchors of the last accepted state (a new pair: the
  // closest points there); `anchor` the anchors used, `keep` the part of the slip they keep.
  contact::Status edge_force(size_t e, int j, int ia, int ib, const contact::Vec12& X, double side,
                             double half, bool tangent, contact::PairResult& r, Vec2& anchor,
                             double& keep) const;
  void add_edges(const LoadState& s, const Frame& fr, double sf, LoadOutput& out, MatX* U,
                 MatX* W) const;
  // At an accepted state: the pairs' forces into the accepted ones, their anchors moved on,
  // their moment on a rotating body and their stiffness against its turning.
  void commit_edges(const LoadState& s, const Frame& fr, double sf, bool starting, Vec3& moment,
                    double& turning);
  void set_up_edges();
  bool edge_friction() const { return !load_.sheet_edges.empty() && load_.friction > 0; }
  void save_edges(std::vector<double>& out) const;
  size_t restore_edges(const std::vector<double>& in, size_t at);
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
  std::vector<char> moves_;      // per node: some direction free on this process
  std::vector<int> slot_of_;     // edges: per model node, its index in load_.nodes (-1: none)
  contact::FaceTree edge_tree_;  // edges: over the mesh's sharp edges, in its frame at s = 0
  std::vector<contact::Box> edge_boxes_;  // edges: the tree's boxes (its queries read them)
  double edge_margin_ = 0;                // edges: how far a pair is followed past contact
  // Edges with friction: per pair (side, ridge) in contact at the last accepted state its
  // anchors (s0 on the side, t0 on the ridge), and per node its position in the mesh's frame
  // there (where a new pair anchors).
  std::map<std::pair<size_t, int>, Vec2> edge_anchor_;
  std::vector<Vec3> y_accepted_;
  std::vector<Vec3> anchor_;      // friction: the body's point (at s = 0) each node sticks to
  std::vector<Vec3> f_accepted_;  // the force on each node at the state accepted last
  std::vector<contact::Status> status_accepted_;  // and its status there
  double k_min_ = 0, k_max_ = 0;
  std::vector<double> c_;                             // the normal damping per node (empty: none)
  std::vector<std::pair<int, Mat3>> damping_blocks_;  // ∂f/∂v at the nodes in touch
  double penetration_ratio_ = 0;   // the largest penetration / tolerance at the last accepted step
  contact::PeakPenetration peak_;  // and over the accepted steps since the start
  contact::InitialPenetrations initial_;  // per node
  bool started_ = false;
  std::shared_ptr<rigid::Spin> spin_;  // a free body that rotates: its rotation (shared)
  bool owner_ = false;                 // the first of the body's entries: it saves the rotation
};

}  // namespace velum::rigid_contact
