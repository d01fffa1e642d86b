// Sheet contact, edge to edge (`edges: true`): element sides against the other set's (or, in
// self contact, their own away from two rings), where nodes alone would let a fold or a
// crossing strip pass between them (docs/contact.md).
#include "sheet_contact_term.hpp"

namespace velum::sheet_contact {

template <class Found>
void SheetContactTerm::scan_edges(const NodePositions& x, Found&& found) {
  const auto& A = load_.edge_lists[0];
  const auto& B = load_.edge_lists[load_.self ? 0 : 1];
  if (B.empty()) return;
  for (size_t j = 0; j < B.size(); ++j) {
    contact::Box b(x.col(B[j].a));
    b.extend(Vec3(x.col(B[j].b)));
    const double grow = B[j].half + reach_ + margin_ + edge_grow_;
    b.min().array() -= grow;
    b.max().array() += grow;
    edge_boxes_[j] = b;
  }
  if (edge_tree_.empty())
    edge_tree_.build(edge_boxes_);
  else
    edge_tree_.refit(edge_boxes_);
  contact::Vec12 X;
  for (size_t i = 0; i < A.size(); ++i) {
    const Edge& e = A[i];
    const Vec3 mid = 0.5 * (x.col(e.a) + x.col(e.b));
    edge_tree_.query(mid, [&](int jj) {
      const Edge& f = B[static_cast<size_t>(jj)];
      if (load_.self && jj <= static_cast<int>(i)) return;
      if (near(e.a, f.a) || near(e.a, f.b) || near(e.b, f.a) || near(e.b, f.b)) return;
      double sp = 0, tp = 0;
      if (!contact::edge_parameters(x.col(e.a), x.col(e.b), x.col(f.a), x.col(f.b), sp, tp) ||
          sp <= 0 || sp >= 1 || tp <= 0 || tp >= 1)
        return;
      X << x.col(e.a), x.col(e.b), x.col(f.a), x.col(f.b);
      contact::Vec12 grad;
      const double g = contact::edge_gap(X, grad, nullptr);
      const double thickness = e.half + f.half;
      if (std::abs(g) >= thickness + margin_) return;
      // The side: the pair's at the last accepted state, else the edges' there.
      double side = 1;
      if (auto it = edge_side_.find({static_cast<int>(i), jj}); it != edge_side_.end()) {
        side = it->second;
      } else {
        contact::Vec12 Y;
        Y << x_accepted_.col(e.a), x_accepted_.col(e.b), x_accepted_.col(f.a), x_accepted_.col(f.b);
        side = contact::edge_gap(Y, grad, nullptr) >= 0 ? 1.0 : -1.0;
      }
      found(static_cast<int>(i), jj, X, side, thickness);
    });
  }
}

void SheetContactTerm::add_edges(const LoadState& s, LoadOutput& out) {
  const auto& A = load_.edge_lists[0];
  const auto& B = load_.edge_lists[load_.self ? 0 : 1];
  contact::PairResult r;
  scan_edges(s.x, [&](int i, int j, const contact::Vec12& X, double side, double thickness) {
    const Edge& e = A[static_cast<size_t>(i)];
    const Edge& f = B[static_cast<size_t>(j)];
    const double k = load_.penalty_scale * std::min(load_.stiffness[static_cast<size_t>(e.a)],
                                                    load_.stiffness[static_cast<size_t>(f.a)]);
    if (!contact::edge_pair_force(X, side, thickness, k, out.K != nullptr, r)) return;
    const std::array<int, 4> nodes = {e.a, e.b, f.a, f.b};
    for (int q = 0; q < 4; ++q) out.F.col(nodes[static_cast<size_t>(q)]) += r.f.segment<3>(3 * q);
    if (!out.K) return;
    // The blocks within each edge (in the pattern); those between the two edges are left out
    // (Newton converges linearly while edge pairs act).
    for (int q0 : {0, 2})
      for (int q = q0; q < q0 + 2; ++q)
        for (int w = q0; w < q0 + 2; ++w)
          add_block(nodes[static_cast<size_t>(q)], nodes[static_cast<size_t>(w)],
                    r.D.block<3, 3>(3 * q, 3 * w), *out.K);
  });
}

void SheetContactTerm::commit_edges(const NodePositions& x) {
  if (!load_.edges) return;
  const auto& A = load_.edge_lists[0];
  const auto& B = load_.edge_lists[load_.self ? 0 : 1];
  std::map<std::pair<int, int>, double> sides;
  edge_active_ = 0;
  contact::PairResult r;
  scan_edges(x, [&](int i, int j, const contact::Vec12& X, double side, double thickness) {
    const Edge& e = A[static_cast<size_t>(i)];
    const Edge& f = B[static_cast<size_t>(j)];
    sides[{i, j}] = side;
    const double k = load_.penalty_scale * std::min(load_.stiffness[static_cast<size_t>(e.a)],
                                                    load_.stiffness[static_cast<size_t>(f.a)]);
    if (!contact::edge_pair_force(X, side, thickness, k, false, r)) return;
    ++edge_active_;
    const std::array<int, 4> nodes = {e.a, e.b, f.a, f.b};
    for (int q = 0; q < 4; ++q) {
      const auto n = static_cast<size_t>(nodes[static_cast<size_t>(q)]);
      transmitted_[n] += r.f.segment<3>(3 * q).norm();
      node_status_[n] = std::max(node_status_[n], 2.0);  // frictionless: slides
    }
    if (load_.self)
      force_on_other_ += (r.f.segment<3>(0) + r.f.segment<3>(3)).cwiseAbs();
    else
      force_on_other_ += r.f.segment<3>(6) + r.f.segment<3>(9);
    const double tol = std::max(0.01 * thickness, 1e-3 * margin_);
    if (tol > 0) penetration_ratio_ = std::max(penetration_ratio_, -r.gap / tol);
  });
  edge_side_ = std::move(sides);
}

}  // namespace velum::sheet_contact
