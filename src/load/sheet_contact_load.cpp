// Sheet–sheet and self contact (sheet_contact.hpp, docs/contact.md "Sheets"): every node of a
// set against the triangles (quads split in two) of the other set, or of its own set outside
// its two rings of elements, found among candidates that a box tree gave with a skin (kept
// until a node has moved past half of it) by exact tests at every evaluation; the pair's
// penalty force of face_contact.hpp. Its 12 x 12 matrix goes into K as node blocks: the
// node's and the face's are in the mesh's pattern, the node–face coupling in the couplings
// the term declares (update_couplings), which the system adds to the pattern.
#include "reference_diagonal.hpp"
#include "sheet_contact_term.hpp"

namespace velum {
namespace sheet_contact {

void SheetContact::set_up(const Model& model, const ElementNamer&) {
  const size_t N = static_cast<size_t>(model.num_nodes());
  std::vector<std::vector<int>> near(N);
  std::array<std::vector<double>, 2> half, size;
  stiffness.assign(N, 0.0);
  ReferenceDiagonal diagonal;
  std::array<std::map<std::pair<int, int>, size_t>, 2> edge_index;
  auto collect = [&](const std::vector<Part>& set, int which) {
    half[which].assign(N, -1.0), size[which].assign(N, 0.0);
    faces[which].clear();
    edge_lists[which].clear();
    for (const Part& part : set) {
      const ElementBlock& b = *model.blocks[static_cast<size_t>(part.block)];
      if (!b.surface()) continue;  // cables: no faces (their nodes are not in sheet contact)
      for (int e : part.elements) {
        if (!b.holds(e)) continue;
        const auto en = b.nodes(e);
        const double h = thickness >= 0 ? thickness : 0.5 * b.output(e, model.X).thickness;
        const double sz = std::sqrt(b.measure(e));
        const int corners = en.size() == 3 || en.size() == 6 ? 3 : 4;
        Face f;
        f.half = h;
        f.element.fill(-1);
        for (int a = 0; a < corners; ++a) f.element[static_cast<size_t>(a)] = en[a];
        f.n = {en[0], en[1], en[2]};
        faces[which].push_back(f);
        if (corners == 4) {
          f.n = {en[0], en[2], en[3]};
          faces[which].push_back(f);
        }
        // Each node's largest diagonal entry of its elements' reference tangents (its
        // in-plane stiffness, about E t) is its share of the automatic penalty.
        diagonal(b, e, model.X, [&](int n, int, double k) {
          stiffness[static_cast<size_t>(n)] = std::max(stiffness[static_cast<size_t>(n)], k);
        });
        if (edges)
          for (int a = 0; a < corners; ++a) {
            const auto key = std::minmax(en[a], en[(a + 1) % corners]);
            const auto [it, fresh] =
                edge_index[which].try_emplace({key.first, key.second}, edge_lists[which].size());
            if (fresh) edge_lists[which].push_back({key.first, key.second, h});
            Edge& ed = edge_lists[which][it->second];
            ed.half = std::max(ed.half, h);
          }
        for (int a : en) {
          half[which][static_cast<size_t>(a)] = std::max(half[which][static_cast<size_t>(a)], h);
          size[which][static_cast<size_t>(a)] = std::max(size[which][static_cast<size_t>(a)], sz);
          for (int c : en)
            if (c != a) near[static_cast<size_t>(a)].push_back(c);
        }
      }
    }
  };
  collect(parts, 0);
  if (!self) collect(other, 1);
  ring_start.assign(N + 1, 0);
  ring.clear();
  for (size_t n = 0; n < N; ++n) {
    auto& r = near[n];
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    ring.insert(ring.end(), r.begin(), r.end());
    ring_start[n + 1] = static_cast<int>(ring.size());
  }
  passes.clear();
  auto pass = [&](int nodes_of, int faces_of) {
    Pass p;
    p.faces = faces_of;
    for (size_t n = 0; n < N; ++n)
      if (half[nodes_of][n] >= 0) {
        p.nodes.push_back(static_cast<int>(n));
        p.half.push_back(half[nodes_of][n]);
        p.size.push_back(size[nodes_of][n]);
      }
    passes.push_back(std::move(p));
  };
  pass(0, self ? 0 : 1);
  if (!self) pass(1, 0);
}

void SheetContactTerm::start(const LoadState& s) {
  if (load_.friction > 0 || load_.edges) x_accepted_ = s.x;  // also after a restart
  if (started_) return;
  started_ = true;
  // Initial penetrations: reported, and with relax_steps relaxed (their depth an offset on
  // the gap that shrinks to zero over the first steps).
  scan(s.x, [&](size_t p, size_t i, const Pair& pair, double gap) {
    const size_t k = slot(p, i);
    pairs_[k] = pair;
    initial_.note(k, gap, load_.relax_steps);
  });
}

SheetContactTerm::SheetContactTerm(const SheetContact& load, const LoadSite& site)
    : load_(load), site_(site) {
  // The automatic penalty: the node's largest diagonal entry of its elements' reference
  // tangent (unconstrained: a node held in its plane keeps its sheet's stiffness), times
  // penalty_scale.
  size_t slots = 0;
  for (const Pass& p : load.passes) first_.push_back(slots), slots += p.nodes.size();
  k_.assign(slots, 0.0);
  for (size_t p = 0; p < load.passes.size(); ++p)
    for (size_t i = 0; i < load.passes[p].nodes.size(); ++i) {
      const double k = load.stiffness[static_cast<size_t>(load.passes[p].nodes[i])];
      if (!(k > 0))
        throw std::invalid_argument(fmt::format(
            "contact {}: a node of the sets has no stiffness at its reference to scale the "
            "penalty on",
            load.index));
      k_[slot(p, i)] = load.penalty_scale * k;
      reach_ = std::max(reach_, load.passes[p].half[i]);
      margin_ = std::max(margin_, load.passes[p].size[i]);
    }
  if (slots) {
    k_min_ = *std::min_element(k_.begin(), k_.end());
    k_max_ = *std::max_element(k_.begin(), k_.end());
  }
  pairs_.assign(slots, Pair{});
  block_guesses_.assign(slots, [] {
    std::array<int, 16> unknown;
    unknown.fill(-1);
    return unknown;
  }());
  initial_.resize(slots);
  gap_accepted_.assign(slots, std::numeric_limits<double>::quiet_NaN());
  transmitted_.assign(static_cast<size_t>(site.model.num_nodes()), 0.0);
  node_status_.assign(static_cast<size_t>(site.model.num_nodes()), 0.0);
  anchor_face_.assign(slots, -1);
  anchor_xi_.assign(slots, Vec2::Zero());
  last_x_.resize(slots);
  if (load.friction > 0 || load.edges) x_accepted_ = site.model.X;
  for (size_t p = 0; p < load.passes.size(); ++p)
    for (size_t i = 0; i < load.passes[p].nodes.size(); ++i)
      last_x_[slot(p, i)] = site.model.X.col(load.passes[p].nodes[i]);
  coupled_.resize(static_cast<size_t>(site.model.num_nodes()));
  for (int w = 0; w < 2; ++w) frames_[static_cast<size_t>(w)].resize(load.faces[w].size());
  if (load.edges) {
    const auto& B = load.edge_lists[load.self ? 0 : 1];
    edge_boxes_.resize(B.size());
    // A query asks at an edge's middle: the boxes grow by half the longest edge of the first
    // list.
    for (const Edge& e : load.edge_lists[0])
      edge_grow_ =
          std::max(edge_grow_, 0.5 * (site.model.X.col(e.b) - site.model.X.col(e.a)).norm());
  }
  // The skin: the least node contact thickness (a quarter of the least contact distance
  // between a node and a face may be crossed before a new candidate search), at most a tenth of
  // the least element size (the candidates grow with it).
  skin_ = std::numeric_limits<double>::infinity();
  for (const Pass& p : load.passes)
    for (size_t i = 0; i < p.nodes.size(); ++i)
      skin_ = std::min({skin_, p.half[i], 0.1 * p.size[i]});
  if (!(skin_ < std::numeric_limits<double>::infinity())) skin_ = 0;
  candidate_start_.assign(slots + 1, 0);
  x_candidates_.resize(slots);
  for (size_t w = 0; w < 2; ++w) {
    search_boxes_[w].resize(load.faces[w].size());
    for (size_t f = 0; f < load.faces[w].size(); ++f)
      search_boxes_[w][f] = face_box(site.model.X, load.faces[w][f], skin_);
    tree_[w].build(search_boxes_[w]);
  }
}

contact::Box SheetContactTerm::face_box(const NodePositions& x, const Face& f, double skin) const {
  // A node the search keeps is within reach of the face's plane (|g| < r) and projects inside
  // the face up to the barycentric slack: inside the face's prism ±r along its normal, grown
  // by the slack. Its box: the box of the face moved by ±r n (the reach along the normal
  // only: a flat sheet's faces then overlap their neighbours' boxes by the slack, not by an
  // element, and a query meets a few faces instead of tens).
  const Vec3 a = x.col(f.n[0]), bb = x.col(f.n[1]), c = x.col(f.n[2]);
  contact::Box b(a);
  b.extend(bb);
  b.extend(c);
  const double r = f.half + reach_ + margin_, size = b.sizes().maxCoeff();
  const Vec3 m = (bb - a).cross(c - a);
  const double area2 = m.norm();
  if (skin > 0) {
    // Every corner moved at most δ/2: the box's sides by δ/2, its largest size (the slack) by
    // δ, m by |Δm| ≤ δ (|b − a| + |c − a|) + δ², the unit normal by 2 |Δm| / |m|; the node
    // by δ/2. Padded by round-off.
    const double turn = area2 > 0
                            ? 2 * (skin * ((bb - a).norm() + (c - a).norm()) + skin * skin) / area2
                            : std::numeric_limits<double>::infinity();
    const double grow =
        2 * kInside * (size + skin) + skin + 1e-9 * (r + size) +
        1e-13 * std::max(b.min().cwiseAbs().maxCoeff(), b.max().cwiseAbs().maxCoeff());
    for (int j = 0; j < 3; ++j) {
      const double d = area2 > 0 ? std::min(r, r * (std::abs(m[j]) / area2 + turn)) : r;
      b.min()[j] -= d + grow;
      b.max()[j] += d + grow;
    }
    return b;
  }
  const double slack = 2 * kInside * size;
  if (area2 > 0) {
    const Vec3 d = (r / area2) * m.cwiseAbs();
    b.min() -= d;
    b.max() += d;
    b.min().array() -= slack;
    b.max().array() += slack;
  } else {  // degenerate: every direction
    b.min().array() -= r + slack;
    b.max().array() += r + slack;
  }
  return b;
}

void SheetContactTerm::fit_boxes(const NodePositions& x, size_t w, double skin,
                                 std::vector<contact::Box>& out) const {
  const auto& fs = load_.faces[w];
  const long faces = static_cast<long>(fs.size());
#pragma omp parallel for schedule(static) if (faces > kParallelSearch)
  for (long f = 0; f < faces; ++f)
    out[static_cast<size_t>(f)] = face_box(x, fs[static_cast<size_t>(f)], skin);
}

void SheetContactTerm::fit_frames(const NodePositions& x) {
  for (size_t w = 0; w < 2; ++w) {
    const auto& fs = load_.faces[w];
    const long faces = static_cast<long>(fs.size());
#pragma omp parallel for schedule(static) if (faces > kParallelSearch)
    for (long f = 0; f < faces; ++f) {
      const Face& face = fs[static_cast<size_t>(f)];
      FaceFrame& fr = frames_[w][static_cast<size_t>(f)];
      const Vec3 a = x.col(face.n[0]), u = x.col(face.n[1]) - a, v = x.col(face.n[2]) - a;
      const Vec3 m = u.cross(v);
      const double mm = m.squaredNorm();  // = |u|² |v|² − (u·v)², the metric's determinant
      if (!(mm > 0)) {
        fr.a = fr.d1 = fr.d2 = fr.n = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
        continue;
      }
      const double inv = 1 / mm;
      fr.a = a;
      fr.d1 = inv * v.cross(m);
      fr.d2 = inv * m.cross(u);
      fr.n = std::sqrt(inv) * m;
    }
  }
}

bool SheetContactTerm::moved_past_skin(const NodePositions& x) const {
  double most = 0;
  for (size_t p = 0; p < load_.passes.size(); ++p) {
    const Pass& pass = load_.passes[p];
    const long nodes = static_cast<long>(pass.nodes.size());
#pragma omp parallel for schedule(static) reduction(max : most) if (nodes > kParallelSearch)
    for (long i = 0; i < nodes; ++i)
      most = std::max(most, (x.col(pass.nodes[static_cast<size_t>(i)]) -
                             x_candidates_[slot(p, static_cast<size_t>(i))])
                                .squaredNorm());
  }
  return most > 0.25 * skin_ * skin_;
}

void SheetContactTerm::find_candidates(const NodePositions& x) {
  for (size_t w = 0; w < 2; ++w) {
    fit_boxes(x, w, skin_, search_boxes_[w]);
    if (!tree_[w].empty()) tree_[w].refit(search_boxes_[w]);
  }
  // Two sweeps of queries, in parallel: each slot's count, then (after their running sum) its
  // faces, so nothing is allocated per node.
  for (int sweep = 0; sweep < 2; ++sweep) {
    for (size_t p = 0; p < load_.passes.size(); ++p) {
      const Pass& pass = load_.passes[p];
      const auto& fs = load_.faces[static_cast<size_t>(pass.faces)];
      const contact::FaceTree& tree = tree_[static_cast<size_t>(pass.faces)];
      const long nodes = static_cast<long>(pass.nodes.size());
#pragma omp parallel for schedule(dynamic, 256) if (nodes > kParallelSearch)
      for (long ii = 0; ii < nodes; ++ii) {
        const size_t i = static_cast<size_t>(ii), k = slot(p, i);
        const int n = pass.nodes[i];
        const Vec3 y = x.col(n);
        if (sweep == 0) {
          int count = 0;
          tree.query(y, [&](int f) { count += excluded(n, fs[static_cast<size_t>(f)]) ? 0 : 1; });
          candidate_start_[k + 1] = count;
          x_candidates_[k] = y;
        } else {
          int at = candidate_start_[k];
          tree.query(y, [&](int f) {
            if (!excluded(n, fs[static_cast<size_t>(f)]))
              candidates_[static_cast<size_t>(at++)] = f;
          });
        }
      }
    }
    if (sweep == 0) {
      candidate_start_[0] = 0;
      for (size_t k = 0; k + 1 < candidate_start_.size(); ++k)
        candidate_start_[k + 1] += candidate_start_[k];
      candidates_.resize(static_cast<size_t>(candidate_start_.back()));
    }
  }
  have_candidates_ = true;
  ++candidate_searches_;
}

void SheetContactTerm::search(const NodePositions& x) {
  searched_at_ = nullptr;  // hits_ now from x
  // The candidates of the last candidate search while no node has moved past half the skin
  // since (they hold every face the search below can keep), else new ones; the exact tests
  // (the projection inside the face by its frame at x, the reach) run on them at every
  // evaluation.
  if (!have_candidates_ || moved_past_skin(x)) find_candidates(x);
  fit_frames(x);
  hits_.resize(pairs_.size());
  for (size_t p = 0; p < load_.passes.size(); ++p) {
    const Pass& pass = load_.passes[p];
    const auto& fs = load_.faces[static_cast<size_t>(pass.faces)];
    // The search in parallel (each node's faces read only), the pairs then taken in node
    // order by `found`, so the sums do not depend on the threads.
    const long nodes = static_cast<long>(pass.nodes.size());
#pragma omp parallel for schedule(dynamic, 256) if (nodes > kParallelSearch)
    for (long ii = 0; ii < nodes; ++ii) {
      const size_t i = static_cast<size_t>(ii);
      const int n = pass.nodes[i];
      const Vec3 y = x.col(n);
      const size_t k = slot(p, i);
      int best = -1;
      double best_g = 0, best_side = 1, best_abs = std::numeric_limits<double>::infinity();
      // The side at the last accepted state, carried to the faces about it by their normals:
      // a node that a Newton iteration (or a step) took through the face stays on its side.
      const Pair& was = pairs_[k];
      const auto& frames = frames_[static_cast<size_t>(pass.faces)];
      const Vec3 was_normal =
          was.face >= 0 ? frames[static_cast<size_t>(was.face)].n : Vec3::Zero().eval();
      for (int q = candidate_start_[k]; q < candidate_start_[k + 1]; ++q) {
        const int f = candidates_[static_cast<size_t>(q)];
        const FaceFrame& fr = frames[static_cast<size_t>(f)];
        const Vec3 r = y - fr.a;
        const double xi0 = r.dot(fr.d1), xi1 = r.dot(fr.d2);
        // Written so that a NaN (a degenerate face) fails.
        if (!(xi0 >= -kInside && xi1 >= -kInside && xi0 + xi1 <= 1 + kInside)) continue;
        const double g = r.dot(fr.n);
        double side = g >= 0 ? 1.0 : -1.0;
        if (was.face >= 0) side = fr.n.dot(was_normal) < 0 ? -was.side : was.side;
        // Within reach: the contact distance and, behind the face, an element more.
        const double reach = pass.half[i] + fs[static_cast<size_t>(f)].half + margin_;
        if (std::abs(g) >= reach) continue;
        // The face of the last accepted state while it still holds the node's projection
        // (the residual then stays smooth through a step), else the nearest, of two as near
        // the lower index (the pair does not depend on the candidates' order).
        if (f == was.face)
          best = f, best_g = g, best_side = side, best_abs = -1;
        else if (std::abs(g) < best_abs || (std::abs(g) == best_abs && f < best))
          best = f, best_g = g, best_side = side, best_abs = std::abs(g);
      }
      hits_[k] = {best, best_side, best_g};
    }
  }
}

template <class Found>
void SheetContactTerm::visit(Found&& found) {
  for (size_t p = 0; p < load_.passes.size(); ++p) {
    const Pass& pass = load_.passes[p];
    const auto& fs = load_.faces[static_cast<size_t>(pass.faces)];
    for (size_t i = 0; i < pass.nodes.size(); ++i) {
      const Hit& h = hits_[slot(p, i)];
      if (h.face < 0) continue;
      const Face& face = fs[static_cast<size_t>(h.face)];
      found(p, i, Pair{h.face, h.side}, h.side * h.g - pass.half[i] - face.half);
    }
  }
}

bool SheetContactTerm::update_couplings(const NodePositions& x) {
  search(x);
  if (load_.edges) search_edges(x);
  searched_at_ = x.data();  // after search(), which forgets it
  bool changed = false;
  if (prune_) {  // far more couplings than pairs within reach: only these
    for (auto& list : coupled_) list.clear();
    coupled_count_ = 0;
    prune_ = false;
    changed = true;
  }
  visit([&](size_t p, size_t i, const Pair& pair, double) {
    const Pass& pass = load_.passes[p];
    const Face& face = load_.faces[static_cast<size_t>(pass.faces)][static_cast<size_t>(pair.face)];
    for (int q : face.n) changed = couple(pass.nodes[i], q) || changed;
  });
  for (const EdgeHit& h : edge_hits_) {
    const Edge& e = load_.edge_lists[0][static_cast<size_t>(h.i)];
    const Edge& f = load_.edge_lists[load_.self ? 0 : 1][static_cast<size_t>(h.j)];
    for (int a : {e.a, e.b})
      for (int b : {f.a, f.b}) changed = couple(a, b) || changed;
  }
  if (changed) ++pattern_changes_;
  return changed;
}

void SheetContactTerm::add(const LoadState& s, LoadOutput& out) {
  // The search update_couplings made at these positions, or a new one.
  const bool searched = searched_at_ == s.x.data();
  searched_at_ = nullptr;
  if (!searched) search(s.x);
  contact::PairResult r;
  visit([&](size_t p, size_t i, const Pair& pair, double) {
    const Pass& pass = load_.passes[p];
    const size_t k = slot(p, i);
    const Face& face = load_.faces[static_cast<size_t>(pass.faces)][static_cast<size_t>(pair.face)];
    const int node = pass.nodes[i];
    const double c = pass.half[i] + face.half - relaxed(k);
    const contact::Vec12 X = coordinates(s.x, node, face);
    const std::array<int, 4> nodes = {node, face.n[0], face.n[1], face.n[2]};
    // A face held in full (a held sheet's): only the node's block is assembled, no Hessian.
    const bool face_held = held(face.n[0]) && held(face.n[1]) && held(face.n[2]);
    if (out.K) {
      if (face_held)
        prefetch_node_columns(site_.dofs, std::array<int, 1>{node}, *out.K);
      else
        prefetch_node_columns(site_.dofs, nodes, *out.K);
    }
    if (!contact::pair_force(X, pair.side, c, k_[k], out.K != nullptr, r, face_held)) return;
    if (load_.friction > 0) {
      Vec3 slip;
      contact::pair_friction(X, pair.side, c, k_[k], load_.friction,
                             anchor_on(k, face, pair.face, pass.faces), out.K != nullptr, r, slip);
    }
    for (int a = 0; a < 4; ++a) out.F.col(nodes[static_cast<size_t>(a)]) += r.f.segment<3>(3 * a);
    // K −= ∂f/∂X: the node's and the face's blocks (the mesh's pattern) and those between
    // them (the couplings).
    if (!out.K) return;
    if (!face_held)
      add_blocks(nodes, r.D, *out.K, &block_guesses_[k]);
    else if (!held(node)) {
      std::array<int, 1> guess = {block_guesses_[k][0]};
      subtract_node_blocks<1>(site_.dofs, {node}, r.D.topLeftCorner<3, 3>(), *out.K, &guess);
      block_guesses_[k][0] = guess[0];
    }
  });
  if (load_.edges) {
    if (!searched) search_edges(s.x);
    add_edges(out);
  }
}

void SheetContactTerm::commit(const LoadState& s) {
  penetration_ratio_ = 0;
  active_accepted_ = 0;
  force_on_other_.setZero();
  std::fill(gap_accepted_.begin(), gap_accepted_.end(), std::numeric_limits<double>::quiet_NaN());
  std::fill(transmitted_.begin(), transmitted_.end(), 0.0);
  std::fill(node_status_.begin(), node_status_.end(), 0.0);
  for (Pair& p : pairs_) p.face = -1;
  // Friction: the anchors as the step found them; every slot starts anew at its node unless
  // it is in contact.
  const std::vector<int> anchor_face = anchor_face_;
  const std::vector<Vec2> anchor_xi = anchor_xi_;
  const std::vector<Vec3> last_x = last_x_;
  std::fill(anchor_face_.begin(), anchor_face_.end(), -1);
  for (size_t p = 0; p < load_.passes.size(); ++p)
    for (size_t i = 0; i < load_.passes[p].nodes.size(); ++i)
      last_x_[slot(p, i)] = s.x.col(load_.passes[p].nodes[i]);
  contact::PairResult r;
  scan(s.x, [&](size_t p, size_t i, const Pair& pair, double gap) {
    const Pass& pass = load_.passes[p];
    const size_t k = slot(p, i);
    const Face& face = load_.faces[static_cast<size_t>(pass.faces)][static_cast<size_t>(pair.face)];
    pairs_[k] = pair;
    gap_accepted_[k] = gap;
    const double c = pass.half[i] + face.half - relaxed(k);
    const contact::Vec12 X = coordinates(s.x, pass.nodes[i], face);
    if (!contact::pair_force(X, pair.side, c, k_[k], false, r)) return;
    contact::Status status = contact::Status::kSlip;  // frictionless: slides
    if (load_.friction > 0) {
      anchor_face_[k] = anchor_face[k], anchor_xi_[k] = anchor_xi[k], last_x_[k] = last_x[k];
      const Vec2 xi0 = anchor_on(k, face, pair.face, pass.faces);
      Vec3 slip;
      status = contact::pair_friction(X, pair.side, c, k_[k], load_.friction, xi0, false, r, slip);
      // The anchor: the face's point at xi0 moved on by the slip.
      const Vec3 a = s.x.col(face.n[0]), b = s.x.col(face.n[1]), cc = s.x.col(face.n[2]);
      const Vec3 y = (1 - xi0[0] - xi0[1]) * a + xi0[0] * b + xi0[1] * cc + slip;
      anchor_face_[k] = pair.face;
      anchor_xi_[k] = contact::plane_coordinates(y, a, b, cc);
    }
    ++active_accepted_;
    const double st = static_cast<double>(status);
    node_status_[static_cast<size_t>(pass.nodes[i])] =
        std::max(node_status_[static_cast<size_t>(pass.nodes[i])], st);
    for (int q : face.n)
      node_status_[static_cast<size_t>(q)] = std::max(node_status_[static_cast<size_t>(q)], st);
    // Each node's share of the pair's force: the node's own and the face nodes'.
    transmitted_[static_cast<size_t>(pass.nodes[i])] += r.f.segment<3>(0).norm();
    for (int a = 0; a < 3; ++a)
      transmitted_[static_cast<size_t>(face.n[static_cast<size_t>(a)])] +=
          r.f.segment<3>(3 + 3 * a).norm();
    // The force the first set exerts on the second: on the second's faces (pass 0) and on
    // its nodes (pass 1). Self contact: the sum of the pairs' normal forces along +side·n.
    if (load_.self)
      force_on_other_ += r.f.segment<3>(0).cwiseAbs();
    else if (p == 0)
      force_on_other_ += r.f.segment<3>(3) + r.f.segment<3>(6) + r.f.segment<3>(9);
    else
      force_on_other_ += r.f.segment<3>(0);
    const double tol = std::max(0.01 * 2 * pass.half[i], 1e-3 * pass.size[i]);
    if (tol > 0) penetration_ratio_ = std::max(penetration_ratio_, (-gap - relaxed(k)) / tol);
  });
  commit_edges(s.x);
  peak_.note(penetration_ratio_, s.t);
  if (load_.friction > 0 || load_.edges) x_accepted_ = s.x;
  initial_.commit();
  // The couplings kept while pairs come and go, dropped (at the next Jacobian: a new
  // pattern) once they are four times those of the pairs within reach now and more than a
  // few hundred: the pattern changes rarely and stays within a small multiple of the need.
  long within = 0;
  for (const Hit& h : hits_) within += h.face >= 0 ? 3 : 0;
  within += 4 * static_cast<long>(edge_pairs_.size());
  prune_ = coupled_count_ > 4 * within + 600;
}

std::unique_ptr<LoadTerm> SheetContact::bind(const LoadSite& site) const {
  return std::make_unique<SheetContactTerm>(*this, site);
}

}  // namespace sheet_contact

std::unique_ptr<Load> make_sheet_contact(ContactLoad p) {
  return std::make_unique<sheet_contact::SheetContact>(std::move(p));
}

}  // namespace velum
