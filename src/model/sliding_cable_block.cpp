// The sliding cable block: each element is one chain (docs/cables.md), its node count the
// chain's; the block's shape row is made for that count (a VTK poly-line in frames). Without
// friction one force acts along the chain; with it, each segment's own, the slips at the
// interior nodes committed at accepted states (the law-history seam of ElementBlock).
#include <fmt/format.h>

#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>

#include "velum/element/sliding_cable.hpp"
#include "velum/element/sliding_cable_friction.hpp"
#include "velum/model/element_block.hpp"

namespace velum {
namespace {

// Rows for chains of k nodes, made once per k (blocks keep a pointer to their row).
const shape::ShapeInfo& chain_shape(int k) {
  static std::mutex mutex;
  static std::map<int, std::unique_ptr<shape::ShapeInfo>> rows;
  const std::lock_guard lock(mutex);
  auto& row = rows[k];
  if (!row) {
    row = std::make_unique<shape::ShapeInfo>();
    row->name = "sliding_cable";
    row->dimension = 1;
    row->shape = 5;  // never reached through with_shape: find() does not list it
    row->nodes = k;
    row->corners = 2;
    row->vtk = 4;  // VTK_POLY_LINE
    row->lumping = shape::Lumping::kRowSum;
  }
  return *row;
}

class SlidingCableBlock final : public ElementBlock, public SlidingChains {
 public:
  SlidingCableBlock(std::string set, int chain_nodes, std::vector<int> conn, const NodePositions& X,
                    const CableLaw& law, double density, double area, BlockSetupReport& report,
                    const SlidingCableSection& section, bool stabilized = false)
      : ElementBlock(chain_shape(chain_nodes), std::move(set), std::move(conn), density),
        law_(law),
        area_(area),
        section_(section),
        stabilized_(stabilized) {
    const int ne = size();
    const int k = nodes_per_element();
    segments_.resize(static_cast<size_t>(ne) * static_cast<size_t>(k - 1));
    L0_.resize(static_cast<size_t>(ne));
    for (int e = 0; e < ne; ++e) {
      const auto n = nodes(e);
      double L = 0, shortest = std::numeric_limits<double>::infinity();
      for (int j = 0; j + 1 < k; ++j) {
        const double lj = (X.col(n[j + 1]) - X.col(n[j])).norm();
        segments_[static_cast<size_t>(e * (k - 1) + j)] = lj;
        L += lj;
        shortest = std::min(shortest, lj);
      }
      L0_[static_cast<size_t>(e)] = L;
      if (e == 0 || shortest < report.worst_jacobian) {
        report.worst_jacobian = shortest;
        report.worst_element = e;
      }
    }
    if (section_.friction > 0) slips_.assign(static_cast<size_t>(ne) * (k - 2), 0.0);
    set_time(0);
  }

  const SlidingChains* sliding() const override { return this; }
  bool changes_in_time() const override {
    return section_.reefing || section_.cut_time < std::numeric_limits<double>::infinity();
  }
  void set_time(double t) override {
    g_ = section_.reefing ? (*section_.reefing)(t) : 1.0;
    cut_ = t >= section_.cut_time;
  }

  bool prestressed() const override { return law_.S0 != 0; }
  std::unique_ptr<ElementBlock> rebuilt(std::vector<int> connectivity, const NodePositions& X,
                                        double stabilizer,
                                        std::span<const int> listed) const override {
    BlockSetupReport report;
    const bool any = !connectivity.empty();
    // Form finding lays a prestressed cable in its sleeves at the shape it finds: its prestress
    // one force along the chain, held by a stabilizer per segment (E A = stabilizer times the
    // force, as a cable2's), nothing slipped, reefed or cut yet: friction, reefing and the cut
    // act in the analyses that follow (stabilizer 0).
    const bool stabilized = stabilizer > 0 && law_.S0 > 0;
    CableLaw law = law_;
    if (stabilized) law.E = stabilizer * law_.S0;
    auto out = std::make_unique<SlidingCableBlock>(
        set_name(), nodes_per_element(), std::move(connectivity), X, law, density(), area_, report,
        stabilized ? SlidingCableSection{} : section_, stabilized);
    if (any && !(report.worst_jacobian > 0))
      throw std::invalid_argument(
          fmt::format("sliding_cable element {} of set '{}' has a zero-length segment on the new "
                      "reference",
                      element_number(report.worst_element, listed), set_name()));
    return out;
  }

  void internal(std::span<const int> elements, const NodePositions& x, double* r,
                double* K) const override {
    const int nd = dofs_per_element();
    for (size_t i = 0; i < elements.size(); ++i) {
      const int e = elements[i];
      sliding_cable::VectorMap re(r + i * nd, nd);
      std::optional<sliding_cable::MatrixMap> Ke;
      if (K) Ke.emplace(K + i * nd * nd, nd, nd);
      if (cut_) {  // a cut line carries nothing
        re.setZero();
        if (Ke) Ke->setZero();
        continue;
      }
      const Chain& xe = gather(x, e);
      if (stabilized_) {
        sliding_cable::stabilized_force_tangent(xe, reference_segments(e), area_, law_.S0, law_.E,
                                                re, Ke ? &*Ke : nullptr);
      } else if (section_.friction > 0) {
        FrictionScratch& w = scratch();
        sliding_cable::friction_force_tangent(xe, friction_chain(e), area_, law_, re,
                                              Ke ? &*Ke : nullptr, w.slips, w.work);
      } else {
        sliding_cable::force_tangent(xe, g_ * L0(e), area_, law_, re, Ke ? &*Ke : nullptr);
      }
    }
  }
  // Each segment's consistent mass ρ A L0_j / 6 [[2, 1], [1, 2]]: row sums put half of it
  // on each of its ends.
  void mass(int e, double* M) const override {
    const int k = nodes_per_element();
    Eigen::Map<Eigen::MatrixXd> out(M, k, k);
    out.setZero();
    for (int j = 0; j + 1 < k; ++j) {
      const double m = density() * area_ * segment(e, j) / 6;
      out(j, j) += 2 * m, out(j + 1, j + 1) += 2 * m;
      out(j, j + 1) += m, out(j + 1, j) += m;
    }
  }
  void tension_stiffness(int e, double* T) const override {
    const int k = nodes_per_element();
    Eigen::Map<Eigen::MatrixXd> out(T, k, k);
    out.setZero();
    for (int j = 0; j + 1 < k; ++j) {
      const double c = area_ / segment(e, j);
      out(j, j) += c, out(j + 1, j + 1) += c;
      out(j, j + 1) -= c, out(j + 1, j) -= c;
    }
  }
  double measure(int e) const override { return L0(e); }
  double strain_energy(std::span<const int> elements, const NodePositions& x) const override {
    double U = 0;
    if (cut_) return U;
    for (int e : elements)
      U += stabilized_ ? sliding_cable::stabilized_strain_energy(
                             gather(x, e), reference_segments(e), area_, law_.S0, law_.E)
           : section_.friction > 0
               ? sliding_cable::friction_strain_energy(gather(x, e), friction_chain(e), area_, law_,
                                                       scratch().work)
               : sliding_cable::strain_energy(gather(x, e), g_ * L0(e), area_, law_);
    return U;
  }
  int first_inverted(std::span<const int> elements, const NodePositions& from,
                     const NodePositions& to) const override {
    for (int e : elements) {
      const auto n = nodes(e);
      for (size_t j = 0; j + 1 < n.size(); ++j)
        if (!((from.col(n[j + 1]) - from.col(n[j])).dot(to.col(n[j + 1]) - to.col(n[j])) > 0))
          return e;
    }
    return -1;
  }
  void keep_only(std::span<const int> elements) override {
    const size_t s = static_cast<size_t>(nodes_per_element() - 1);
    std::vector<double> seg, L0;
    for (int e : elements) {
      const size_t at = static_cast<size_t>(slot(e));
      seg.insert(seg.end(), segments_.begin() + static_cast<long>(at * s),
                 segments_.begin() + static_cast<long>((at + 1) * s));
      L0.push_back(L0_[at]);
    }
    std::vector<double> slips;
    for (int e : elements) {
      const auto c = committed(e);
      slips.insert(slips.end(), c.begin(), c.end());
    }
    segments_ = std::move(seg);
    L0_ = std::move(L0);
    if (!slips_.empty()) slips_ = std::move(slips);
    set_kept(elements);
  }
  // The mean force along the chain (each segment's force weighted by its length); one force
  // without friction.
  ElementOutput output(int e, const NodePositions& x) const override {
    ElementOutput out;
    if (cut_) return out;
    out.cable_force = stabilized_ ? sliding_cable::stabilized_mean_force(
                                        gather(x, e), reference_segments(e), area_, law_.S0, law_.E)
                      : section_.friction > 0
                          ? sliding_cable::friction_mean_force(gather(x, e), friction_chain(e),
                                                               area_, law_, scratch().work)
                          : sliding_cable::true_force(gather(x, e), g_ * L0(e), area_, law_);
    return out;
  }
  double slip(int e, int j, const NodePositions& x) const override {
    FrictionScratch& w = scratch();
    w.slips.resize(static_cast<size_t>(nodes_per_element() - 2));
    if (section_.friction == 0) {
      sliding_cable::frictionless_slips(gather(x, e), reference_segments(e), w.slips);
    } else if (cut_) {
      const auto c = committed(e);
      std::copy(c.begin(), c.end(), w.slips.begin());
    } else {
      sliding_cable::solve_slips(gather(x, e), friction_chain(e), area_, law_, w.slips, w.work);
    }
    return w.slips[static_cast<size_t>(j - 1)];
  }

  // With friction, the slips at the interior nodes (k − 2 per chain) are the history: the
  // forces are evaluated from those committed at the last accepted state.
  size_t history_size() const override { return slips_.size(); }
  size_t history_per_element() const override {
    return section_.friction > 0 ? static_cast<size_t>(nodes_per_element() - 2) : 0;
  }
  void commit_history(const NodePositions& x) override {
    if (cut_ || slips_.empty()) return;
    FrictionScratch& w = scratch();
    for (int e = 0; e < size(); ++e) {
      if (!holds(e)) continue;
      if (!sliding_cable::solve_slips(gather(x, e), friction_chain(e), area_, law_, w.slips,
                                      w.work))
        continue;  // keeps the last state (an accepted state has converged slips)
      const auto at = static_cast<std::ptrdiff_t>(slot(e) * (nodes_per_element() - 2));
      std::copy(w.slips.begin(), w.slips.end(), slips_.begin() + at);
    }
  }
  void save_history(std::vector<double>& out) const override {
    out.insert(out.end(), slips_.begin(), slips_.end());
  }
  size_t restore_history(const std::vector<double>& in, size_t at) override {
    if (at + slips_.size() > in.size())
      throw std::invalid_argument(
          fmt::format("the saved slips of sliding cable set '{}' are cut short", set_name()));
    std::copy(in.begin() + static_cast<std::ptrdiff_t>(at),
              in.begin() + static_cast<std::ptrdiff_t>(at + slips_.size()), slips_.begin());
    return at + slips_.size();
  }

 private:
  using Chain = Eigen::Matrix<double, 3, Eigen::Dynamic>;
  // The chain's positions in a buffer per thread: it grows to the longest chain once and the
  // force loop allocates nothing after that. The reference is valid until the next gather.
  const Chain& gather(const NodePositions& x, int e) const {
    const auto n = nodes(e);
    thread_local Chain out;
    out.resize(3, static_cast<Eigen::Index>(n.size()));
    for (size_t j = 0; j < n.size(); ++j) out.col(static_cast<Eigen::Index>(j)) = x.col(n[j]);
    return out;
  }
  // Per thread: the friction solve's scratch and a chain's slips.
  struct FrictionScratch {
    sliding_cable::FrictionWork work;
    std::vector<double> slips;
  };
  FrictionScratch& scratch() const {
    thread_local FrictionScratch w;
    w.slips.resize(static_cast<size_t>(nodes_per_element() - 2));
    return w;
  }
  std::span<const double> reference_segments(int e) const {
    const auto s = static_cast<size_t>(nodes_per_element() - 1);
    return {segments_.data() + static_cast<size_t>(slot(e)) * s, s};
  }
  std::span<const double> committed(int e) const {
    if (slips_.empty()) return {};
    const auto s = static_cast<size_t>(nodes_per_element() - 2);
    return {slips_.data() + static_cast<size_t>(slot(e)) * s, s};
  }
  sliding_cable::FrictionChain friction_chain(int e) const {
    return {reference_segments(e), committed(e), section_.friction, g_};
  }
  double L0(int e) const { return L0_[static_cast<size_t>(slot(e))]; }
  double segment(int e, int j) const {
    return segments_[static_cast<size_t>(slot(e) * (nodes_per_element() - 1) + j)];
  }

  CableLaw law_;
  double area_;
  SlidingCableSection section_;
  std::vector<double> segments_;  // reference segment lengths, k − 1 per element
  std::vector<double> L0_;        // reference length of each chain
  std::vector<double> slips_;     // with friction: committed slips, k − 2 per element
  double g_ = 1;                  // the reefing factor at the time set
  bool cut_ = false;              // the line cut at the time set
  bool stabilized_ = false;       // form finding's chain (rebuilt with a stabilizer)
};

}  // namespace

std::unique_ptr<ElementBlock> make_sliding_cable_block(std::string set_name, int chain_nodes,
                                                       std::vector<int> connectivity,
                                                       const NodePositions& X, const CableLaw& law,
                                                       double density, double area,
                                                       BlockSetupReport& report,
                                                       const SlidingCableSection& section) {
  if (chain_nodes < 3)
    throw std::invalid_argument(
        "a sliding_cable runs through at least 3 nodes (2 segments); use a cable2 element for "
        "one segment");
  if (!(section.friction >= 0))
    throw std::invalid_argument("a sliding_cable's friction coefficient must be >= 0");
  return std::make_unique<SlidingCableBlock>(std::move(set_name), chain_nodes,
                                             std::move(connectivity), X, law, density, area, report,
                                             section);
}

}  // namespace velum
