// The sheet–sheet and self contact's load and its term (sheet_contact.hpp, docs/contact.md
// "Sheets"), shared by the files that implement the term: node to face
// (sheet_contact_load.cpp), edge to edge (sheet_contact_edges.cpp) and the outputs
// (sheet_contact_outputs.cpp). Private to src/load.
#pragma once

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <span>
#include <stdexcept>
#include <vector>

#include "contact_law.hpp"
#include "edge_contact.hpp"
#include "face_contact.hpp"
#include "face_tree.hpp"
#include "initial_penetrations.hpp"
#include "node_blocks.hpp"
#include "sheet_contact.hpp"
#include "velum/assembly/assembler.hpp"
#include "velum/model/model.hpp"
#include "velum/parallel/processes.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum::sheet_contact {

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

// A node's pair: the face it is against and on which side.
struct Pair {
  int face = -1;
  double side = 1;
};

// An edge pair at the last accepted state: its side and, with friction while it touched, its
// anchor (the material points s0 on the first edge and t0 on the second that touched).
struct EdgePair {
  double side = 1;
  bool anchored = false;
  Vec2 anchor = Vec2::Zero();
};

class SheetContactTerm final : public LoadTerm {
 public:
  SheetContactTerm(const SheetContact& load, const LoadSite& site);

  void add(const LoadState& s, LoadOutput& out) override;
  // The node–face pairs' couplings (a node with its face's nodes) and the edge pairs' (an
  // edge's nodes with the other's), of every pair within reach (not only those that touch):
  // kept while the pairs come and go, dropped when far more than the pairs within reach
  // (commit). The search made here is the one add() uses next.
  bool update_couplings(const NodePositions& x) override;
  void couplings(std::vector<std::array<int, 2>>& pairs) const override {
    for (size_t n = 0; n < coupled_.size(); ++n)
      for (int m : coupled_[n]) pairs.push_back({static_cast<int>(n), m});
  }
  void start(const LoadState& s) override;
  void commit(const LoadState& s) override;
  // The pairs, the steps taken and the initial penetrations with their relaxation offsets
  // (a restart inside the relaxation goes on shrinking the same offsets).
  void save_state(std::vector<double>& out) const override {
    out.push_back(static_cast<double>(pairs_.size()));
    for (size_t k = 0; k < pairs_.size(); ++k)
      out.push_back(pairs_[k].face), out.push_back(pairs_[k].side);
    if (load_.friction > 0)  // the friction anchors
      for (size_t k = 0; k < pairs_.size(); ++k) {
        out.push_back(anchor_face_[k]);
        out.insert(out.end(), anchor_xi_[k].data(), anchor_xi_[k].data() + 2);
        out.insert(out.end(), last_x_[k].data(), last_x_[k].data() + 3);
      }
    initial_.save(out);
    if (load_.edges) save_edges(out);
    peak_.save(out);
  }
  size_t restore_state(const std::vector<double>& in, size_t at) override {
    const size_t per = load_.friction > 0 ? 8 : 2;
    if (at >= in.size() || in[at] != static_cast<double>(pairs_.size()) ||
        in.size() < at + 1 + per * pairs_.size())
      throw std::invalid_argument("the sheet contact's saved state does not fit its nodes");
    ++at;
    for (size_t k = 0; k < pairs_.size(); ++k, at += 2)
      pairs_[k].face = static_cast<int>(in[at]), pairs_[k].side = in[at + 1];
    if (load_.friction > 0)
      for (size_t k = 0; k < pairs_.size(); ++k, at += 6) {
        anchor_face_[k] = static_cast<int>(in[at]);
        anchor_xi_[k] = Vec2(in[at + 1], in[at + 2]);
        last_x_[k] = Vec3(in[at + 3], in[at + 4], in[at + 5]);
      }
    at = initial_.restore(in, at);
    if (load_.edges) at = restore_edges(in, at);
    at = peak_.restore(in, at);
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
    initial_.warn(fmt::format("contact {}", load_.index), load_.relax_steps, warn);
    return contact::penetration_check(penetration_ratio_, peak_,
                                      fmt::format("contact {}", load_.index),
                                      "through a face, past the contact thickness", warn);
  }
  // The candidate searches (the trees' queries) made since construction; the other
  // evaluations reused the last one's candidates.
  int candidate_searches() const { return candidate_searches_; }
  std::string account_json() const override {
    return fmt::format(
        "{{\"contact\": {}, \"sheets\": true, \"self\": {}, \"penalty\": [{:.6g}, {:.6g}], "
        "\"max_penetration_ratio\": {:.6g}, \"kept\": {}, \"initial_penetrations\": {}, "
        "\"initial_max_depth\": {:.6g}, \"active_pairs\": {}, \"coupled_node_pairs\": {}, "
        "\"pattern_changes\": {}, \"peak_penetration_ratio\": {:.6g}, "
        "\"peak_penetration_time\": {:.6g}{}}}",
        load_.index, load_.self ? "true" : "false", k_min_, k_max_, penetration_ratio_,
        penetration_ratio_ <= 1 ? "true" : "false", initial_.count(), initial_.depth(),
        active_accepted_, coupled_count_, pattern_changes_, peak_.ratio, peak_.time,
        load_.edges ? fmt::format(", \"active_edge_pairs\": {}", edge_active_) : std::string());
  }

 private:
  static constexpr double kInside = 1e-3;  // barycentric slack at the faces' edges
  // Nodes of a pass above which its search runs in parallel (below, threads cost more).
  static constexpr long kParallelSearch = 2048;
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
  // Face f's box at x (docs/contact.md "Search"): a node that the search keeps is inside it.
  // With skin δ > 0, a box that also holds any such node after every node has moved at most
  // δ/2: grown by δ (the face's corners and the node), the slack's growth and the turn of the
  // face's normal that such moves allow (|Δn̂| ≤ 2 |Δm| / |m|, m the face's doubled area
  // vector), so the faces it finds are candidates for every evaluation until a node has moved
  // more than δ/2.
  contact::Box face_box(const NodePositions& x, const Face& f, double skin) const;
  // Each face's plane at x into frames_, for the exact test of every evaluation.
  void fit_frames(const NodePositions& x);
  // Side w's face boxes at x grown by `skin` into out (sized to the faces).
  void fit_boxes(const NodePositions& x, size_t w, double skin,
                 std::vector<contact::Box>& out) const;
  // The candidates at x: the trees refitted to the faces' boxes grown by skin_, each slot's
  // faces (outside its excluded rings) into candidates_, and x kept as x_candidates_.
  void find_candidates(const NodePositions& x);
  // Whether some node of the passes (they hold every face's corners) is more than skin_/2
  // from where the last candidate search saw it.
  bool moved_past_skin(const NodePositions& x) const;
  // Edge pairs: calls found(i, j, X, pair, thickness) for every pair of a first-list edge i
  // and a second-list edge j (self: j > i) away from each other's rings whose closest points
  // lie inside both and within reach; `pair` the state it had at the last accepted state (a
  // new pair: the side its edges had there, not anchored).
  template <class Found>
  void scan_edges(const NodePositions& x, Found&& found);
  // An edge pair's force (and tangent), with its friction from its anchor (a new pair's: the
  // closest points at the last accepted state); `keep` and the status as edge_friction's.
  contact::Status edge_force(int i, int j, const contact::Vec12& X, const EdgePair& pair,
                             double thickness, bool tangent, contact::PairResult& r, Vec2& anchor,
                             double& keep) const;
  void save_edges(std::vector<double>& out) const;
  size_t restore_edges(const std::vector<double>& in, size_t at);
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
  // The edge pairs of edge_hits_: their forces and matrix blocks.
  void add_edges(LoadOutput& out);
  void commit_edges(const NodePositions& x);
  // A node's area: a third of its triangles' current areas (the faces of set `which`, or of
  // both sets: -1).
  std::vector<double> node_areas(const NodePositions& x, int which) const;
  double contact_area(const NodePositions& x) const;
  // Calls found(pass, node index, pair, gap) for every node that has a face within reach:
  // search (the faces, into hits_), then visit (the hits in node order).
  template <class Found>
  void scan(const NodePositions& x, Found&& found) {
    search(x);
    visit(found);
  }
  void search(const NodePositions& x);
  template <class Found>
  void visit(Found&& found);
  // The edge pairs within reach at x (scan_edges) into edge_hits_.
  void search_edges(const NodePositions& x);
  // Couples nodes n and m in the Jacobian's pattern (update_couplings); true when new.
  bool couple(int n, int m) {
    // A node held in every direction has no equations: no entry to make room for.
    if (n == m || held(n) || held(m)) return false;
    if (n > m) std::swap(n, m);
    auto& list = coupled_[static_cast<size_t>(n)];
    if (std::find(list.begin(), list.end(), m) != list.end()) return false;
    list.push_back(m);
    ++coupled_count_;
    return true;
  }
  double relaxed(size_t k) const { return initial_.relaxed(k, load_.relax_steps); }
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
  // Whether node n has no equation (held in every direction).
  bool held(int n) const {
    const int* e = site_.dofs.equations() + 3 * static_cast<size_t>(n);
    return e[0] < 0 && e[1] < 0 && e[2] < 0;
  }
  // K −= D (a pair's 12 x 12 matrix ∂f/∂X over its four nodes) as sixteen node blocks;
  // `guesses`: where the blocks were for this pair's slot the last time (subtract_node_blocks).
  void add_blocks(const std::array<int, 4>& nodes, const contact::Mat12& D, SparseMatrix& K,
                  std::array<int, 16>* guesses = nullptr) const {
    subtract_node_blocks<4>(site_.dofs, nodes, D, K, guesses);
  }

  const SheetContact& load_;
  LoadSite site_;
  std::vector<size_t> first_;  ///< per pass: its first slot
  std::vector<double> k_;      ///< per slot: the penalty
  std::vector<Pair> pairs_;    ///< per slot: the pair at the last accepted state
  // Per slot: the face scan() found (-1: none), the side and the signed distance to it.
  struct Hit {
    int face = -1;
    double side = 1, g = 0;
  };
  std::vector<Hit> hits_;
  // Per slot: where its pair's node blocks were in K at the last evaluation (the pair keeps
  // its face and K its pattern over most evaluations: then the scatter searches nothing).
  std::vector<std::array<int, 16>> block_guesses_;
  std::vector<double> gap_accepted_;
  contact::InitialPenetrations initial_;  // per slot
  std::vector<double> transmitted_;       ///< per model node: the contact force it carries
  std::vector<int> anchor_face_;          ///< friction, per slot: the face of the anchor (-1: none)
  std::vector<Vec2> anchor_xi_;           ///< its barycentric coordinates of b and c
  std::vector<Vec3> last_x_;              ///< the node's accepted position (a new pair's anchor)
  NodePositions x_accepted_;  ///< friction, edges: the positions at the last accepted state
  // Edge pairs (edges: true): a tree over the second list's edges, and each pair (first
  // list's edge, second's) at the last accepted state.
  contact::FaceTree edge_tree_;
  std::vector<contact::Box> edge_boxes_;
  std::map<std::pair<int, int>, EdgePair> edge_pairs_;
  double edge_grow_ = 0;
  int edge_active_ = 0;
  // An edge pair within reach (search_edges): its edges, coordinates, state and thickness.
  struct EdgeHit {
    int i = 0, j = 0;
    contact::Vec12 X;
    EdgePair pair;
    double thickness = 0;
  };
  std::vector<EdgeHit> edge_hits_;
  // The couplings in the Jacobian's pattern: per model node n, the nodes m > n coupled with
  // it (update_couplings); their number; whether commit found them far more than needed.
  std::vector<std::vector<int>> coupled_;
  long coupled_count_ = 0;
  int pattern_changes_ = 0;
  bool prune_ = false;
  // update_couplings searched at these positions (their data): add() at the same reuses it.
  const double* searched_at_ = nullptr;
  std::vector<double> node_status_;  ///< per model node: 0 open, 1 stick, 2 slip (accepted)
  std::array<contact::FaceTree, 2> tree_;
  // A face's plane at the evaluation: its first corner a, the dual basis d1, d2 of its sides
  // b − a, c − a (a point's barycentric coordinates of b and c are (y − a)·d1, (y − a)·d2)
  // and its unit normal: the exact test of a candidate is three dot products, where solving
  // the face's 2 x 2 metric per candidate made most of the search's time (a node meets
  // about six faces about it). A degenerate face's frame is NaN: no test accepts it.
  struct FaceFrame {
    Vec3 a, d1, d2, n;
  };
  std::array<std::vector<FaceFrame>, 2> frames_;
  // The candidates (a Verlet list): the trees' boxes grown by the skin, per slot its faces
  // (slot k's: candidates_[candidate_start_[k]] up to candidate_start_[k + 1]) and the nodes'
  // positions at the last candidate search (per slot).
  std::array<std::vector<contact::Box>, 2> search_boxes_;
  std::vector<int> candidate_start_, candidates_;
  std::vector<Vec3> x_candidates_;
  bool have_candidates_ = false;
  int candidate_searches_ = 0;
  double skin_ = 0;    ///< δ: the least node contact thickness, at most a tenth of an element
  double reach_ = 0;   ///< the largest node contact thickness
  double margin_ = 0;  ///< how far a node is followed past its contact distance (an element)
  int active_accepted_ = 0;
  bool started_ = false;
  double penetration_ratio_ = 0, k_min_ = 0, k_max_ = 0;
  contact::PeakPenetration peak_;  // the largest penetration_ratio_ since the start, and when
  Vec3 force_on_other_ = Vec3::Zero();
};

}  // namespace velum::sheet_contact
