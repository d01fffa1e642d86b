#include "velum/analysis/plausibility.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "velum/parallel/model_piece.hpp"
#include "velum/parallel/processes.hpp"

namespace velum {
namespace {

double energy_floor(double held, double work_scale, double held_start, double stored) {
  return 1e-9 * std::max({std::abs(held), work_scale, std::abs(held_start), stored});
}

}  // namespace

PlausibilityCheck::PlausibilityCheck(const Model& model, PlausibilityLimits limits)
    : limits_(limits) {
  if (model.piece)  // a process's piece: the whole model's size, alike on every process
    size_ = model.piece->size;
  else if (model.num_nodes() > 0)
    size_ = (model.X.rowwise().maxCoeff() - model.X.rowwise().minCoeff()).norm();
  // The prestress's energy per unit strain (its largest component times the sheets' volume):
  // the round-off of its forces moves an unloaded prestressed sheet by an energy of about
  // ε times it (4.9e-14 J on a 1 m² sheet at 1 kN/m), which is no energy created. On a
  // process's piece each process measures the elements it holds (its own: the others' slots
  // are empty) and the sum is the whole model's, alike on every process.
  for (const auto& b : model.blocks)
    if (const double S0 = b->sheet_prestress().cwiseAbs().maxCoeff(); S0 > 0) {
      double volume = 0;
      for (int e = 0; e < b->size(); ++e)
        if (b->holds(e)) volume += b->measure(e);
      stored_ += S0 * volume;
    }
  if (model.piece) processes::sum(&stored_, 1);
}

std::string PlausibilityCheck::check(double t, const NodePositions& U, const State& s, bool energy,
                                     double held, double work, double work_scale,
                                     double held_start) const {
  const bool several = assembler_ && processes::count() > 1;
  const bool finite = s.u.allFinite() && s.v.allFinite() && s.a.allFinite() && U.allFinite();
  if (several ? !processes::all(finite) : !finite)
    return fmt::format(
        "implausible: non-finite displacements, velocities or accelerations at "
        "t = {:.6g}",
        t);
  if ((several ? assembler_->global_nodes() : U.cols()) > 0 && size_ > 0) {
    Vec3 mean;
    double spread = 0;
    if (!several) {
      mean = U.rowwise().mean();
      spread = (U.colwise() - mean).colwise().norm().maxCoeff();
    } else {  // each node counted once, by the process keeping it
      Vec3 sum = Vec3::Zero();
      for (int n = 0; n < U.cols(); ++n)
        if (assembler_->keeps_node(n)) sum += U.col(n);
      processes::sum(sum.data(), 3);
      mean = sum / static_cast<double>(assembler_->global_nodes());
      for (int n = 0; n < U.cols(); ++n)
        if (assembler_->keeps_node(n)) spread = std::max(spread, (U.col(n) - mean).norm());
      spread = processes::max(spread);
    }
    if (spread > limits_.spread * size_)
      return fmt::format(
          "implausible: at t = {:.6g} a node is {:.3g} from the mean displacement, {:.3g} times "
          "the model's size {:.3g} (the limit is {:g} times): a blow-up, or a material or load "
          "in other units than the geometry",
          t, spread, spread / size_, size_, limits_.spread);
  }
  if (!energy) return {};
  // Energy created: what the system holds and has dissipated beyond the work done on it.
  // Round-off and the trapezoidal work leave a little; a blow-up leaves orders of magnitude.
  // The floor is the round-off of the energies compared, the one held at the start included: a
  // dynamic step after a static one that does next to nothing held 2.34e-16 against 2.08e-17 of
  // work, differences of a strain energy of 7.1e-3 (a change of round-off failed it).
  // The limit scales with the work done and the kinetic energy at the start: a sheet thrown
  // (an initial velocity) moves its energy between kinetic and strain with the integrator's
  // own error (a few percent), and no load does work on it.
  const double created = held - work;
  const double floor = energy_floor(held, work_scale, held_start, stored_);
  if (!std::isfinite(created))
    return fmt::format("implausible: non-finite energy at t = {:.6g}", t);
  if (created > limits_.energy_fail * (work_scale + kinetic_start_) + floor)
    return fmt::format(
        "implausible: the energy balance fails at t = {:.6g}: kinetic + strain + damping "
        "energy {:.4g} against {:.4g} of work done on the model (loads and prescribed "
        "motions): {:.3g} created by the solution (the limit is {:g} times the work's "
        "magnitude and the kinetic energy at the start); a blow-up: try smaller steps or another "
        "integrator",
        t, held, work, created, limits_.energy_fail);
  return {};
}

std::string PlausibilityCheck::final_balance(double t, const EnergyBalance& b,
                                             const std::function<void(std::string)>& warn) const {
  const double scale = std::max(std::abs(b.work), b.peak_work) + kinetic_start_;
  const double created = b.held - b.work;
  const double floor = energy_floor(b.held, scale, b.held_start, stored_);
  if (created > limits_.energy_fail_end * scale + floor)
    return fmt::format(
        "implausible: the energy balance fails at the end (t = {:.6g}): kinetic + strain + "
        "damping energy {:.4g} against {:.4g} of work done (at most {:.4g} during the run): "
        "{:.3g} created by the solution, {:.0f}% of the work (the limit is {:g}%); a blow-up "
        "or a collapsed element: try smaller steps or another integrator",
        t, b.held, b.work, b.peak_work, created, 100 * created / scale,
        100 * limits_.energy_fail_end);
  if (created > limits_.energy_warn * scale + floor)
    warn(fmt::format(
        "energy balance off at the end (t = {:.6g}): kinetic + strain + damping energy {:.4g} "
        "against {:.4g} of work done (at most {:.4g} during the run), {:.0f}% of the work "
        "created by the solution (more than {:g}%)",
        t, b.held, b.work, b.peak_work, 100 * created / scale, 100 * limits_.energy_warn));
  else if (b.peak_created > limits_.energy_warn * scale + floor)
    warn(fmt::format(
        "energy spike at t = {:.6g}: the model held {:.4g} more energy than all the work done "
        "on it by then ({:.0f}% of the most work done, {:.4g}; more than {:g}%): a collapsed "
        "(folded) element or a blow-up that died down; results near it are not physical",
        b.peak_t, b.peak_created, 100 * b.peak_created / scale, scale, 100 * limits_.energy_warn));
  return {};
}

}  // namespace velum
