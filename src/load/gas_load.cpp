// Enclosed gas: the chamber's set-up (closure, orientation, V0), its follower pressure
// p(V) − ambient with the load stiffness, and the rank-one term of p(V) in the Jacobian.
#include "velum/load/gas_load.hpp"

#include "chamber_surface.hpp"

#include "gas_flow_term.hpp"

#include <fmt/format.h>

#include "velum/assembly/assembler.hpp"
#include "velum/element/enclosed_volume.hpp"
#include "velum/model/gas_chamber.hpp"
#include "velum/model/model.hpp"
#include "velum/parallel/processes.hpp"
#include "velum/time/second_order_system.hpp"

namespace velum {
namespace {

class GasChamber final : public Load, public GasLoad {
 public:
  explicit GasChamber(GasLoad p) : GasLoad(std::move(p)) {}
  std::string_view kind() const override { return "gas"; }
  LoadOrder order() const override { return LoadOrder::kChamber; }
  std::unique_ptr<Load> clone() const override { return std::make_unique<GasChamber>(*this); }
  void set_up(const Model& model, const ElementNamer& name) override {
    set_up_gas_chamber(model, *this, name);
  }
  std::unique_ptr<Load> held(double t, const Model& owner, Model& step) const override {
    // The amount is a time function: held by a constant function of its value.
    TimeFunction f;
    f.value = owner.function_value(amount, t);
    f.name = "held";
    step.functions.push_back(f);
    auto h = std::make_unique<GasChamber>(*this);
    h->amount = static_cast<int>(step.functions.size()) - 1;
    // Gas flow goes on as it was: the inflators' curves (in the run's time) come along.
    auto carry = [&](int& f) {
      if (f < 0) return;
      step.functions.push_back(owner.functions[static_cast<size_t>(f)]);
      f = static_cast<int>(step.functions.size()) - 1;
    };
    for (auto& in : h->inflators) carry(in.mass_flow), carry(in.temperature_function);
    return h;
  }
  std::string_view counted_as() const override { return {}; }  // a line of its own
  std::string summary(int index) const override {
    if (flows())
      return fmt::format(
          "gas {}:      initial volume {:.6g}, initial pressure {:.6g}, ambient {:.6g}, "
          "gamma {:.6g}, temperature {:.6g}, gas constant {:.6g}; {} inflator(s), {} vent(s), "
          "{} leaking set(s), {} orifice(s)",
          index, V0, initial_pressure, ambient, gamma, temperature, gas_constant, inflators.size(),
          vents.size(), leaks.size(), orifices.size());
    return fmt::format(
        "gas {}:      initial volume {:.6g}, initial pressure {:.6g}, ambient {:.6g}, "
        "gamma {:.6g}",
        index, V0, initial_pressure, ambient, gamma);
  }
  std::unique_ptr<LoadTerm> bind(const LoadSite& site) const override;
};

class GasChamberTerm final : public LoadTerm {
 public:
  GasChamberTerm(const GasChamber& load, const LoadSite& site)
      : load_(load), site_(site), walls_(load.parts, site) {
    volume_ = load.V0;
    pressure_ = load.pressure(load.V0, site.model.function_value(load.amount, 0.0));
  }

  int low_rank_columns() const override { return 1; }

  // Enclosed gas: the sheet carries p(V) − ambient as a follower pressure, f = (p − p_a) ∂V/∂x,
  // so ∂r/∂x = −(p − p_a) ∂²V/∂x² − (dp/dV) a aᵀ with dp/dV = −γ p / V: the first term into
  // the sparse matrix, the second (dense over the chamber) kept as a rank-one column.
  void add(const LoadState& s, LoadOutput& out) override {
    const double V = volume(s.x);
    const double p = load_.pressure(V, site_.model.function_value(load_.amount, s.t));
    volume_ = V;
    pressure_ = p;
    if (s.at_supports) {  // the reactions: the traction, not ∂V/∂x (LoadState::at_supports)
      walls_.add_traction(s.x, p - load_.ambient, gradient_, out.F);
      return;
    }
    walls_.volume_derivatives(s.x, load_.origin, p - load_.ambient, gradient_, out.K);
    out.F += (p - load_.ambient) * gradient_;
    if (!out.K) return;
    site_.dofs.gather(gradient_, gradient_eq_);
    site_.dofs.layout().sum_to_owners(gradient_eq_);  // this process's share, on several
    out.low_rank->W.col(out.column) = gradient_eq_;
    out.low_rank->U.col(out.column) = (load_.gamma * p / V) * gradient_eq_;
  }

  std::optional<double> quantity(std::string_view name) const override {
    if (name == "gas_volume") return volume_;
    if (name == "gas_pressure") return pressure_;
    return {};
  }
  std::optional<double> quantity_at(std::string_view name, double t,
                                    const NodePositions& x) const override {
    if (name == "gas_volume") return volume(x);
    if (name == "gas_pressure") return pressure_at(t, x);
    return {};
  }
  bool cell_field(std::string_view name, double t, const NodePositions& x,
                  std::span<const int> first_cell, std::vector<double>& per_cell) const override {
    if (name != "gas_pressure") return false;
    const double p = pressure_at(t, x);  // collective
    for (const auto& part : load_.parts)
      for (int e : part.elements) per_cell[static_cast<size_t>(first_cell[part.block] + e)] = p;
    return true;
  }

 private:
  double pressure_at(double t, const NodePositions& x) const {
    return load_.pressure(volume(x), site_.model.function_value(load_.amount, t));
  }
  // The chamber's volume at x (summed over the processes: p(V) is not linear).
  double volume(const NodePositions& x) const { return walls_.volume(x, load_.origin); }

  const GasChamber& load_;
  LoadSite site_;
  ChamberSurface walls_;
  double volume_ = 0, pressure_ = 0;
  NodePositions gradient_;
  VecX gradient_eq_;
};

std::unique_ptr<LoadTerm> GasChamber::bind(const LoadSite& site) const {
  if (flows()) return make_gas_flow_term(*this, site);
  return std::make_unique<GasChamberTerm>(*this, site);
}

}  // namespace

std::unique_ptr<Load> make_load(GasLoad p) {
  return std::make_unique<GasChamber>(std::move(p));
}

}  // namespace velum
