// Sheet–sheet and self contact (sheet_contact.hpp, docs/contact.md "Sheets"): every node of a
// set against the triangles (quads split in two) of the other set, or of its own set outside
// its two rings of elements, found through a box tree refitted at every evaluation; the pair's
// penalty force of face_contact.hpp. The node's own 3 x 3 block and the face's 9 x 9 block
// go into K (they are in the mesh's pattern); the node–face coupling (outside it) into the
// Jacobian's low-rank part, six columns per pair up to a budget.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <span>
#include <stdexcept>

#include "contact_law.hpp"
#include "edge_contact.hpp"
#include "face_contact.hpp"
#include "face_tree.hpp"
#include "sheet_contact.hpp"
#include "velum/assembly/assembler.hpp"
#include "velum/model/model.hpp"
#include "velum/parallel/processes.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum {
namespace {

struct Face {
  std::array<int, 3> n{};        ///< the triangle's nodes
  std::array<int, 4> element{};  ///< its element's corners (-1: none): never against these
  double half = 0;               ///< its contact thickness
};

// An element's side (edges: true): its two corners and its contact thickness.
struct Edge {
  int a = -1, b = -1;
  double half = 0;
};

// One direction of the contact: these nodes against those faces.
struct Pass {
  std::vector<int> nodes;    ///< model nodes
  std::vector<double> half;  ///< their contact thickness
  std::vector<double> size;  ///< element size about each (penetration tolerance)
  int faces = 0;             ///< which face list (0: the first set's, 1: the second's)
};

class SheetContact final : public Load, public ContactLoad {
 public:
  explicit SheetContact(ContactLoad p) : ContactLoad(std::move(p)) {}
  std::string_view kind() const override { return "contact"; }
  LoadOrder order() const override { return LoadOrder::kContact; }
  std::string_view counted_as() const override { return {}; }
  std::unique_ptr<Load> clone() const override { return std::make_unique<SheetContact>(*this); }
  std::unique_ptr<Load> held(double, const Model&, Model&) const override {
    auto h = std::make_unique<SheetContact>(*this);
    h->relax_steps = 0;  // a later step starts from the state the first one left
    return h;
  }
  void set_up(const Model& model, const ElementNamer&) override;
  bool keep_piece(const Model&, const std::vector<std::vector<int>>&,
                  const std::vector<int>&) override {
    throw std::invalid_argument(fmt::format(
        "contact {}: contact between element sets (or self contact) runs on one process only "
        "(docs/scaling.md)",
        index));
  }
  std::string summary(int) const override {
    size_t n = 0;
    for (const Pass& p : passes) n += p.nodes.size();
    return fmt::format("contact {}: {} nodes against {} faces{}", index, n,
                       faces[0].size() + faces[1].size(), self ? " (self)" : "");
  }
  std::unique_ptr<LoadTerm> bind(const LoadSite& site) const override;

  std::array<std::vector<Face>, 2> faces;
  std::array<std::vector<Edge>, 2> edge_lists;  ///< edges: true: each set's element sides
  std::vector<Pass> passes;
  std::vector<int> ring_start, ring;  ///< per model node: the nodes sharing an element with it
  std::vector<double> stiffness;      ///< per model node: the largest diagonal of its elements'
};

void SheetContact::set_up(const Model& model, const ElementNamer&) {
  const size_t N = static_cast<size_t>(model.num_nodes());
  std::vector<std::vector<int>> near(N);
  std::array<std::vector<double>, 2> half, size;
  stiffness.assign(N, 0.0);
  // The kernels store fixed-size Eigen blocks into these: aligned as Eigen wants.
  std::vector<double, Eigen::aligned_allocator<double>> r, Ke;
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
        // The element's reference tangent, unconstrained: each node's largest diagonal entry
        // (its in-plane stiffness, about E t) is its share of the automatic penalty.
        const size_t nd = static_cast<size_t>(b.dofs_per_element());
        r.assign(nd, 0.0), Ke.assign(nd * nd, 0.0);
        b.internal(std::span<const int>(&e, 1), model.X, r.data(), Ke.data());
        for (size_t a = 0; a < en.size(); ++a)
          for (size_t c = 3 * a; c < 3 * a + 3; ++c)
            stiffness[static_cast<size_t>(en[a])] =
                std::max(stiffness[static_cast<size_t>(en[a])], Ke[c * nd + c]);
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

// A node's pair: the face it is against and on which side.
struct Pair {
  int face = -1;
  double side = 1;
};

class SheetContactTerm final : public LoadTerm {
 public:
  SheetContactTerm(const SheetContact& load, const LoadSite& site);

  void add(const LoadState& s, LoadOutput& out) override;
  int low_rank_columns() const override { return 6 * budget_; }
  void start(const LoadState& s) override {
    if (load_.friction > 0 || load_.edges) x_accepted_ = s.x;  // also after a restart
    if (started_) return;
    started_ = true;
    // Initial penetrations: reported, and with relax_steps relaxed (their depth an offset on
    // the gap that shrinks to zero over the first steps).
    scan(s.x, [&](size_t p, size_t i, const Pair& pair, double gap) {
      const size_t k = slot(p, i);
      pairs_[k] = pair;
      if (gap < 0) {
        ++initial_count_;
        initial_depth_ = std::max(initial_depth_, -gap);
        if (load_.relax_steps > 0) offset_[k] = -gap;
      }
    });
  }
  void commit(const LoadState& s) override;
  // The pairs, the steps taken and the initial penetrations with their relaxation offsets
  // (a restart inside the relaxation goes on shrinking the same offsets).
  void save_state(std::vector<double>& out) const override {
    out.push_back(static_cast<double>(pairs_.size()));
    for (size_t k = 0; k < pairs_.size(); ++k)
      out.push_back(pairs_[k].face), out.push_back(pairs_[k].side), out.push_back(offset_[k]);
    if (load_.friction > 0)  // the friction anchors
      for (size_t k = 0; k < pairs_.size(); ++k) {
        out.push_back(anchor_face_[k]);
        out.insert(out.end(), anchor_xi_[k].data(), anchor_xi_[k].data() + 2);
        out.insert(out.end(), last_x_[k].data(), last_x_[k].data() + 3);
      }
    out.push_back(steps_);
    out.push_back(initial_count_);
    out.push_back(initial_depth_);
  }
  size_t restore_state(const std::vector<double>& in, size_t at) override {
    const size_t per = load_.friction > 0 ? 9 : 3;
    if (at >= in.size() || in[at] != static_cast<double>(pairs_.size()) ||
        in.size() < at + 4 + per * pairs_.size())
      throw std::invalid_argument("the sheet contact's saved state does not fit its nodes");
    ++at;
    for (size_t k = 0; k < pairs_.size(); ++k, at += 3)
      pairs_[k].face = static_cast<int>(in[at]), pairs_[k].side = in[at + 1],
      offset_[k] = in[at + 2];
    if (load_.friction > 0)
      for (size_t k = 0; k < pairs_.size(); ++k, at += 6) {
        anchor_face_[k] = static_cast<int>(in[at]);
        anchor_xi_[k] = Vec2(in[at + 1], in[at + 2]);
        last_x_[k] = Vec3(in[at + 3], in[at + 4], in[at + 5]);
      }
    steps_ = static_cast<int>(in[at++]);
    initial_count_ = static_cast<int>(in[at++]);
    initial_depth_ = in[at++];
    started_ = true;  // the state is the saved one, not a new start's
    return at;
  }
  std::optional<double> quantity(std::string_view name) const override {
    if (name.starts_with("contact_force") || name.starts_with("contact_area")) return 0.0;
    return {};
  }
  std::optional<double> quantity_at(std::string_view name, double,
                                    const NodePositions& x) const override {
    if (name == fmt::format("contact_area:contact={}", load_.index)) return contact_area(x);
    const auto last = name.rfind(':');
    if (last == std::string_view::npos ||
        name.substr(0, last) != fmt::format("contact_force:contact={}", load_.index))
      return {};
    const int c = name[last + 1] - '0';
    return c == 3 ? force_on_other_.norm() : force_on_other_[c];
  }
  bool node_field(std::string_view name, double t, const NodePositions& x,
                  std::vector<double>& per_node) const override;
  double max_stiffness_over_mass(std::span<const double> node_mass) const override {
    double most = 0;
    for (size_t p = 0; p < load_.passes.size(); ++p)
      for (size_t i = 0; i < load_.passes[p].nodes.size(); ++i)
        if (const double m = node_mass[static_cast<size_t>(load_.passes[p].nodes[i])]; m > 0)
          most = std::max(
              most, 2 * k_[slot(p, i)] * (1 + load_.friction) / m);  // the node and a face node
    return most;
  }
  std::string end_check(const std::function<void(std::string)>& warn) const override {
    if (initial_count_ > 0)
      warn(fmt::format("contact {}: {} initial penetrations, the deepest {:.4g}{}", load_.index,
                       initial_count_, initial_depth_,
                       load_.relax_steps > 0
                           ? fmt::format(" (relaxed over the first {} steps)", load_.relax_steps)
                           : std::string(" (pushed out at the first step)")));
    return contact::penetration_check(penetration_ratio_, fmt::format("contact {}", load_.index),
                                      "through a face, past the contact thickness", warn);
  }
  std::string account_json() const override {
    return fmt::format(
        "{{\"contact\": {}, \"sheets\": true, \"self\": {}, \"penalty\": [{:.6g}, {:.6g}], "
        "\"max_penetration_ratio\": {:.6g}, \"kept\": {}, \"initial_penetrations\": {}, "
        "\"initial_max_depth\": {:.6g}, \"active_pairs\": {}, \"pair_budget\": {}{}}}",
        load_.index, load_.self ? "true" : "false", k_min_, k_max_, penetration_ratio_,
        penetration_ratio_ <= 1 ? "true" : "false", initial_count_, initial_depth_,
        active_accepted_, budget_,
        load_.edges ? fmt::format(", \"active_edge_pairs\": {}", edge_active_) : std::string());
  }

 private:
  static constexpr double kInside = 1e-3;  // barycentric slack at the faces' edges
  size_t slot(size_t p, size_t i) const { return first_[p] + i; }
  contact::Vec12 coordinates(const NodePositions& x, int node, const Face& f) const {
    contact::Vec12 X;
    X << x.col(node), x.col(f.n[0]), x.col(f.n[1]), x.col(f.n[2]);
    return X;
  }
  bool excluded(int node, const Face& f) const {
    const int* r0 = load_.ring.data() + load_.ring_start[static_cast<size_t>(node)];
    const int* r1 = load_.ring.data() + load_.ring_start[static_cast<size_t>(node) + 1];
    for (int e : f.element) {
      if (e < 0) continue;
      if (e == node) return true;
      for (const int* r = r0; r != r1; ++r) {
        if (*r == e) return true;
        // Self contact: two rings (a face touching a neighbour of the node).
        if (load_.self) {
          const int* s0 = load_.ring.data() + load_.ring_start[static_cast<size_t>(*r)];
          const int* s1 = load_.ring.data() + load_.ring_start[static_cast<size_t>(*r) + 1];
          if (std::binary_search(s0, s1, e)) return true;
        }
      }
    }
    return false;
  }
  void refit(const NodePositions& x);
  // Edge pairs: calls found(i, j, X, side, thickness) for every pair of a first-list edge i
  // and a second-list edge j (self: j > i) away from each other's rings whose closest points
  // lie inside both and within reach.
  template <class Found>
  void scan_edges(const NodePositions& x, Found&& found);
  bool near(int n, int m) const {
    if (n == m) return true;
    const int* r0 = load_.ring.data() + load_.ring_start[static_cast<size_t>(n)];
    const int* r1 = load_.ring.data() + load_.ring_start[static_cast<size_t>(n) + 1];
    if (std::binary_search(r0, r1, m)) return true;
    if (load_.self)
      for (const int* r = r0; r != r1; ++r) {
        const int* s0 = load_.ring.data() + load_.ring_start[static_cast<size_t>(*r)];
        const int* s1 = load_.ring.data() + load_.ring_start[static_cast<size_t>(*r) + 1];
        if (std::binary_search(s0, s1, m)) return true;
      }
    return false;
  }
  void add_edges(const LoadState& s, LoadOutput& out);
  void commit_edges(const NodePositions& x);
  // A node's area: a third of its triangles' current areas (the faces of set `which`, or of
  // both sets: -1).
  std::vector<double> node_areas(const NodePositions& x, int which) const;
  double contact_area(const NodePositions& x) const;
  // Calls found(pass, node index, pair, gap) for every node that has a face within reach.
  template <class Found>
  void scan(const NodePositions& x, Found&& found);
  double relaxed(size_t k) const {
    if (offset_[k] <= 0 || load_.relax_steps <= 0) return 0.0;
    return offset_[k] * std::max(0.0, 1.0 - static_cast<double>(steps_ + 1) / load_.relax_steps);
  }
  void add_block(int i, int j, const Mat3& D, SparseMatrix& K) const;
  // Friction: slot k's anchor on `face` (barycentric coordinates of its b and c): the anchor's
  // face point carried to a new face, or the node's accepted position for a new pair, both
  // by the faces' accepted positions (so the anchor holds within a step: the tangent stays
  // consistent).
  Vec2 anchor_on(size_t k, const Face& face, int face_index, int faces_of) const {
    const NodePositions& x = x_accepted_;
    if (anchor_face_[k] == face_index) return anchor_xi_[k];
    Vec3 y = last_x_[k];
    if (anchor_face_[k] >= 0) {
      const Face& was =
          load_.faces[static_cast<size_t>(faces_of)][static_cast<size_t>(anchor_face_[k])];
      const Vec2& xi = anchor_xi_[k];
      y = (1 - xi[0] - xi[1]) * x.col(was.n[0]) + xi[0] * x.col(was.n[1]) + xi[1] * x.col(was.n[2]);
    }
    return contact::plane_coordinates(y, x.col(face.n[0]), x.col(face.n[1]), x.col(face.n[2]));
  }
  template <class Column>
  void put(int n, const Vec3& v, Column&& to) const {
    const Vec3 l = site_.dofs.to_local(n, v);
    for (int c = 0; c < 3; ++c)
      if (const int eq = site_.dofs.equation(n, c); eq >= 0) to[eq] += l[c];
  }

  const SheetContact& load_;
  LoadSite site_;
  std::vector<size_t> first_;  ///< per pass: its first slot
  std::vector<double> k_;      ///< per slot: the penalty
  std::vector<Pair> pairs_;    ///< per slot: the pair at the last accepted state
  std::vector<double> offset_, gap_accepted_;
  std::vector<double> transmitted_;  ///< per model node: the contact force it carries
  std::vector<int> anchor_face_;     ///< friction, per slot: the face of the anchor (-1: none)
  std::vector<Vec2> anchor_xi_;      ///< its barycentric coordinates of b and c
  std::vector<Vec3> last_x_;         ///< the node's accepted position (a new pair's anchor)
  NodePositions x_accepted_;         ///< friction, edges: the positions at the last accepted state
  // Edge pairs (edges: true): a tree over the second list's edges, and the side of each pair
  // (first list's edge, second's) at the last accepted state.
  contact::FaceTree edge_tree_;
  std::vector<contact::Box> edge_boxes_;
  std::map<std::pair<int, int>, double> edge_side_;
  double edge_grow_ = 0;
  int edge_active_ = 0;
  std::vector<double> node_status_;  ///< per model node: 0 open, 1 stick, 2 slip (accepted)
  std::array<contact::FaceTree, 2> tree_;
  std::array<std::vector<contact::Box>, 2> boxes_;
  double reach_ = 0;   ///< the largest node contact thickness
  double margin_ = 0;  ///< how far a node is followed past its contact distance (an element)
  int budget_ = 0;
  int steps_ = 0, initial_count_ = 0, active_accepted_ = 0;
  bool started_ = false;
  double initial_depth_ = 0, penetration_ratio_ = 0, k_min_ = 0, k_max_ = 0;
  Vec3 force_on_other_ = Vec3::Zero();
};

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
  offset_.assign(slots, 0.0);
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
  // The node–face coupling's columns: six a pair, for as many pairs as keep U and W within
  // about 32 MB (the pairs past it lose that coupling: Newton slows, the answer holds).
  const double per_column = 2.0 * 8.0 * std::max(1, site.dofs.num_equations());
  budget_ = static_cast<int>(std::min<double>(static_cast<double>(slots), 32e6 / per_column / 6));
  budget_ = std::max(budget_, std::min(static_cast<int>(slots), 8));
  for (int w = 0; w < 2; ++w) boxes_[static_cast<size_t>(w)].resize(load.faces[w].size());
  if (load.edges) {
    const auto& B = load.edge_lists[load.self ? 0 : 1];
    edge_boxes_.resize(B.size());
    // A query asks at an edge's middle: the boxes grow by half the longest edge of the first
    // list.
    for (const Edge& e : load.edge_lists[0])
      edge_grow_ =
          std::max(edge_grow_, 0.5 * (site.model.X.col(e.b) - site.model.X.col(e.a)).norm());
  }
  refit(site.model.X);
  for (int w = 0; w < 2; ++w) tree_[static_cast<size_t>(w)].build(boxes_[static_cast<size_t>(w)]);
}

void SheetContactTerm::refit(const NodePositions& x) {
  for (size_t w = 0; w < 2; ++w) {
    const auto& fs = load_.faces[w];
    for (size_t f = 0; f < fs.size(); ++f) {
      contact::Box b(x.col(fs[f].n[0]));
      b.extend(Vec3(x.col(fs[f].n[1])));
      b.extend(Vec3(x.col(fs[f].n[2])));
      const double grow = fs[f].half + reach_ + margin_ + 2 * kInside * b.sizes().maxCoeff();
      b.min().array() -= grow;
      b.max().array() += grow;
      boxes_[w][f] = b;
    }
    if (!tree_[w].empty()) tree_[w].refit(boxes_[w]);
  }
}

template <class Found>
void SheetContactTerm::scan(const NodePositions& x, Found&& found) {
  refit(x);
  for (size_t p = 0; p < load_.passes.size(); ++p) {
    const Pass& pass = load_.passes[p];
    const auto& fs = load_.faces[static_cast<size_t>(pass.faces)];
    for (size_t i = 0; i < pass.nodes.size(); ++i) {
      const int n = pass.nodes[i];
      const Vec3 y = x.col(n);
      const size_t k = slot(p, i);
      int best = -1;
      double best_g = 0, best_side = 1, best_abs = std::numeric_limits<double>::infinity();
      // The side at the last accepted state, carried to the faces about it by their normals:
      // a node that a Newton iteration (or a step) took through the face stays on its side.
      const Pair& was = pairs_[k];
      Vec3 was_normal = Vec3::Zero();
      if (was.face >= 0) {
        const Face& wf = fs[static_cast<size_t>(was.face)];
        was_normal = (x.col(wf.n[1]) - x.col(wf.n[0])).cross(x.col(wf.n[2]) - x.col(wf.n[0]));
      }
      tree_[static_cast<size_t>(pass.faces)].query(y, [&](int f) {
        const Face& face = fs[static_cast<size_t>(f)];
        if (excluded(n, face)) return;
        const Vec3 a = x.col(face.n[0]), b = x.col(face.n[1]), c = x.col(face.n[2]);
        const Vec2 xi = contact::plane_coordinates(y, a, b, c);
        if (xi[0] < -kInside || xi[1] < -kInside || xi.sum() > 1 + kInside) return;
        const Vec3 m = (b - a).cross(c - a);
        const double g = (y - a).dot(m) / m.norm();
        double side = g >= 0 ? 1.0 : -1.0;
        if (was.face >= 0) side = m.dot(was_normal) >= 0 ? was.side : -was.side;
        // Within reach: the contact distance and, behind the face, an element more.
        const double reach = pass.half[i] + face.half + margin_;
        if (std::abs(g) >= reach) return;
        // The face of the last accepted state while it still holds the node's projection
        // (the residual then stays smooth through a step), else the nearest.
        if (f == was.face)
          best = f, best_g = g, best_side = side, best_abs = -1;
        else if (std::abs(g) < best_abs)
          best = f, best_g = g, best_side = side, best_abs = std::abs(g);
      });
      if (best < 0) continue;
      const Face& face = fs[static_cast<size_t>(best)];
      found(p, i, Pair{best, best_side}, best_side * best_g - pass.half[i] - face.half);
    }
  }
}

void SheetContactTerm::add(const LoadState& s, LoadOutput& out) {
  MatX* U = out.K && out.low_rank && budget_ > 0 ? &out.low_rank->U : nullptr;
  MatX* W = U ? &out.low_rank->W : nullptr;
  if (U)
    for (int c = 0; c < 6 * budget_; ++c)
      U->col(out.column + c).setZero(), W->col(out.column + c).setZero();
  int used = 0;
  contact::PairResult r;
  scan(s.x, [&](size_t p, size_t i, const Pair& pair, double) {
    const Pass& pass = load_.passes[p];
    const size_t k = slot(p, i);
    const Face& face = load_.faces[static_cast<size_t>(pass.faces)][static_cast<size_t>(pair.face)];
    const int node = pass.nodes[i];
    const double c = pass.half[i] + face.half - relaxed(k);
    const contact::Vec12 X = coordinates(s.x, node, face);
    if (!contact::pair_force(X, pair.side, c, k_[k], out.K != nullptr, r)) return;
    if (load_.friction > 0) {
      Vec3 slip;
      contact::pair_friction(X, pair.side, c, k_[k], load_.friction,
                             anchor_on(k, face, pair.face, pass.faces), out.K != nullptr, r, slip);
    }
    const std::array<int, 4> nodes = {node, face.n[0], face.n[1], face.n[2]};
    for (int a = 0; a < 4; ++a) out.F.col(nodes[static_cast<size_t>(a)]) += r.f.segment<3>(3 * a);
    if (!out.K) return;
    // K −= ∂f/∂X: the node's block and the face's blocks in the pattern.
    add_block(node, node, r.D.block<3, 3>(0, 0), *out.K);
    for (int a = 1; a < 4; ++a)
      for (int b = 1; b < 4; ++b)
        add_block(nodes[static_cast<size_t>(a)], nodes[static_cast<size_t>(b)],
                  r.D.block<3, 3>(3 * a, 3 * b), *out.K);
    if (!U || used >= budget_) return;
    // The node–face coupling as U Wᵀ (stiffness −D): the rows of the node times the face's
    // columns, and the face's rows times the node's columns.
    const int col = out.column + 6 * used++;
    for (int c = 0; c < 3; ++c) {
      put(node, Vec3::Unit(c), U->col(col + c));
      put(node, Vec3::Unit(c), W->col(col + 3 + c));
      for (int a = 1; a < 4; ++a) {
        const int fa = nodes[static_cast<size_t>(a)];
        put(fa, Vec3(-r.D.block<1, 3>(c, 3 * a).transpose()), W->col(col + c));
        put(fa, Vec3(-r.D.block<3, 1>(3 * a, c)), U->col(col + 3 + c));
      }
    }
  });
  if (load_.edges) add_edges(s, out);
}

void SheetContactTerm::add_block(int i, int j, const Mat3& D, SparseMatrix& K) const {
  const int fi = site_.dofs.frame(i), fj = site_.dofs.frame(j);
  Mat3 A = -D;
  if (fi >= 0) A = site_.dofs.rotation(fi) * A;
  if (fj >= 0) A = A * site_.dofs.rotation(fj).transpose();
  for (int b = 0; b < 3; ++b) {
    const int cj = site_.dofs.equation(j, b);
    if (cj < 0) continue;
    for (int a = 0; a < 3; ++a)
      if (const int ri = site_.dofs.equation(i, a); ri >= 0 && A(a, b) != 0)
        K.coeffRef(ri, cj) += A(a, b);
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
  if (load_.friction > 0 || load_.edges) x_accepted_ = s.x;
  ++steps_;
}

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

std::vector<double> SheetContactTerm::node_areas(const NodePositions& x, int which) const {
  std::vector<double> area(static_cast<size_t>(x.cols()), 0.0);
  for (int w = 0; w < 2; ++w) {
    if (which >= 0 && w != which) continue;
    for (const Face& f : load_.faces[static_cast<size_t>(w)]) {
      const double A =
          (x.col(f.n[1]) - x.col(f.n[0])).cross(x.col(f.n[2]) - x.col(f.n[0])).norm() / 6;
      for (int n : f.n) area[static_cast<size_t>(n)] += A;
    }
  }
  return area;
}

double SheetContactTerm::contact_area(const NodePositions& x) const {
  // The first set's nodes that carry a contact force at the accepted state (as a node or as a
  // face's corner), each with its area; self contact touches with both layers: half of it.
  const std::vector<double> area = node_areas(x, 0);
  double sum = 0;
  for (int n : load_.passes[0].nodes)
    if (transmitted_[static_cast<size_t>(n)] > 0) sum += area[static_cast<size_t>(n)];
  return load_.self ? sum / 2 : sum;
}

bool SheetContactTerm::node_field(std::string_view name, double, const NodePositions& x,
                                  std::vector<double>& per_node) const {
  const bool pressure = name == "contact_pressure", status = name == "contact_status";
  if (!pressure && !status && name != "contact_gap") return false;
  const std::vector<double> area = pressure ? node_areas(x, -1) : std::vector<double>();
  for (size_t p = 0; p < load_.passes.size(); ++p)
    for (size_t i = 0; i < load_.passes[p].nodes.size(); ++i) {
      const size_t k = slot(p, i), n = static_cast<size_t>(load_.passes[p].nodes[i]);
      double& v = per_node[n];
      if (status) {
        // 0 open, 1 stick, 2 slip (frictionless pairs slide).
        const double s = node_status_[n];
        v = std::isnan(v) ? s : std::max(v, s);
      } else if (pressure) {
        // Once per node (self contact and shared nodes list a node in one pass only).
        v = (std::isnan(v) ? 0.0 : v) + (area[n] > 0 ? transmitted_[n] / area[n] : 0.0);
      } else if (!std::isnan(gap_accepted_[k])) {
        v = std::isnan(v) ? gap_accepted_[k] : std::min(v, gap_accepted_[k]);
      }
    }
  return true;
}

std::unique_ptr<LoadTerm> SheetContact::bind(const LoadSite& site) const {
  return std::make_unique<SheetContactTerm>(*this, site);
}

}  // namespace

std::unique_ptr<Load> make_sheet_contact(ContactLoad p) {
  return std::make_unique<SheetContact>(std::move(p));
}

}  // namespace velum
