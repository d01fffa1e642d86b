// Edge contact with a rigid mesh (`edges: true`, docs/contact.md "Rigid meshes"): the set's
// membrane sides against the mesh's sharp convex edges (RigidMesh::sharp_edges), where a ridge
// narrower than the sheet's elements would pass between the nodes. The pair is the sheets' edge
// kernel (edge_contact.hpp) in the mesh's frame at s = 0, the side outside the ridge (along its
// outward direction), frictionless; a free body takes the opposite forces (its coupling in the
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
  for (const auto& [na, nb] : load_.sheet_edges) {
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
      found(ia, ib, X, side, half, s);
    });
  }
}

void ContactTerm::add_edges(const LoadState& s, const Frame& fr, double sf, LoadOutput& out,
                            MatX* U, MatX* W) const {
  const BodyMap m = body_map(fr, sf);
  const int b = load_.body_node;
  const Mat3 Lt = m.L.transpose();
  contact::PairResult r;
  scan_edges(
      s.x, m, [&](int ia, int ib, const contact::Vec12& X, double side, double half, double) {
        const double k = std::min(k_[static_cast<size_t>(ia)], k_[static_cast<size_t>(ib)]);
        if (!contact::edge_pair_force(X, side, half, k, out.K != nullptr, r)) return;
        const int n[2] = {load_.nodes[static_cast<size_t>(ia)],
                          load_.nodes[static_cast<size_t>(ib)]};
        const Vec3 f0 = Lt * r.f.segment<3>(0), f1 = Lt * r.f.segment<3>(3);
        out.F.col(n[0]) += f0;
        out.F.col(n[1]) += f1;
        if (b >= 0) out.F.col(b) -= f0 + f1;
        if (!out.K) return;
        // ∂f/∂x of the side's two nodes (the ridge is the body's): global, into K (one element's).
        Mat3 D[2][2];
        for (int q = 0; q < 2; ++q)
          for (int w = 0; w < 2; ++w) {
            D[q][w] = Lt * r.D.block<3, 3>(3 * q, 3 * w) * m.L;
            subtract_node_block(site_.dofs, n[q], n[w], D[q][w], *out.K);
          }
        if (b < 0) return;
        // A free body: the forces depend on x − (the body's translation), and it takes their
        // opposite: K_bb = −ΣD, K_nb = D_n0 + D_n1 and K_bn = D_0n + D_1n (low rank, as nodes).
        add_block(b, D[0][0] + D[0][1] + D[1][0] + D[1][1], *out.K);
        if (!U) return;
        for (int c = 0; c < 3; ++c)
          for (int q = 0; q < 2; ++q) {
            put(n[q], Vec3((D[q][0] + D[q][1]).col(c)), U->col(out.column + c));
            put(n[q], Vec3((D[0][q] + D[1][q]).row(c).transpose()), W->col(out.column + 3 + c));
          }
      });
}

void ContactTerm::commit_edges(const LoadState& s, const Frame& fr, double sf, Vec3& moment,
                               double& turning) {
  const BodyMap m = body_map(fr, sf);
  const Mat3 Lt = m.L.transpose();
  contact::PairResult r;
  scan_edges(
      s.x, m, [&](int ia, int ib, const contact::Vec12& X, double side, double half, double at) {
        const double k = std::min(k_[static_cast<size_t>(ia)], k_[static_cast<size_t>(ib)]);
        if (!contact::edge_pair_force(X, side, half, k, false, r)) return;
        const size_t i[2] = {static_cast<size_t>(ia), static_cast<size_t>(ib)};
        Vec3 sum = Vec3::Zero();
        for (int q = 0; q < 2; ++q) {
          const Vec3 f = Lt * r.f.segment<3>(3 * q);
          f_accepted_[i[q]] += f;
          sum += f;
          if (status_accepted_[i[q]] == contact::Status::kOpen)
            status_accepted_[i[q]] = contact::Status::kSlip;  // frictionless: slides
          const double tol =
              std::max(0.01 * 2 * load_.node_thickness[i[q]], 1e-3 * load_.node_size[i[q]]);
          if (tol > 0) penetration_ratio_ = std::max(penetration_ratio_, -r.gap / tol);
        }
        if (!fr.turned) return;
        // The body takes −sum at the side's closest point (along the pair's normal: where on it
        // does not change the moment).
        const Vec3 P = (1 - at) * s.x.col(load_.nodes[i[0]]) + at * s.x.col(load_.nodes[i[1]]);
        moment -= (P - fr.c).cross(sum);
        turning += k * (P - fr.c).squaredNorm();
      });
}

}  // namespace velum::rigid_contact
