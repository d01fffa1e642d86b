// Runs a model: builds the MechanicalSystem, the chosen integrator and linear solver, marches
// in time with step control, and tracks the energy balance. Output is the observer's job
// (io/ writes files from what it receives); the run itself writes nothing.
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "velum/analysis/mechanical_system.hpp"
#include "velum/solve/linear_solver.hpp"
#include "velum/time/relaxation.hpp"
#include "velum/time/time_loop.hpp"

namespace velum {

struct AnalysisSettings {
  /// static: load stepping with Newton; relaxation: each load level by dynamic relaxation,
  /// finished by Newton (relaxation.hpp); dynamic: a time integrator.
  enum class Type { kStatic, kDynamic, kRelaxation };
  Type type = Type::kDynamic;
  /// Equilibrium at each load level, no inertia (static and relaxation).
  bool equilibrium() const { return type != Type::kDynamic; }
  std::string type_name() const {
    return type == Type::kStatic ? "static" : type == Type::kRelaxation ? "relaxation" : "dynamic";
  }
  /// newmark | hht | generalized-alpha | central-difference
  std::string scheme = "generalized-alpha";
  double rho_inf = 0.8;     ///< generalized-alpha
  double hht_alpha = 0.05;  ///< hht, in [0, 1/3]
  double newmark_beta = 0.25, newmark_gamma = 0.5;
  TimeLoopSettings time;
  NewtonSettings newton;
  RelaxationSettings relaxation;
  SolverKind solver =
      SolverKind::kAuto;  ///< auto: CHOLMOD while symmetric and definite, else UMFPACK
};

struct Energies {
  double kinetic = 0, strain = 0, external_work = 0, damping = 0;
};

/// What an observer sees after each accepted step.
struct StepSnapshot {
  const AcceptedStep& step;
  const MechanicalSystem& system;
  const State& state;
  const Energies& energy;
};

struct AnalysisResult {
  TimeLoopResult loop;
  Energies energy;
  std::string integrator, solver;
  int dofs = 0;
  long factorizations = 0, analyses = 0;
  double stable_step = 0;  ///< central difference: the estimate used
};

std::unique_ptr<TimeIntegrator> make_integrator(const AnalysisSettings& s);

/// Runs the analysis from rest at the reference configuration. The observer is called after
/// each accepted step (and once at t0 with step 0); returning false stops the run.
AnalysisResult run_analysis(MechanicalSystem& system, const AnalysisSettings& settings,
                            const std::function<bool(const StepSnapshot&)>& observer = {});

}  // namespace velum
