// Edge contact with a rigid mesh (`edges: true`, docs/contact.md "Rigid meshes"): the set's
// membrane sides against the mesh's sharp convex edges (RigidMesh::sharp_edges), where a ridge
// narrower than the sheet's elements would pass between the nodes. The pair is the sheets' edge
// kernel (edge_contact.hpp) in the mesh's frame at s = 0, the side outside the ridge (along its
// outward direction), with Coulomb friction as the sheets' edge pairs (anchors on the side and
// on the ridge, a body point); a free body takes the opposite forces (its coupling in the
// low-rank columns of the node contact) and, turning, their moment.
#include "contact_term.hpp"
#include "edge_contact.hpp"

namespace velum::rigid_contact {

void ContactTerm::set_up_edges() {
  const Model& m = site_.model;
  slot_of_.assign(static_cast<size_t>(m.num_nodes()), -1);
  double half = 0, size = 0, longest = 0;
  for (size_t i = 0; i < load_.nodes.size(); ++i) {
    slot_of_[static_cast<size_t>(load_.nodes[i])] = static_cast<int>(i);
    half = std::max(half, load_.node_thickness[i]);
    size = std::max(size, load_.node_size[i]);
  }
  for (const auto& [a, b] : load_.sheet_edges)
    longest = std::max(longest, (m.X.col(a) - m.X.col(b)).norm());
  edge_margin_ = size;
  // The ridges' boxes, grown so that a side within reach has its middle inside.
  const auto& V = load_.body.mesh->vertices();
  std::vector<contact::Box>& boxes = edge_boxes_;  // read by the tree's queries: kept
  boxes.clear();
  for (const auto& e : load_.body.mesh->sharp_edges()) {
    contact::Box b(V[static_cast<size_t>(e.a)]);
    b.extend(V[static_cast<size_t>(e.b)]);
    const double grow = half + edge_margin_ + 0.5 * longest;
    b.min().array() -= grow;
    b.max().array() += grow;
    boxes.push_back(b);
  }
  if (!boxes.empty()) edge_tree_.build(boxes);
  y_accepted_.assign(load_.nodes.size(), Vec3::Zero());
}

ContactTerm::BodyMap ContactTerm::body_map(const Frame& fr, double sf) const {
  BodyMap m;
  m.o = load_.body.unmoved(to_body(fr, Vec3::Zero()), sf);
  for (int k = 0; k < 3; ++k) m.L.col(k) = load_.body.unmoved(to_body(fr, Vec3::Unit(k)), sf) - m.o;
  return m;
}

template <class Found>
void ContactTerm::scan_edges(const NodePositions& x, const BodyMap& m, Found&& found) const {
  if (edge_tree_.empty()) return;
  const auto& ridges = load_.body.mesh->sharp_edges();
  const auto& V = load_.body.mesh->vertices();
  contact::Vec12 X, grad;
  for (size_t e = 0; e < load_.sheet_edges.size(); ++e) {
    const auto [na, nb] = load_.sheet_edges[e];
    const int ia = slot_of_[static_cast<size_t>(na)], ib = slot_of_[static_cast<size_t>(nb)];
    X.segment<3>(0) = m.o + m.L * x.col(na);
    X.segment<3>(3) = m.o + m.L * x.col(nb);
    const Vec3 A = X.segment<3>(0), B = X.segment<3>(3);
    const double half = std::max(load_.node_thickness[static_cast<size_t>(ia)],
                                 load_.node_thickness[static_cast<size_t>(ib)]);
    edge_tree_.query(Vec3(0.5 * (A + B)), [&](int j) {
      const RigidMesh::SharpEdge& r = ridges[static_cast<size_t>(j)];
      const Vec3& C = V[static_cast<size_t>(r.a)];
      const Vec3& D = V[static_cast<size_t>(r.b)];
      double s = 0, t = 0;
      if (!contact::edge_parameters(A, B, C, D, s, t) || s <= 0 || s >= 1 || t <= 0 || t >= 1)
        return;
      X.segment<3>(6) = C;
      X.segment<3>(9) = D;
      const double g = contact::edge_gap(X, grad, nullptr);
      if (std::abs(g) >= half + edge_margin_) return;
      // Outside: the side the ridge's outward direction points to.
      const double side = (B - A).cross(D - C).dot(r.out) >= 0 ? 1.0 : -1.0;
      // Behind the ridge's line: a pair only where the side's closest point is inside the body
      // and the ridge about as near as the surface (not a far ridge whose line the side passes
      // behind: the wedge's base under a strip resting on its top).
      if (const double depth = -side * g; depth > 0) {
        Vec3 n;
        Mat3 H;
        const double d = load_.body.mesh->gap(Vec3(A + s * (B - A)), n, H);
        if (d > 0 || depth > -d + half + 0.1 * edge_margin_) return;
      }
      found(e, j, ia, ib, X, side, half);
    });
  }
}

contact::Status ContactTerm::edge_force(size_t e, int j, int ia, int ib, const contact::Vec12& X,
                                        double side, double half, bool tangent,
                                        contact::PairResult& r, Vec2& anchor, double& keep) const {
  const double k = std::min(k_[static_cast<size_t>(ia)], k_[static_cast<size_t>(ib)]);
  keep = 1;
  if (!contact::edge_pair_force(X, side, half, k, tangent, r)) return contact::Status::kOpen;
  if (!(load_.friction > 0)) return contact::Status::kSlip;  // frictionless: slides
  if (auto it = edge_anchor_.find({e, j}); it != edge_anchor_.end()) {
    anchor = it->second;
  } else {
    // A new pair anchors at the closest points of the last accepted state (the ridge is the
    // body's: fixed in its frame), held within the step so the tangent stays consistent; the
    // side parallel to the ridge there: at today's.
    double s = 0, t = 0;
    if (!contact::edge_parameters(y_accepted_[static_cast<size_t>(ia)],
                                  y_accepted_[static_cast<size_t>(ib)], X.segment<3>(6),
                                  X.segment<3>(9), s, t))
      contact::edge_parameters(X.segment<3>(0), X.segment<3>(3), X.segment<3>(6), X.segment<3>(9),
                               s, t);
    anchor = Vec2(s, t);
  }
  return contact::edge_friction(X, side, half, k, load_.friction, anchor, tangent, r, keep);
}

void ContactTerm::add_edges(const LoadState& s, const Frame& fr, double sf, LoadOutput& out,
                            MatX* U, MatX* W) const {
  const BodyMap m = body_map(fr, sf);
  const int b = load_.body_node;
  const Mat3 Lt = m.L.transpose();
  contact::PairResult r;
  scan_edges(
      s.x, m,
      [&](size_t e, int j, int ia, int ib, const contact::Vec12& X, double side, double half) {
        Vec2 anchor;
        double keep = 1;
        if (edge_force(e, j, ia, ib, X, side, half, out.K != nullptr, r, anchor, keep) ==
            contact::Status::kOpen)
          return;
        const int n[2] = {load_.nodes[static_cast<size_t>(ia)],
                          load_.nodes[static_cast<size_t>(ib)]};
        const Vec3 f0 = Lt * r.f.segment<3>(0), f1 = Lt * r.f.segment<3>(3);
        out.F.col(n[0]) += f0;
        out.F.col(n[1]) += f1;
        if (b >= 0) out.F.col(b) -= f0 + f1;
        if (!out.K) return;
        // ∂f/∂x of the side's two nodes (the ridge is the body's): global, into K (one
        // element's). Unsymmetric with friction.
        Mat3 D[2][2];
        for (int q = 0; q < 2; ++q)
          for (int w = 0; w < 2; ++w) {
            D[q][w] = Lt * r.D.block<3, 3>(3 * q, 3 * w) * m.L;
            subtract_node_block(site_.dofs, n[q], n[w], D[q][w], *out.K);
          }
        if (b < 0) return;
        // A free body: the forces depend on x − (the body's translation), and it takes
        // their opposite: K_bb = −ΣD, K_nb = D_n0 + D_n1 and K_bn = D_0n + D_1n (low
        // rank, as nodes).
        add_block(b, D[0][0] + D[0][1] + D[1][0] + D[1][1], *out.K);
        if (!U) return;
        for (int c = 0; c < 3; ++c)
          for (int q = 0; q < 2; ++q) {
            put(n[q], Vec3((D[q][0] + D[q][1]).col(c)), U->col(out.column + c));
            put(n[q], Vec3((D[0][q] + D[1][q]).row(c).transpose()), W->col(out.column + 3 + c));
          }
      });
}

void ContactTerm::commit_edges(const LoadState& s, const Frame& fr, double sf, bool starting,
                               Vec3& moment, double& turning) {
  const BodyMap m = body_map(fr, sf);
  const Mat3 Lt = m.L.transpose();
  const bool friction = edge_friction();
  // Where a new pair anchors: at the start, where it is.
  if (friction && starting)
    for (size_t i = 0; i < load_.nodes.size(); ++i)
      y_accepted_[i] = m.o + m.L * s.x.col(load_.nodes[i]);
  std::map<std::pair<size_t, int>, Vec2> anchors;
  contact::PairResult r;
  scan_edges(
      s.x, m,
      [&](size_t e, int j, int ia, int ib, const contact::Vec12& X, double side, double half) {
        Vec2 anchor;
        double keep = 1;
        const contact::Status status =
            edge_force(e, j, ia, ib, X, side, half, false, r, anchor, keep);
        if (status == contact::Status::kOpen) return;
        if (friction) {
          // The anchors toward the closest points now by the part of the slip not kept.
          double sn = 0, tn = 0;
          contact::edge_parameters(X.segment<3>(0), X.segment<3>(3), X.segment<3>(6),
                                   X.segment<3>(9), sn, tn);
          anchors[{e, j}] = Vec2(sn + keep * (anchor[0] - sn), tn + keep * (anchor[1] - tn));
        }
        const size_t i[2] = {static_cast<size_t>(ia), static_cast<size_t>(ib)};
        for (int q = 0; q < 2; ++q) {
          const Vec3 f = Lt * r.f.segment<3>(3 * q);
          f_accepted_[i[q]] += f;
          status_accepted_[i[q]] = std::max(status_accepted_[i[q]], status);
          const double tol =
              std::max(0.01 * 2 * load_.node_thickness[i[q]], 1e-3 * load_.node_size[i[q]]);
          if (tol > 0) penetration_ratio_ = std::max(penetration_ratio_, -r.gap / tol);
          // The body takes the opposite force of each node, about its centre (the
          // sheet's and the body's angular momenta balance).
          if (fr.turned) {
            const Vec3 arm = s.x.col(load_.nodes[i[q]]) - fr.c;
            moment -= arm.cross(f);
            turning +=
                0.5 * std::min(k_[i[0]], k_[i[1]]) * (1 + load_.friction) * arm.squaredNorm();
          }
        }
      });
  if (!friction) return;
  edge_anchor_ = std::move(anchors);
  for (size_t i = 0; i < load_.nodes.size(); ++i)
    y_accepted_[i] = m.o + m.L * s.x.col(load_.nodes[i]);
}

// The pairs' anchors and the nodes' positions in the mesh's frame at the last accepted state:
// the nodes' positions, the number of pairs, then per pair its side, ridge and anchors.
void ContactTerm::save_edges(std::vector<double>& out) const {
  for (const Vec3& y : y_accepted_) out.insert(out.end(), y.data(), y.data() + 3);
  out.push_back(static_cast<double>(edge_anchor_.size()));
  for (const auto& [key, a] : edge_anchor_)
    out.insert(out.end(),
               {static_cast<double>(key.first), static_cast<double>(key.second), a[0], a[1]});
}

size_t ContactTerm::restore_edges(const std::vector<double>& in, size_t at) {
  const auto fail = [] {
    return std::invalid_argument("the contact's saved edge pairs do not fit its edges");
  };
  const size_t N = y_accepted_.size();
  if (in.size() < at + 3 * N + 1) throw fail();
  for (size_t i = 0; i < N; ++i, at += 3) y_accepted_[i] = Vec3(in[at], in[at + 1], in[at + 2]);
  const auto n = static_cast<size_t>(in[at++]);
  if (in.size() < at + 4 * n) throw fail();
  const auto sides = static_cast<double>(load_.sheet_edges.size());
  const auto ridges = static_cast<double>(load_.body.mesh->sharp_edges().size());
  edge_anchor_.clear();
  for (size_t p = 0; p < n; ++p, at += 4) {
    if (!(in[at] >= 0 && in[at] < sides && in[at + 1] >= 0 && in[at + 1] < ridges)) throw fail();
    edge_anchor_[{static_cast<size_t>(in[at]), static_cast<int>(in[at + 1])}] =
        Vec2(in[at + 2], in[at + 3]);
  }
  return at;
}

}  // namespace velum::rigid_contact
