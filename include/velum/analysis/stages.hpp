// Staged analyses (docs/model-format.md "Analysis steps", docs/fabric-structures.md): one model
// solved in several steps in sequence, each with its own analysis, boundary conditions and
// loads. The steps are put end to end in time: step k runs from where step k-1 ended, and
// the time functions of its own loads and motions run in step time (from 0 at its start). The
// state goes on from step to step (displacements, velocities, accelerations, and the energy
// account); a form-finding step instead ends by making the found shape, with its prestress,
// the reference of the steps after it (displacements and the energy account start again from
// zero there). Loads and boundary conditions a step does not give go on from the step before,
// each held at the value it had reached (Abaqus's propagation). On several processes every
// step's model is cut to the same piece (assembly/share_model.hpp, MeshSharing): the same
// elements and nodes in every step, so that the state goes on node by node.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "velum/analysis/analysis.hpp"
#include "velum/analysis/form_finding.hpp"

namespace velum {

/// One step as read from a model file: its analysis (times in step time: analysis.time.end
/// is the step's duration) and the model with the boundary conditions and loads active in it.
struct AnalysisStep {
  std::string name;
  int line = 0;  ///< 1-based line of the step in the model file (0: unknown)
  Model model;
  AnalysisSettings analysis;  ///< time.output_interval: the output interval of the step
  /// false: the step gave no `boundary:` (or `loads:`) and goes on with the list before it,
  /// each item held at the value it had reached.
  bool boundary_given = false, loads_given = false;
};

/// What became of one step.
struct StepOutcome {
  bool run = false;  ///< false: an earlier step failed
  double t_start = 0, t_end = 0;
  AnalysisResult result;   ///< energy: of this step alone
  FormFindingReport form;  ///< form-finding steps
};

struct StagedResult {
  std::vector<StepOutcome> steps;
  bool completed = false, stopped = false;
  int failed = -1;     ///< index of the step that failed or was stopped
  std::string reason;  ///< names the step
  Energies energy;     ///< at the end: work and damping summed over the steps
};

/// What the caller (the results writer) hears.
struct StageObserver {
  /// Step k begins: `system` solves it, on the model now in the slot.
  std::function<void(int k, MechanicalSystem& system)> begin;
  /// After each accepted step (energies of the whole run so far); false stops the run. The
  /// state at a step's start is shown only for the first step (it is the end of the one before).
  std::function<bool(int k, const StepSnapshot&)> step;
  std::function<void(const std::string&)> warn;
};

/// The steps' models made ready, in order, before any of them runs: time functions in total
/// time (each step starts where the ones before it end) and the loads and motions a step does
/// not give held from the step before. What cannot be made ready fails that step when it is
/// reached (failed: its index, -1 none).
struct PreparedSteps {
  int failed = -1;
  std::string reason;
};
PreparedSteps prepare_steps(std::vector<AnalysisStep>& steps);

/// Runs the prepared steps in order in `slot`, into which each step's model is moved when it
/// begins (so that whoever holds `slot` sees the model being solved). Stops at the first step
/// that fails. Throws std::invalid_argument for a step whose model cannot be set up.
StagedResult run_stages(std::vector<AnalysisStep>& steps, const PreparedSteps& prepared,
                        Model& slot, const StageObserver& obs);
/// prepare_steps, then run_stages.
StagedResult run_stages(std::vector<AnalysisStep>& steps, Model& slot, const StageObserver& obs);

// The parts of run_stages, for tests.

/// Time functions from step time to total time: the step starts at t0.
void shift_functions(Model& model, double t0);
/// The loads of `step` are those of `before` (the same list), each held at its value at t.
void hold_loads(Model& step, const Model& before, double t);
/// The prescribed motions of `step` are those of `before`, each held at its value at t.
void hold_boundary(Model& step, const Model& before, double t);
/// The found shape x becomes the reference, the sections' prestress on it.
void move_reference(Model& model, const NodePositions& x);

}  // namespace velum
