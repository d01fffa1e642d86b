// Runs a model: builds the MechanicalSystem, the chosen integrator and linear solver, marches
// in time with step control, and tracks the energy balance. Output is the observer's job
// (io/ writes files from what it receives); the run itself writes nothing.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "velum/analysis/mechanical_system.hpp"
#include "velum/assembly/element_partition.hpp"
#include "velum/solve/linear_solver.hpp"
#include "velum/time/path_following.hpp"
#include "velum/time/relaxation.hpp"
#include "velum/time/time_loop.hpp"

namespace velum {

/// Form finding by the updated reference strategy (form_finding.hpp).
struct FormFindingSettings {
  /// Stiffness of the stabilizing elastic law relative to the prestress (its largest modulus
  /// over the largest prestress component; E A over the force of a cable): small values take
  /// long strides, large ones short and safe ones. Raised tenfold, up to four times, when a
  /// step's Newton fails.
  double stiffness = 1.0;
  /// The shape is found when the residual of prestress and loads on it is below this
  /// fraction of the force scale.
  double tolerance = 1e-5;
  int max_updates = 500;  ///< reference updates per load level
};

struct AnalysisSettings {
  /// static: load stepping with Newton; relaxation: each load level by dynamic relaxation,
  /// finished by Newton (relaxation.hpp); dynamic: a time integrator.
  /// form_finding: the shape in equilibrium with the prestress (form_finding.hpp).
  enum class Type { kStatic, kDynamic, kRelaxation, kFormFinding };
  Type type = Type::kDynamic;
  /// Equilibrium at each load level, no inertia (static, relaxation and form finding).
  bool equilibrium() const { return type != Type::kDynamic; }
  std::string type_name() const {
    return type == Type::kStatic       ? "static"
           : type == Type::kRelaxation ? "relaxation"
           : type == Type::kDynamic    ? "dynamic"
                                       : "form_finding";
  }
  /// newmark | hht | generalized-alpha | central-difference
  std::string scheme = "generalized-alpha";
  double rho_inf = 0.8;     ///< generalized-alpha
  double hht_alpha = 0.05;  ///< hht, in [0, 1/3]
  double newmark_beta = 0.25, newmark_gamma = 0.5;
  /// Static steps: start Newton from the last state extrapolated along the last increments
  /// (kExtrapolate), or from the last state itself (kNone).
  enum class Predictor { kExtrapolate, kNone };
  Predictor predictor = Predictor::kExtrapolate;
  /// Static: load control (the time loop), or a path followed by arc length or displacement
  /// control (path_following.hpp).
  PathSettings path;
  TimeLoopSettings time;
  NewtonSettings newton;
  RelaxationSettings relaxation;
  FormFindingSettings form_finding;
  SolverKind solver =
      SolverKind::kAuto;  ///< auto: CHOLMOD while symmetric and definite, else UMFPACK
  /// linear_solver petsc: PETSc options over the defaults (analysis.petsc_options).
  std::string petsc_options;
  /// Under mpirun: how the elements are shared (analysis.partition).
  ElementPartition partition = ElementPartition::kRows;
};

struct Energies {
  double kinetic = 0, strain = 0, external_work = 0, damping = 0;
};

/// Everything a run needs to go on from an accepted step exactly as it would have (io/ writes
/// it to DIR/checkpoint.bin): the loop's place and step control, the state, the integrator's
/// memory, the energy account and what was warned.
struct Checkpoint {
  LoopResume loop;
  State state;
  Energies energy;
  std::vector<double> integrator;  ///< TimeIntegrator::save
  std::vector<double> analysis;    ///< the energy account and the watches
  std::vector<std::string> warnings;
};

/// What an observer sees after each accepted step.
struct StepSnapshot {
  const AcceptedStep& step;
  const MechanicalSystem& system;
  const State& state;
  const Energies& energy;
  /// Makes the checkpoint of this step (load stepping and dynamics; null in path following).
  const std::function<Checkpoint()>* checkpoint = nullptr;
};

struct AnalysisResult {
  TimeLoopResult loop;
  Energies energy;
  std::string integrator, solver;
  int dofs = 0;
  long factorizations = 0, analyses = 0;
  double stable_step = 0;  ///< central difference: the estimate used
  /// What a user must know about a run that ended normally (an unstable equilibrium ...);
  /// each also went to `on_warning` as it happened.
  std::vector<std::string> warnings;
};

std::unique_ptr<TimeIntegrator> make_integrator(const AnalysisSettings& s);
/// The linear solver of the settings; for PETSc, with the system's rigid-body modes (computed
/// when an iterative solve is analysed: the solver must not outlive `system`) and block size
/// (solver_setup.cpp).
std::unique_ptr<LinearSolver> make_solver(const MechanicalSystem& system,
                                          const AnalysisSettings& s);

/// Runs the analysis from `resume` (a checkpoint of the same model, not in path following),
/// from `start` at t0, or from rest at the reference configuration. The
/// observer is called after each accepted step (and once at t0 with step 0); returning false
/// stops the run. `on_warning` hears each warning as it arises.
AnalysisResult run_analysis(MechanicalSystem& system, const AnalysisSettings& settings,
                            const std::function<bool(const StepSnapshot&)>& observer = {},
                            const std::function<void(const std::string&)>& on_warning = {},
                            const State* start = nullptr, const Checkpoint* resume = nullptr);

}  // namespace velum
