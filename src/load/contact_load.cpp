// Node-to-rigid-surface contact (docs/contact.md): every node of the set against the body, the
// law of contact_law.hpp at each, the 3 x 3 block of its derivative into the node's diagonal
// block of K; the multipliers and friction anchors move on at accepted steps only. A free body
// that rotates has one rotation, shared by the contact entries it takes part in (Spin).
#include "contact_term.hpp"
#include "reference_diagonal.hpp"

namespace velum {
namespace rigid_contact {

void Contact::set_up(const Model& model, const ElementNamer&) {
  const int N = model.num_nodes();
  std::vector<double> t(static_cast<size_t>(N), -1.0), h(static_cast<size_t>(N), 0.0);
  std::set<std::pair<int, int>> sides;  // edges: true, the membranes' element sides
  for (const Part& part : parts) {
    const ElementBlock& b = *model.blocks[static_cast<size_t>(part.block)];
    for (int e : part.elements) {
      if (!b.holds(e)) continue;
      const double half = b.surface() ? 0.5 * b.output(e, model.X).thickness : 0.0;
      const double size = b.surface() ? std::sqrt(b.measure(e)) : b.measure(e);
      const auto en = b.nodes(e);
      for (int n : en) {
        t[static_cast<size_t>(n)] = std::max(t[static_cast<size_t>(n)], half);
        h[static_cast<size_t>(n)] = std::max(h[static_cast<size_t>(n)], size);
      }
      if (edges && b.surface()) {
        const int corners = en.size() == 3 || en.size() == 6 ? 3 : 4;
        for (int a = 0; a < corners; ++a) sides.insert(std::minmax(en[a], en[(a + 1) % corners]));
      }
    }
  }
  sheet_edges.assign(sides.begin(), sides.end());
  // Every element at a node of the set adds to its stiffness, as in the assembled matrix
  // (a sheet's edge node joined to a cable has both), but unconstrained.
  // So does its lumped mass (the damping's scale), point masses included.
  NodePositions diagonal = NodePositions::Zero(3, N);
  std::vector<double> mass(static_cast<size_t>(N), 0.0);
  ReferenceDiagonal reference;
  MatX Me;
  std::vector<double> lumped;
  for (const auto& block : model.blocks)
    for (int e = 0; e < block->size(); ++e) {
      const auto en = block->nodes(e);
      if (!block->holds(e) ||
          std::none_of(en.begin(), en.end(), [&](int n) { return t[static_cast<size_t>(n)] >= 0; }))
        continue;
      reference(*block, e, model.X, [&](int n, int c, double k) { diagonal(c, n) += k; });
      Me.resize(block->nodes_per_element(), block->nodes_per_element());
      lumped.resize(en.size());
      block->mass(e, Me.data());
      block->shape().lump(Me.data(), lumped.data());
      for (size_t a = 0; a < en.size(); ++a) mass[static_cast<size_t>(en[a])] += lumped[a];
    }
  for (const auto& pm : model.masses) mass[static_cast<size_t>(pm.node)] += pm.mass;
  nodes.clear(), node_thickness.clear(), node_size.clear(), node_stiffness.clear();
  node_mass.clear();
  for (int n = 0; n < N; ++n)
    if (t[static_cast<size_t>(n)] >= 0) {
      nodes.push_back(n);
      node_thickness.push_back(thickness >= 0 ? thickness : t[static_cast<size_t>(n)]);
      node_size.push_back(h[static_cast<size_t>(n)]);
      node_stiffness.push_back(diagonal.col(n).maxCoeff());
      node_mass.push_back(mass[static_cast<size_t>(n)]);
    }
}

ContactTerm::ContactTerm(const Contact& load, const LoadSite& site) : load_(load), site_(site) {
  // The automatic penalty: the largest diagonal entry of the node's block of the reference
  // tangent, unconstrained (the sheet's in-plane stiffness, E t for a membrane), times
  // penalty_scale; a node held in all three directions takes the mean of the others (it never
  // moves: the figure only enters the reported range, not the forces or the explicit step).
  // Each process holds the whole set's figures (Contact::set_up, whole model).
  const size_t N = load.nodes.size();
  k_.assign(N, 0.0);
  moves_.assign(N, 0);
  double sums[3] = {0, 0, static_cast<double>(N)};  // of k > 0, their count, the set's nodes
  for (size_t i = 0; i < N; ++i) {
    const int n = load.nodes[i];
    bool moves = false;
    for (int c = 0; c < 3; ++c) moves = moves || site.dofs.equation(n, c) >= 0;
    k_[i] = moves ? load.node_stiffness[i] : 0.0;
    moves_[i] = moves;
    if (k_[i] > 0 && site.assembler.keeps_node(n)) sums[0] += k_[i], ++sums[1];
  }
  if (site.model.piece) processes::sum(sums, 3);
  const double mean = sums[1] > 0 ? sums[0] / sums[1] : 0.0;
  if (sums[2] > 0 && mean <= 0)
    throw std::invalid_argument(
        fmt::format("contact {}: the set has no stiffness at its reference to scale the penalty on",
                    load.index));
  for (double& k : k_) k = load.penalty_scale * (k > 0 ? k : mean);
  double lo = N ? *std::min_element(k_.begin(), k_.end()) : INFINITY,
         hi = N ? *std::max_element(k_.begin(), k_.end()) : 0.0;
  if (site.model.piece) lo = -processes::max(-lo), hi = processes::max(hi);
  if (sums[2] > 0) k_min_ = lo, k_max_ = hi;
  if (load.damping > 0) {  // c = 2 ζ √(k m), m the node's lumped mass
    c_.assign(N, 0.0);
    for (size_t i = 0; i < N; ++i) c_[i] = 2 * load.damping * std::sqrt(k_[i] * load.node_mass[i]);
  }
  lambda_.assign(N, 0.0);
  initial_.resize(N);
  anchor_.resize(N);
  f_accepted_.assign(N, Vec3::Zero());
  status_accepted_.assign(N, contact::Status::kOpen);
  for (size_t i = 0; i < N; ++i) anchor_[i] = site.model.X.col(load.nodes[i]);
  if (load.body_node >= 0 && load.body.inertia != Mat3::Zero())
    spin_ = std::make_shared<rigid::Spin>(load.body.inertia, load.body.angular_velocity),
    owner_ = true;
  if (!load.sheet_edges.empty()) set_up_edges();
}

void ContactTerm::move_on(const LoadState& s, bool update_multipliers, bool starting) {
  const double sf = site_.model.function_value(load_.body.function, s.t);
  penetration_ratio_ = 0;
  const Frame fr = frame(s.t, s.x);
  Vec3 moment = Vec3::Zero();  // of the forces on a rotating body, about its centre
  double turning = 0;          // Σ k r²: the contact's stiffness against its rotation
  // With damping, the accepted force (the history's contact_force, the frames' pressure) and
  // the anchors are those add() applied, damping included; a multiplier takes the elastic
  // part only, which is what a steady state holds.
  const BodyRate rate = damping_rate(s.t);
  for (size_t i = 0; i < load_.nodes.size(); ++i) {
    const Vec3 x = to_body(fr, s.x.col(load_.nodes[i]));  // relative to a free body
    const contact::NodeResult r =
        evaluate(i, x, sf, false,
                 c_.empty() ? Vec3::Zero() : relative_velocity(s, fr, rate, load_.nodes[i], x));
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
    const double g = load_.body.gap(x, sf, n, H) - load_.node_thickness[i] + relaxed(i);
    const double tol = std::max(0.01 * 2 * load_.node_thickness[i], 1e-3 * load_.node_size[i]);
    if (tol > 0) penetration_ratio_ = std::max(penetration_ratio_, -g / tol);
    if (update_multipliers) lambda_[i] = std::max(0.0, lambda_[i] - k_[i] * g);
    anchor_[i] = load_.body.unmoved(x - r.slip, sf);
  }
  if (!load_.sheet_edges.empty()) commit_edges(s, fr, sf, starting, moment, turning);
  if (!starting) peak_.note(penetration_ratio_, s.t);  // accepted states, not the given start
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

void ContactTerm::find_initial_penetrations(const LoadState& s) {
  started_ = true;
  const double sf = site_.model.function_value(load_.body.function, s.t);
  const Frame fr = frame(s.t, s.x);
  for (size_t i = 0; i < load_.nodes.size(); ++i) {
    Vec3 n;
    Mat3 H;
    const double g =
        load_.body.gap(to_body(fr, s.x.col(load_.nodes[i])), sf, n, H) - load_.node_thickness[i];
    initial_.note(i, g, load_.relax_steps, site_.assembler.keeps_node(load_.nodes[i]));
  }
  if (site_.model.piece) initial_.total_over_processes();
}

std::unique_ptr<LoadTerm> Contact::bind(const LoadSite& site) const {
  return std::make_unique<ContactTerm>(*this, site);
}

}  // namespace rigid_contact

std::unique_ptr<Load> make_load(ContactLoad p) {
  if (p.friction < 0) throw std::invalid_argument("a friction coefficient below 0");
  if (p.self || !p.other.empty()) return make_sheet_contact(std::move(p));
  return std::make_unique<rigid_contact::Contact>(std::move(p));
}

}  // namespace velum
