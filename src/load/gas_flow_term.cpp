// Gas chambers with gas flow: the chambers joined by orifices form a group whose gas state one
// gas::Network integrates; the group's first chamber (in the model's order, so the first of it
// to be added at each evaluation) measures every member's volume and leaking areas and solves
// the group, and each member then loads its walls with its own pressure.
//
// Jacobian: f_i = (p_i − p_a) ∂V_i/∂x with p_i = p_i(V_1.., A_1..), so
// ∂(−f_i)/∂x = −(p_i − p_a) ∂²V_i/∂x² − a_i (∂p_i/∂x)ᵀ, ∂p_i/∂x = Σ_j ∂p_i/∂V_j a_j +
// Σ_k ∂p_i/∂A_k b_k (a = ∂V/∂x, b = ∂A/∂x): the first term into the sparse matrix, the second
// one low-rank column per chamber (U = −a_i, W = ∂p_i/∂x).
#include "gas_flow_term.hpp"

#include "chamber_surface.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "velum/assembly/assembler.hpp"
#include "velum/element/enclosed_volume.hpp"
#include "velum/model/model.hpp"
#include "velum/parallel/processes.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

class GasFlowTerm;

// Chambers joined by orifices, and what their first member found at the last evaluation.
struct Group {
  std::vector<GasFlowTerm*> members;
  std::unique_ptr<gas::Network> net;
  std::vector<double> V, A, inflow, inflow_T;
  gas::Solution solution;
  std::vector<VecX> a_eq, b_eq;  // ∂V_j/∂x, ∂A_k/∂x as equation vectors (with a Jacobian)
  gas::Inputs inputs() const { return {V, A, inflow, inflow_T}; }
};

class GasFlowTerm final : public LoadTerm {
 public:
  GasFlowTerm(const GasLoad& load, const LoadSite& site)
      : load_(load), site_(site), walls_(load.parts, site) {
    for (const auto& leak : load.leaks) leaks_.emplace_back(leak.parts, site);
  }

  int low_rank_columns() const override { return 1; }

  void connect(std::span<LoadTerm* const> all, int self) override {
    if (group_) return;  // joined by a chamber before it
    // The gas chambers in their order (the index the orifices and history entries use).
    std::vector<LoadTerm*> chambers;
    for (LoadTerm* t : all)
      if (t->quantity("gas_volume")) chambers.push_back(t);
    auto flow_term = [&](int chamber) -> GasFlowTerm* {
      if (chamber < 0 || chamber >= static_cast<int>(chambers.size())) return nullptr;
      return dynamic_cast<GasFlowTerm*>(chambers[static_cast<size_t>(chamber)]);
    };
    // The group: every chamber reached through orifices (listed on either side).
    auto group = std::make_shared<Group>();
    group->members.push_back(this);
    for (size_t k = 0; k < group->members.size(); ++k) {
      GasFlowTerm* m = group->members[k];
      auto join = [&](GasFlowTerm* other) {
        if (other &&
            std::find(group->members.begin(), group->members.end(), other) == group->members.end())
          group->members.push_back(other);
      };
      for (const auto& o : m->load_.orifices) {
        GasFlowTerm* other = flow_term(o.chamber);
        if (!other)
          throw std::invalid_argument(fmt::format(
              "an orifice joins a gas chamber to gas load {}, which is not a chamber with gas "
              "flow (temperature and gas_constant)",
              o.chamber));
        join(other);
      }
      for (LoadTerm* t : chambers)
        if (auto* other = dynamic_cast<GasFlowTerm*>(t))
          for (const auto& o : other->load_.orifices)
            if (flow_term(o.chamber) == m) join(other);
    }
    for (size_t k = 0; k < chambers.size(); ++k)
      if (auto* c = dynamic_cast<GasFlowTerm*>(chambers[k])) c->gas_index_ = static_cast<int>(k);
    (void)self;
    std::sort(group->members.begin(), group->members.end(), [&](GasFlowTerm* a, GasFlowTerm* b) {
      return std::find(all.begin(), all.end(), a) < std::find(all.begin(), all.end(), b);
    });
    std::vector<gas::Chamber> net;
    std::vector<gas::Orifice> orifices;
    for (size_t i = 0; i < group->members.size(); ++i) {
      const GasLoad& g = group->members[i]->load_;
      gas::Chamber& c = net.emplace_back();
      c.gamma = g.gamma, c.R = g.gas_constant, c.temperature = g.temperature;
      c.initial_pressure = g.initial_pressure, c.ambient = g.ambient;
      c.inflators = static_cast<int>(g.inflators.size());
      c.vents = g.vents;
      for (const auto& l : g.leaks) c.leaks.push_back({l.permeability, l.quadratic});
      for (const auto& o : g.orifices) {
        GasFlowTerm* other = flow_term(o.chamber);
        const auto to =
            std::find(group->members.begin(), group->members.end(), other) - group->members.begin();
        orifices.push_back({static_cast<int>(i), static_cast<int>(to), o.area, o.discharge});
      }
      group->members[i]->group_ = group;
      group->members[i]->index_ = static_cast<int>(i);
    }
    group->net = std::make_unique<gas::Network>(std::move(net), std::move(orifices));
  }

  void start(const LoadState& s) override {
    if (index_ != 0) return;
    measure(s.t, s.x, false);
    group_->net->start(s.t, group_->inputs());
    group_->solution = group_->net->committed();
  }

  void commit(const LoadState& s) override {
    if (index_ != 0) return;
    measure(s.t, s.x, false);
    group_->solution = group_->net->commit(s.t, group_->inputs());
  }

  void save_state(std::vector<double>& out) const override {
    if (index_ == 0) group_->net->save(out);
  }
  size_t restore_state(const std::vector<double>& in, size_t at) override {
    if (index_ != 0) return at;
    at = group_->net->restore(in, at);
    group_->solution = group_->net->committed();
    return at;
  }

  void add(const LoadState& s, LoadOutput& out) override {
    Group& g = *group_;
    const bool jacobian = out.K != nullptr;
    if (index_ == 0) {
      measure(s.t, s.x, jacobian);
      g.net->solve(s.t, g.inputs(), jacobian, g.solution);
      if (jacobian) gradients(s.x);
    }
    const double p = g.solution.ok ? g.solution.p[index_] : kNaN;
    if (s.at_supports) {  // the reactions: the traction, not ∂V/∂x (LoadState::at_supports)
      walls_.add_traction(s.x, p - load_.ambient, gradient_, out.F);
      return;
    }
    walls_.volume_derivatives(s.x, load_.origin, p - load_.ambient, gradient_, out.K);
    out.F += (p - load_.ambient) * gradient_;
    if (!jacobian) return;
    site_.dofs.gather(gradient_, own_eq_);
    site_.dofs.layout().sum_to_owners(own_eq_);
    out.low_rank->U.col(out.column) = -own_eq_;
    auto W = out.low_rank->W.col(out.column);
    if (!g.solution.ok) {
      W.setConstant(kNaN);
      return;
    }
    const int n = static_cast<int>(g.members.size());
    if (n == 1) {
      W = g.solution.dp_dV(0, 0) * own_eq_;
    } else {
      W.setZero();
      for (int j = 0; j < n; ++j) W += g.solution.dp_dV(index_, j) * g.a_eq[j];
    }
    for (int k = 0; k < g.net->leaks(); ++k) W += g.solution.dp_dA(index_, k) * g.b_eq[k];
  }

  std::optional<double> quantity(std::string_view name) const override {
    if (!group_) return name == "gas_volume" ? std::optional<double>(0.0) : std::nullopt;
    return value(name, group_->solution, group_->V[index_]);
  }
  std::optional<double> quantity_at(std::string_view name, double t,
                                    const NodePositions& x) const override {
    const gas::Solution* s = &group_->net->committed();
    gas::Solution here;
    const double V = walls_.volume(x, load_.origin);
    if (t != group_->net->committed_time()) {  // a state the run has not committed
      Group copy;
      copy.V.resize(group_->members.size());
      for (size_t j = 0; j < group_->members.size(); ++j)
        copy.V[j] = group_->members[j]->walls_.volume(x, group_->members[j]->load_.origin);
      for (GasFlowTerm* m : group_->members)
        for (const ChamberSurface& l : m->leaks_) copy.A.push_back(l.area(x));
      for (GasFlowTerm* m : group_->members) m->inflow(t, copy.inflow, copy.inflow_T);
      group_->net->solve(t, copy.inputs(), false, here);
      s = &here;
    }
    return value(name, *s, V);
  }
  bool cell_field(std::string_view name, double t, const NodePositions& x,
                  std::span<const int> first_cell, std::vector<double>& per_cell) const override {
    if (name != "gas_pressure") return false;
    const double p = *quantity_at("gas_pressure", t, x);
    for (const auto& part : load_.parts)
      for (int e : part.elements) per_cell[static_cast<size_t>(first_cell[part.block] + e)] = p;
    return true;
  }

  std::string account_json() const override {
    const gas::Network& net = *group_->net;
    const gas::Solution& s = net.committed();
    const gas::Account& a = net.account(index_);
    const double g = load_.gamma, m = s.m[index_];
    auto num = [](double x) { return fmt::format("{:.17g}", x); };
    std::string j = fmt::format(
        "{{\"load\": {}, \"time\": {}, \"mass\": {{\"initial\": {}, \"final\": {}, \"in\": {}, "
        "\"out\": {}, \"residual\": {}}}",
        gas_index_, num(net.committed_time()), num(a.mass0), num(m), num(a.mass_in),
        num(a.mass_out), num(m - a.mass0 - (a.mass_in - a.mass_out)));
    if (g != 1) {
      const double U = s.E[index_] / (g - 1);
      const double residual = U - a.U0 - (a.enthalpy_in - a.enthalpy_out - a.work);
      j += fmt::format(
          ", \"energy\": {{\"internal_initial\": {}, \"internal_final\": {}, \"enthalpy_in\": {}, "
          "\"enthalpy_out\": {}, \"work\": {}, \"first_law_residual\": {}}}",
          num(a.U0), num(U), num(a.enthalpy_in), num(a.enthalpy_out), num(a.work), num(residual));
    }
    return j + "}";
  }

 private:
  std::optional<double> value(std::string_view name, const gas::Solution& s, double V) const {
    const int i = index_;
    const bool ok = s.ok && !s.m.empty();
    if (name == "gas_volume") return V;
    if (name == "gas_pressure") return ok ? s.p[i] : kNaN;
    if (name == "gas_mass") return ok ? s.m[i] : kNaN;
    if (name == "gas_temperature") return ok ? s.E[i] / (s.m[i] * load_.gas_constant) : kNaN;
    // gas_mass_flow:KIND:j (KIND inflator, vent, leakage, orifice: this chamber's j-th).
    if (name.starts_with("gas_mass_flow:")) {
      const std::string rest(name.substr(14));
      const auto colon = rest.find(':');
      if (colon == std::string::npos) return {};
      const std::string kind = rest.substr(0, colon);
      const int j = std::stoi(rest.substr(colon + 1));
      const gas::Network& net = *group_->net;
      int f = -1;
      if (kind == "inflator") f = net.inflator_flow(i, j);
      if (kind == "vent") f = net.vent_flow(i, j);
      if (kind == "leakage") f = net.leak_flow(i, j);
      if (kind == "orifice") {  // this chamber's j-th orifice among the group's
        int k = 0;
        for (int m = 0; m < i; ++m)
          k += static_cast<int>(group_->members[m]->load_.orifices.size());
        f = net.orifice_flow(k + j);
      }
      if (f < 0) return {};
      return ok ? s.rate[f] : kNaN;
    }
    return {};
  }

  void inflow(double t, std::vector<double>& rate, std::vector<double>& T) const {
    for (const auto& in : load_.inflators) {
      rate.push_back(in.scale * site_.model.function_value(in.mass_flow, t));
      T.push_back(in.temperature_function >= 0
                      ? site_.model.function_value(in.temperature_function, t)
                      : in.temperature);
    }
  }

  // The group's volumes, leaking areas and inflows at (t, x).
  void measure(double t, const NodePositions& x, bool) {
    Group& g = *group_;
    g.V.clear(), g.A.clear(), g.inflow.clear(), g.inflow_T.clear();
    for (GasFlowTerm* m : g.members) {
      g.V.push_back(m->walls_.volume(x, m->load_.origin));
      for (const ChamberSurface& l : m->leaks_) g.A.push_back(l.area(x));
      m->inflow(t, g.inflow, g.inflow_T);
    }
  }

  // ∂V_j/∂x of the other members and ∂A_k/∂x of every leak, as equation vectors.
  void gradients(const NodePositions& x) {
    Group& g = *group_;
    const size_t n = g.members.size();
    g.a_eq.resize(n > 1 ? n : 0);
    if (n > 1)
      for (size_t j = 0; j < n; ++j) {
        const GasFlowTerm& m = *g.members[j];
        m.walls_.volume_derivatives(x, m.load_.origin, 0.0, work_, nullptr);
        site_.dofs.gather(work_, g.a_eq[j]);
        site_.dofs.layout().sum_to_owners(g.a_eq[j]);
      }
    g.b_eq.clear();
    for (GasFlowTerm* m : g.members)
      for (const ChamberSurface& l : m->leaks_) {
        l.area_gradient(x, work_);
        VecX& b = g.b_eq.emplace_back();
        site_.dofs.gather(work_, b);
        site_.dofs.layout().sum_to_owners(b);
      }
  }

  const GasLoad& load_;
  LoadSite site_;
  ChamberSurface walls_;
  std::vector<ChamberSurface> leaks_;
  std::shared_ptr<Group> group_;
  int index_ = 0, gas_index_ = 0;
  NodePositions gradient_, work_;
  VecX own_eq_;
};

}  // namespace

std::unique_ptr<LoadTerm> make_gas_flow_term(const GasLoad& load, const LoadSite& site) {
  return std::make_unique<GasFlowTerm>(load, site);
}

}  // namespace velum
