#include "velum/analysis/analysis.hpp"

#include <stdexcept>

namespace velum {

std::unique_ptr<TimeIntegrator> make_integrator(const AnalysisSettings& s) {
  std::unique_ptr<TimeIntegrator> out;
  if (s.type == AnalysisSettings::Type::kStatic) {
    out = std::make_unique<StaticNewton>();
  } else if (s.type == AnalysisSettings::Type::kRelaxation) {
    auto dr = std::make_unique<DynamicRelaxation>();
    dr->relaxation = s.relaxation;
    out = std::move(dr);
  }
  else if (s.scheme == "generalized-alpha")
    out = GeneralizedAlpha::chung_hulbert(s.rho_inf);
  else if (s.scheme == "hht")
    out = GeneralizedAlpha::hht(s.hht_alpha);
  else if (s.scheme == "newmark")
    out = GeneralizedAlpha::newmark(s.newmark_beta, s.newmark_gamma);
  else if (s.scheme == "central-difference")
    out = std::make_unique<CentralDifference>();
  else
    throw std::invalid_argument("unknown integrator scheme '" + s.scheme + "'");
  out->newton = s.newton;
  return out;
}

AnalysisResult run_analysis(MechanicalSystem& sys, const AnalysisSettings& settings,
                            const std::function<bool(const StepSnapshot&)>& observer) {
  AnalysisResult result;
  auto integrator = make_integrator(settings);
  auto solver = make_linear_solver(settings.solver);
  result.integrator = integrator->name();
  result.solver = std::string(solver->name());
  result.dofs = sys.size();

  State s;
  s.u = VecX::Zero(sys.size());
  s.v = VecX::Zero(sys.size());
  s.a = VecX::Zero(sys.size());
  TimeLoopSettings loop = settings.time;
  if (!integrator->implicit()) {
    // Central difference: cap the step at 0.9 of the stable estimate at the start.
    result.stable_step = stable_time_step(sys, loop.t0, s);
    loop.step = std::min(loop.step, 0.9 * result.stable_step);
    loop.adaptive = false;
  }

  // Energy balance: W_ext by the trapezoidal rule on Fext·ΔU, damping work likewise on the
  // Rayleigh force. Full-vector quantities include prescribed motions.
  Energies& E = result.energy;
  double t_prev = loop.t0;
  NodePositions U_prev = sys.displacements(t_prev, s.u);
  NodePositions F_prev = sys.external_forces(t_prev, s.u, s.v);
  VecX v_prev = s.v;
  const double alpha = sys.model().rayleigh_mass;

  AcceptedStep start{.t = loop.t0, .output_time = true};
  if (observer && !observer(StepSnapshot{start, sys, s, E})) return result;

  result.loop = run_time_loop(
      sys, *integrator, *solver, loop, s, [&](const AcceptedStep& st, const State& cur) {
        const NodePositions U = sys.displacements(st.t, cur.u);
        const NodePositions F = sys.external_forces(st.t, cur.u, cur.v);
        E.external_work += 0.5 * ((F + F_prev).array() * (U - U_prev).array()).sum();
        if (alpha != 0)
          E.damping +=
              0.5 * st.h * alpha *
              (cur.v.dot(sys.mass_matrix() * cur.v) + v_prev.dot(sys.mass_matrix() * v_prev));
        E.kinetic =
            settings.equilibrium() ? 0.0 : sys.kinetic_energy(cur.v);
        E.strain = sys.strain_energy(st.t, cur.u);
        U_prev = U, F_prev = F, v_prev = cur.v, t_prev = st.t;
        return !observer || observer(StepSnapshot{st, sys, cur, E});
      });
  result.solver = std::string(solver->name());  // what `auto` settled on
  result.factorizations = solver->factorizations();
  result.analyses = solver->analyses();
  return result;
}

}  // namespace velum
