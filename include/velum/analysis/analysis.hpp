// Runs a model: builds the MechanicalSystem, the chosen integrator and linear solver, marches
// in time with step control, and tracks the energy balance. Output is the observer's job
// (io/ writes files from what it receives); the run itself writes nothing.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "velum/analysis/mechanical_system.hpp"
#include "velum/assembly/dof_map.hpp"
#include "velum/parallel/element_partition.hpp"
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
  /// Wall-clock seconds a load level may take (0: no limit); spent, the level fails.
  double max_seconds = 0;
};

/// Central difference's step (analysis.integrator; docs/performance.md, explicit dynamics).
struct ExplicitStepSettings {
  /// The run's step is safety x the stable step estimated (capped by time.step), in (0, 1]:
  /// the estimate is a power iteration, which approaches ω_max from below. 0.6 keeps the
  /// stiffest mode at h ω <= 1.2, below central difference's nonlinear resonances of orders 4
  /// and 3 (h ω = √2, √3), where a struck sheet's energy grows though h ω < 2 (measured bands
  /// in docs/performance.md, "Nonlinear resonance").
  static constexpr double kDefaultSafety = 0.6;
  /// h ω of the stiffest mode below the fourth-order band's measured edge (1.35): a step at a
  /// safety past half of it may meet the resonances.
  static constexpr double kBelowResonances = 1.3;
  double safety = kDefaultSafety;
  /// Re-estimate the stable step from the current state at every trust check
  /// (kExplicitCheckInterval steps, output times); false: at the start only.
  bool from_current_state = true;
  /// Mass scaling (> 0): at the start, mass added to every node whose own stable step (its
  /// rows' Gershgorin bound over its mass) is below this, so that the run's step reaches it;
  /// the mass added is reported (AnalysisResult::explicit_step). 0: none.
  double target_step = 0;
};

/// What central difference did with its step (AnalysisResult::explicit_step).
struct ExplicitStepReport {
  /// The stable step estimated at the start (after mass scaling) and last; the smallest and
  /// largest steps the run set from them (safety x estimate, capped by time.step).
  double first = 0, last = 0, smallest = 0, largest = 0;
  int estimates = 0;     ///< estimates in the run (the start's included)
  long evaluations = 0;  ///< force evaluations the estimates after the start cost
  /// Mass scaling: the mass added over the nodes, the model's mass before, the nodes scaled.
  double added_mass = 0, model_mass = 0;
  int scaled_nodes = 0;
};

struct AnalysisSettings {
  /// static: load stepping with Newton; relaxation: each load level by dynamic relaxation,
  /// finished by Newton (relaxation.hpp); dynamic: a time integrator.
  /// form_finding: the shape in equilibrium with the prestress (form_finding.hpp).
  /// A new type is a value here, its row in kAnalysisTypes and its branch in run_analysis.
  enum class Type { kStatic, kDynamic, kRelaxation, kFormFinding };
  Type type = Type::kDynamic;
  /// Equilibrium at each load level, no inertia (static, relaxation and form finding).
  bool equilibrium() const { return type != Type::kDynamic; }
  /// Its name in a model file (analysis.type).
  std::string type_name() const;
  /// How it solves, for `velum check` ("load stepping"; the scheme of a dynamic run).
  std::string method() const;
  /// What runs, for the progress line ("static load stepping").
  std::string run_name() const;
  /// newmark | hht | generalized-alpha | central-difference
  std::string scheme = "generalized-alpha";
  /// A dynamic run by central differences: short explicit steps, checked every
  /// kExplicitCheckInterval steps.
  bool explicit_steps() const { return type == Type::kDynamic && scheme == "central-difference"; }
  double rho_inf = 0.8;     ///< generalized-alpha
  double hht_alpha = 0.05;  ///< hht, in [0, 1/3]
  double newmark_beta = 0.25, newmark_gamma = 0.5;
  ExplicitStepSettings explicit_step;  ///< central-difference
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

/// The analysis types: each one's name in a model file (analysis.type), how `velum check`
/// describes its method (empty: the integrator scheme) and the progress line's name of its run
/// (empty: "dynamic run (scheme)").
struct AnalysisTypeInfo {
  AnalysisSettings::Type type;
  const char* name;
  const char* method;
  const char* run;
};
inline constexpr AnalysisTypeInfo kAnalysisTypes[] = {
    {AnalysisSettings::Type::kStatic, "static", "load stepping", "static load stepping"},
    {AnalysisSettings::Type::kDynamic, "dynamic", "", ""},
    {AnalysisSettings::Type::kRelaxation, "relaxation", "kinetic damping, then Newton",
     "dynamic relaxation"},
    {AnalysisSettings::Type::kFormFinding, "form_finding", "updated reference",
     "form finding (updated reference)"},
};

/// What form finding reports beyond an AnalysisResult.
struct FormFindingReport {
  int updates = 0;        ///< reference updates over all load levels
  double residual = 0;    ///< ‖r‖ / force scale of prestress and loads on the final shape
  double stabilizer = 0;  ///< the stabilizing stiffness in force at the end
  NodePositions shape;    ///< the found node coordinates (3 x nodes)
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
  std::vector<double> loads;       ///< MechanicalSystem::save_load_state (empty: none saved)
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
  double stable_step = 0;            ///< central difference: the estimate at the start
  ExplicitStepReport explicit_step;  ///< central difference
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

/// Where a run starts: from rest at the reference configuration (both null), from `state` at
/// t0, or from `resume`, a checkpoint of the same model (not in path following or form
/// finding, which start from their model).
struct AnalysisStart {
  const State* state = nullptr;
  const Checkpoint* resume = nullptr;
  /// The loads' state the analysis goes on from (the step before, in a staged run;
  /// MechanicalSystem::save_load_state): null, the loads start afresh at t0.
  const std::vector<double>* loads = nullptr;
};

/// Who hears a run: `step` after each accepted step (and once at t0 with step 0; false stops
/// the run), `warning` each warning as it arises, `form` what form finding found.
struct AnalysisObservers {
  std::function<bool(const StepSnapshot&)> step;
  std::function<void(const std::string&)> warning;
  FormFindingReport* form = nullptr;
};

/// Every analysis type from one call, which chooses once what runs: form finding (on `model`,
/// the model `system` was built on, whose reference it moves: form_finding.hpp), path following
/// (a static analysis with analysis.path), load stepping, relaxation or dynamics (a time
/// integrator in the time loop).
AnalysisResult run_analysis(Model& model, MechanicalSystem& system,
                            const AnalysisSettings& settings, const AnalysisObservers& observers,
                            const AnalysisStart& from = {});

/// run_analysis for every type but form finding (which needs the model it moves: throws
/// std::invalid_argument), with the observers and the start as arguments.
AnalysisResult run_analysis(MechanicalSystem& system, const AnalysisSettings& settings,
                            const std::function<bool(const StepSnapshot&)>& observer = {},
                            const std::function<void(const std::string&)>& on_warning = {},
                            const State* start = nullptr, const Checkpoint* resume = nullptr);

/// Displacement control (path.method): sets path.equation, when not yet set, to the
/// controlled component's equation in `dofs`, the numbering of `model` (the whole model's:
/// under mpirun it is resolved before the model is shared out). Returns why that component
/// cannot be controlled (fixed, prescribed, normal to a symmetry plane), or an empty string.
std::string resolve_path_equation(PathSettings& path, const Model& model, const DofMap& dofs);

}  // namespace velum
