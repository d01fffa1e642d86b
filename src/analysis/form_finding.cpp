#include "velum/analysis/form_finding.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace velum {
namespace {

// The model of one update: reference X = the current shape x, the sections' form-finding laws
// (stabilizer > 0), the same supports and loads; prescribed motions as the displacement that
// takes each node from x to where the motion puts it at t.
Model update_model(const Model& model, const NodePositions& x, double t, double stabilizer) {
  Model w;
  w.X = x;
  w.node_ids = model.node_ids;
  w.node_index = model.node_index;
  for (const auto& b : model.blocks) w.blocks.push_back(b->on_reference(x, stabilizer));
  w.masses = model.masses;
  w.fixed = model.fixed;
  w.symmetry = model.symmetry;
  for (const auto& p : model.prescribed) {
    const Vec3 d = p.displacement * model.function_value(p.function, t);
    for (int n : p.nodes)
      w.prescribed.push_back({.nodes = {n}, .displacement = model.X.col(n) + d - x.col(n)});
  }
  w.loads = model.loads;
  w.functions = model.functions;
  w.rayleigh_mass = model.rayleigh_mass;
  w.rayleigh_stiffness = model.rayleigh_stiffness;
  w.piece = model.piece;  // under mpirun: the same piece, its nodes and partition
  return w;
}

// Whether a level begun at `start` has spent its max_seconds (0: no limit).
bool out_of_time(std::chrono::steady_clock::time_point start, double max_seconds) {
  return max_seconds > 0 &&
         std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() >
             max_seconds;
}

// Why the updates found no shape, and what helps. A residual that still falls wants more
// updates; one that has levelled off (the mesh sliding along the surface) does not: with a
// warp ≠ fill prestress there is in general no shape that carries it, with an isotropic one
// the shape has settled above the tolerance.
std::string no_shape_advice(const Model& model, const std::vector<double>& residuals) {
  const double last = residuals.empty() ? 0.0 : residuals.back();
  const size_t back = residuals.empty() ? 0 : std::min<size_t>(10, residuals.size() - 1);
  const double before = residuals.empty() ? 0.0 : residuals[residuals.size() - 1 - back];
  const bool falling = back >= 5 && last <= 0.5 * before;
  const std::string trend =
      back >= 5 ? fmt::format("; the residual was {:.3g} {} updates before", before, back) : "";
  const ElementBlock* anisotropic = nullptr;
  for (const auto& b : model.blocks) {
    const Vec3 S0 = b->sheet_prestress();
    const double size = S0.cwiseAbs().maxCoeff();
    if (size > 0 && (std::abs(S0[0] - S0[1]) > 1e-12 * size || S0[2] != 0)) {
      anisotropic = b.get();
      break;
    }
  }
  if (falling || (back < 5 && !anisotropic))
    return fmt::format("{}; raise analysis.form_finding.max_updates or lower its stiffness{}",
                       trend,
                       anisotropic ? " (a warp ≠ fill prestress need not have an equilibrium "
                                     "shape: docs/fabric-structures.md)"
                                   : "");
  if (anisotropic) {
    const Vec3 S0 = anisotropic->sheet_prestress();
    return fmt::format(
        "{}. The prestress of set '{}' differs between warp and fill ([{:.6g}, {:.6g}, {:.6g}]): "
        "on a curved surface a uniform warp ≠ fill stress is in general not in equilibrium in "
        "the plane of the sheet (nor balanced by a uniform edge-cable force), so no shape "
        "carries it exactly and more updates only slide the mesh along the surface. Give equal "
        "warp and fill prestress (a minimal surface), or accept this shape with "
        "analysis.form_finding.tolerance above {:.2g} and let form.yaml, run as static, settle "
        "it elastically (docs/fabric-structures.md)",
        trend, anisotropic->set_name(), S0[0], S0[1], S0[2], last);
  }
  return fmt::format(
      "{}: it has levelled off (the mesh slides along the surface, the shape no longer "
      "changes) and more updates cannot help; raise analysis.form_finding.tolerance above "
      "{:.2g} (docs/fabric-structures.md)",
      trend, last);
}

}  // namespace

AnalysisResult run_form_finding(Model& model, MechanicalSystem& view,
                                const AnalysisSettings& settings,
                                const std::function<bool(const StepSnapshot&)>& observer,
                                const std::function<void(const std::string&)>& on_warning,
                                FormFindingReport* report) {
  if (model.U0.size())
    throw std::invalid_argument(
        "form finding finds the reference shape itself: it does not take "
        "mesh.reference_positions (give the found form's positions as mesh.positions)");
  AnalysisResult result;
  (void)on_warning;
  result.integrator = "form finding (updated reference)";
  result.dofs = view.size();
  const FormFindingSettings& ff = settings.form_finding;
  bool any_prestress = false;
  for (const auto& b : model.blocks) any_prestress = any_prestress || b->prestressed();
  if (!any_prestress)
    throw std::invalid_argument(
        "form finding needs a prestress: give membrane or cable sections a 'prestress'");

  const NodePositions X0 = model.X;
  NodePositions x = X0;
  Energies& E = result.energy;
  State shown;
  shown.u = VecX::Zero(view.size());
  shown.v = shown.u, shown.a = shown.u;
  const TimeLoopSettings& loop = settings.time;
  double t = loop.t0;
  {
    AcceptedStep first{.t = t, .output_time = true};
    if (observer && !observer(StepSnapshot{first, view, shown, E})) {
      result.loop.stopped = true;
      return result;
    }
  }
  FormFindingReport rep_out;
  if (report) *report = rep_out;
  const bool trace = std::getenv("VELUM_FORM_FINDING_TRACE") != nullptr;
  double stabilizer = ff.stiffness;
  int level = 0;
  TimeLoopResult& out = result.loop;
  out.t = t;
  const double h_nominal = loop.step > 0 ? loop.step : loop.t_end - loop.t0;
  while (t < loop.t_end - 1e-12 * std::max(1.0, std::abs(loop.t_end))) {
    const double h = std::min(h_nominal, loop.t_end - t);
    const double t_next = (loop.t_end - (t + h) < 1e-9 * h_nominal) ? loop.t_end : t + h;
    int level_iterations = 0, level_factorizations = 0;
    StepReport last;
    bool found = false;
    const auto level_start = std::chrono::steady_clock::now();
    // Several processes: each one's clock, the decision together (any one spent ends it).
    auto spent = [&] {
      return ff.max_seconds > 0 &&
             view.sum_over_processes(out_of_time(level_start, ff.max_seconds) ? 1.0 : 0.0) > 0;
    };
    auto end_level = [&](int update, bool over_time) {
      out.stopped = !over_time;
      out.reason = out.stopped
                       ? fmt::format("form finding interrupted at t = {:.6g} after {} updates",
                                     t_next, update)
                       : fmt::format(
                             "form finding at t = {:.6g}: no equilibrium shape within "
                             "analysis.form_finding.max_seconds = {:g} s ({} updates; residual "
                             "{:.3g} of the force scale, tolerance {:.3g})",
                             t_next, ff.max_seconds, update, rep_out.residual, ff.tolerance);
      rep_out.shape = x;
      if (report) *report = rep_out;
      return result;
    };
    std::vector<double> residuals;  // of this level's updates, for the advice on failing
    for (int update = 0; update <= ff.max_updates; ++update) {
      // A signal, or the level's time spent: the level fails here (a stiffer stabilizer or
      // a shorter level would spend it again).
      if (settings.newton.interrupt_requested()) return end_level(update, false);
      if (spent()) return end_level(update, true);
      Model work = update_model(model, x, t_next, stabilizer);
      MechanicalSystem sys(work);
      const VecX zero = VecX::Zero(sys.size());
      VecX r;
      sys.evaluate(t_next, zero, zero, zero, 1.0, 0.0, 0.0, r, nullptr);
      // The residual on the unmoved reference: prescribed motions still to make count as
      // not found.
      bool moves = false;
      for (const auto& p : work.prescribed) moves = moves || p.displacement.norm() > 0;
      const double res = sys.norm(r), scale = sys.force_scale();
      rep_out.residual = scale > 0 ? res / scale : res;
      residuals.push_back(rep_out.residual);
      if (!std::isfinite(res)) {
        out.reason = fmt::format("form finding at t = {:.6g}: non-finite forces after {} updates",
                                 t_next, update);
        if (report) *report = rep_out;
        return result;
      }
      if (!moves && (res <= ff.tolerance * scale || res <= settings.newton.abs_residual)) {
        found = true;
        break;
      }
      if (update == ff.max_updates) break;
      StaticNewton newton(false);
      newton.newton = settings.newton;
      // Several processes: PETSc over this process's local equations.
      auto solver =
          sys.distributed() ? make_solver(sys, settings) : make_linear_solver(settings.solver);
      State s;
      s.u = zero, s.v = zero, s.a = zero;
      last = newton.step(sys, *solver, t_next - h, h, s);
      level_iterations += last.iterations;
      level_factorizations += last.factorizations;
      result.solver = std::string(solver->name());
      result.factorizations += solver->factorizations();
      result.analyses += solver->analyses();
      if (last.interrupted) return end_level(update, false);
      if (!last.converged) {
        // Homotopy towards shorter strides: a stiffer stabilizer.
        if (stabilizer >= 1e4 * ff.stiffness) {
          out.reason = fmt::format(
              "form finding at t = {:.6g}: the update's Newton did not converge even with the "
              "stabilizing stiffness raised to {:.3g} ({})",
              t_next, stabilizer, last.reason);
          if (report) *report = rep_out;
          return result;
        }
        stabilizer *= 10;
        continue;
      }
      ++rep_out.updates;
      NodePositions U = sys.displacements(t_next, s.u);
      sys.assembler().from_keepers(U);  // several processes: each node from its keeper
      x += U;
      // Back towards the nominal stabilizer once an update has gone through.
      stabilizer = std::max(ff.stiffness, stabilizer / 10);
      if (trace)
        fmt::print(stderr,
                   "form finding t = {:.6g} update {}: residual {:.3e}, stabilizer {:.3g}, "
                   "{} Newton iterations\n",
                   t_next, update, rep_out.residual, stabilizer, last.iterations);
    }
    out.iterations += level_iterations;
    out.factorizations += level_factorizations;
    if (!found) {
      out.reason = fmt::format(
          "form finding at t = {:.6g}: no equilibrium shape after {} reference updates (residual "
          "{:.3g} of the force scale, tolerance {:.3g}){}",
          t_next, ff.max_updates, rep_out.residual, ff.tolerance,
          no_shape_advice(model, residuals));
      rep_out.shape = x;
      if (report) *report = rep_out;
      return result;
    }
    // The sections on the found shape: the view shows it with its stresses.
    for (auto& b : model.blocks) b = b->on_reference(x, 0.0);
    view.dofs().gather(NodePositions(x - X0), shown.u);
    t = t_next;
    out.t = t;
    ++out.steps;
    ++level;
    last.converged = true;
    AcceptedStep st{.t = t,
                    .h = h,
                    .step = level,
                    .iterations = level_iterations,
                    .total_iterations = out.iterations,
                    .factorizations = level_factorizations,
                    .total_factorizations = out.factorizations,
                    .output_time = true,
                    .report = &last};
    E.strain = view.strain_energy(t, shown.u);
    if (observer && !observer(StepSnapshot{st, view, shown, E})) {
      out.stopped = true;
      return result;
    }
  }
  out.completed = true;
  rep_out.stabilizer = stabilizer;
  rep_out.shape = x;
  if (report) *report = rep_out;
  return result;
}

}  // namespace velum
