// Sheet contact, edge to edge (`edges: true`): element sides against the other set's (or, in
// self contact, their own away from two rings), where nodes alone would let a fold or a
// crossing strip pass between them (docs/contact.md), with Coulomb friction as node to face.
// The pair's matrix goes into K as node blocks: within each edge (the mesh's pattern) and
// between the two edges (the couplings the term declares, update_couplings).
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
      // The pair at the last accepted state, else its edges' side there.
      EdgePair pair;
      if (auto it = edge_pairs_.find({static_cast<int>(i), jj}); it != edge_pairs_.end()) {
        pair = it->second;
      } else {
        contact::Vec12 Y;
        Y << x_accepted_.col(e.a), x_accepted_.col(e.b), x_accepted_.col(f.a), x_accepted_.col(f.b);
        pair.side = contact::edge_gap(Y, grad, nullptr) >= 0 ? 1.0 : -1.0;
      }
      found(static_cast<int>(i), jj, X, pair, thickness);
    });
  }
}

contact::Status SheetContactTerm::edge_force(int i, int j, const contact::Vec12& X,
                                             const EdgePair& pair, double thickness, bool tangent,
                                             contact::PairResult& r, Vec2& anchor,
                                             double& keep) const {
  const Edge& e = load_.edge_lists[0][static_cast<size_t>(i)];
  const Edge& f = load_.edge_lists[load_.self ? 0 : 1][static_cast<size_t>(j)];
  // The penalty: the smaller of the two edges' first nodes'.
  const double k = load_.penalty_scale * std::min(load_.stiffness[static_cast<size_t>(e.a)],
                                                  load_.stiffness[static_cast<size_t>(f.a)]);
  keep = 1;
  if (!contact::edge_pair_force(X, pair.side, thickness, k, tangent, r))
    return contact::Status::kOpen;
  if (!(load_.friction > 0)) return contact::Status::kSlip;  // frictionless: slides
  anchor = pair.anchor;
  if (!pair.anchored) {
    // A new pair anchors at the closest points of the last accepted state (held within the
    // step: the tangent stays consistent); edges parallel there: at today's.
    double s = 0, t = 0;
    if (!contact::edge_parameters(x_accepted_.col(e.a), x_accepted_.col(e.b), x_accepted_.col(f.a),
                                  x_accepted_.col(f.b), s, t))
      contact::edge_parameters(X.segment<3>(0), X.segment<3>(3), X.segment<3>(6), X.segment<3>(9),
                               s, t);
    anchor = Vec2(s, t);
  }
  return contact::edge_friction(X, pair.side, thickness, k, load_.friction, anchor, tangent, r,
                                keep);
}

void SheetContactTerm::search_edges(const NodePositions& x) {
  edge_hits_.clear();
  scan_edges(x, [&](int i, int j, const contact::Vec12& X, const EdgePair& pair, double thickness) {
    edge_hits_.push_back({i, j, X, pair, thickness});
  });
}

void SheetContactTerm::add_edges(LoadOutput& out) {
  const auto& A = load_.edge_lists[0];
  const auto& B = load_.edge_lists[load_.self ? 0 : 1];
  contact::PairResult r;
  for (const EdgeHit& h : edge_hits_) {
    Vec2 anchor;
    double keep = 1;
    if (edge_force(h.i, h.j, h.X, h.pair, h.thickness, out.K != nullptr, r, anchor, keep) ==
        contact::Status::kOpen)
      continue;
    const Edge& e = A[static_cast<size_t>(h.i)];
    const Edge& f = B[static_cast<size_t>(h.j)];
    const std::array<int, 4> nodes = {e.a, e.b, f.a, f.b};
    for (int q = 0; q < 4; ++q) out.F.col(nodes[static_cast<size_t>(q)]) += r.f.segment<3>(3 * q);
    // K −= ∂f/∂X: the blocks within each edge and between the edges.
    if (out.K) add_blocks(nodes, r.D, *out.K);
  }
}

void SheetContactTerm::commit_edges(const NodePositions& x) {
  if (!load_.edges) return;
  const auto& A = load_.edge_lists[0];
  const auto& B = load_.edge_lists[load_.self ? 0 : 1];
  std::map<std::pair<int, int>, EdgePair> pairs;
  edge_active_ = 0;
  contact::PairResult r;
  scan_edges(x, [&](int i, int j, const contact::Vec12& X, const EdgePair& pair, double thickness) {
    EdgePair& now = pairs[{i, j}];
    now.side = pair.side;
    Vec2 anchor;
    double keep = 1;
    const contact::Status status = edge_force(i, j, X, pair, thickness, false, r, anchor, keep);
    if (status == contact::Status::kOpen) return;  // not touching: no anchor
    if (load_.friction > 0) {
      // The anchors toward the closest points now, by the part of the slip kept.
      double s = 0, t = 0;
      contact::edge_parameters(X.segment<3>(0), X.segment<3>(3), X.segment<3>(6), X.segment<3>(9),
                               s, t);
      now.anchored = true;
      now.anchor = Vec2(s + keep * (anchor[0] - s), t + keep * (anchor[1] - t));
    }
    ++edge_active_;
    const Edge& e = A[static_cast<size_t>(i)];
    const Edge& f = B[static_cast<size_t>(j)];
    const std::array<int, 4> nodes = {e.a, e.b, f.a, f.b};
    for (int q = 0; q < 4; ++q) {
      const auto n = static_cast<size_t>(nodes[static_cast<size_t>(q)]);
      transmitted_[n] += r.f.segment<3>(3 * q).norm();
      node_status_[n] = std::max(node_status_[n], static_cast<double>(status));
    }
    if (load_.self)
      force_on_other_ += (r.f.segment<3>(0) + r.f.segment<3>(3)).cwiseAbs();
    else
      force_on_other_ += r.f.segment<3>(6) + r.f.segment<3>(9);
    const double tol = std::max(0.01 * thickness, 1e-3 * margin_);
    if (tol > 0) penetration_ratio_ = std::max(penetration_ratio_, -r.gap / tol);
  });
  edge_pairs_ = std::move(pairs);
}

// The edge pairs of the last accepted state: their number, then per pair its edges, side,
// whether anchored and the anchor.
void SheetContactTerm::save_edges(std::vector<double>& out) const {
  out.push_back(static_cast<double>(edge_pairs_.size()));
  for (const auto& [key, p] : edge_pairs_)
    out.insert(out.end(), {static_cast<double>(key.first), static_cast<double>(key.second), p.side,
                           p.anchored ? 1.0 : 0.0, p.anchor[0], p.anchor[1]});
}

size_t SheetContactTerm::restore_edges(const std::vector<double>& in, size_t at) {
  const auto fail = [] {
    return std::invalid_argument("the sheet contact's saved edge pairs do not fit its edges");
  };
  if (at >= in.size()) throw fail();
  const auto n = static_cast<size_t>(in[at++]);
  if (in.size() < at + 6 * n) throw fail();
  const auto first = static_cast<double>(load_.edge_lists[0].size());
  const auto second = static_cast<double>(load_.edge_lists[load_.self ? 0 : 1].size());
  edge_pairs_.clear();
  for (size_t p = 0; p < n; ++p, at += 6) {
    if (!(in[at] >= 0 && in[at] < first && in[at + 1] >= 0 && in[at + 1] < second)) throw fail();
    edge_pairs_[{static_cast<int>(in[at]), static_cast<int>(in[at + 1])}] =
        EdgePair{in[at + 2], in[at + 3] != 0, Vec2(in[at + 4], in[at + 5])};
  }
  return at;
}

}  // namespace velum::sheet_contact
