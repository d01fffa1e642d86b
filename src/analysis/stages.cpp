#include "velum/analysis/stages.hpp"

#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <stdexcept>

#include "velum/parallel/processes.hpp"

namespace velum {

void shift_functions(Model& model, double t0) {
  if (t0 == 0) return;
  for (TimeFunction& f : model.functions) {
    if (f.kind == TimeFunction::Kind::kRamp) {
      f.kind = TimeFunction::Kind::kTable;
      f.points = {{t0, 0.0}, {t0 + f.duration, 1.0}};
    } else if (f.kind == TimeFunction::Kind::kTable) {
      for (auto& p : f.points) p.first += t0;
    }
  }
}

namespace {

template <class T>
void same_list(const std::vector<T>& a, const std::vector<T>& b, const char* what) {
  if (a.size() != b.size())
    throw std::logic_error(
        fmt::format("a step goes on with the {} before it, but they differ "
                    "in number ({} and {})",
                    what, a.size(), b.size()));
}

}  // namespace

void hold_loads(Model& step, const Model& before, double t) {
  if (step.loads.size() != before.loads.size())
    throw std::logic_error(
        fmt::format("a step goes on with the loads before it, but they differ in number ({} and "
                    "{})",
                    step.loads.size(), before.loads.size()));
  for (size_t i = 0; i < step.loads.size(); ++i) {
    if (step.loads[i].kind() != before.loads[i].kind())
      throw std::logic_error(fmt::format(
          "a step goes on with the loads before it, but load {} is a {} load there and a {} "
          "load here",
          i, before.loads[i].kind(), step.loads[i].kind()));
    step.loads.replace(i, before.loads[i].held(t, before, step));
  }
}

void hold_boundary(Model& step, const Model& before, double t) {
  same_list(step.prescribed, before.prescribed, "prescribed motions");
  for (size_t i = 0; i < step.prescribed.size(); ++i) {
    const PrescribedMotion& b = before.prescribed[i];
    step.prescribed[i].displacement = b.displacement * before.function_value(b.function, t);
    step.prescribed[i].function = -1;
  }
}

void move_reference(Model& model, const NodePositions& x) {
  model.X = x;
  for (auto& b : model.blocks) b = b->on_reference(x, 0.0);
  for (auto& load : model.loads) load->set_up(model);
}

namespace {

/// The state at the end of a step as full nodal vectors (they outlive its equation numbering).
struct NodalState {
  NodePositions U, V, A;
};

NodalState nodal(const MechanicalSystem& sys, double t, const State& s) {
  return {sys.displacements(t, s.u), sys.velocities(s.v), sys.velocities(s.a)};
}

/// The state of the step that `sys` solves, from the end of the step before; a message when a
/// node's constrained components would put it elsewhere than where that step left it.
State carry_in(const MechanicalSystem& sys, double t, const NodalState& n, std::string& jump) {
  State s;
  s.u.resize(sys.size()), s.v.resize(sys.size()), s.a.resize(sys.size());
  sys.dofs().gather(n.U, s.u);
  sys.dofs().gather(n.V, s.v);
  sys.dofs().gather(n.A, s.a);
  const NodePositions U = sys.displacements(t, s.u);
  const Model& m = sys.model();
  const double size = (m.X.rowwise().maxCoeff() - m.X.rowwise().minCoeff()).norm();
  const double tol = 1e-9 * (size + n.U.cwiseAbs().maxCoeff());
  int worst = -1;
  double worst_d = tol;
  for (int i = 0; i < m.num_nodes(); ++i)
    if (const double d = (U.col(i) - n.U.col(i)).norm(); d > worst_d) worst = i, worst_d = d;
  if (worst >= 0)
    jump = fmt::format(
        "node {} would jump by {:.6g} at the start of the step: its fixed, prescribed or "
        "symmetry components put it elsewhere than where the step before left it (fixed "
        "components hold zero displacement from the reference, prescribed motions are measured "
        "from it); leave it free, or prescribe where it is",
        m.node_ids[static_cast<size_t>(worst)], worst_d);
  return s;
}

}  // namespace

namespace {

// The run of the steps: what goes on from one to the next.
class StageRunner {
 public:
  StageRunner(std::vector<AnalysisStep>& steps, const PreparedSteps& prepared, Model& slot,
              const StageObserver& obs)
      : steps_(steps), prepared_(prepared), slot_(slot), obs_(obs) {
    out_.steps.resize(steps.size());
  }

  StagedResult run() {
    for (size_t k = 0; k < steps_.size(); ++k) {
      const std::string which =
          fmt::format("step '{}' ({} of {})", steps_[k].name, k + 1, steps_.size());
      StepOutcome& o = out_.steps[k];
      o.run = true;
      o.t_start = o.t_end = t_;
      if (static_cast<int>(k) == prepared_.failed) {
        out_.failed = static_cast<int>(k);
        out_.reason = which + ": " + prepared_.reason;
        return std::move(out_);
      }
      try {
        if (!step(k, o)) {
          out_.failed = static_cast<int>(k);
          out_.reason = which + ": " + reason_;
          return std::move(out_);
        }
      } catch (const std::exception& e) {  // a model that cannot be set up, a solver that throws
        out_.failed = static_cast<int>(k);
        out_.reason = which + ": " + e.what();
        return std::move(out_);
      }
    }
    out_.completed = true;
    return std::move(out_);
  }

 private:
  // Runs step k; false (reason_ set) when it fails.
  bool step(size_t k, StepOutcome& o) {
    AnalysisStep& step = steps_[k];
    Model& m = step.model;  // prepared: in total time, with what it holds from the step before
    if (found_) {
      move_reference(m, *found_);
      // The motions held from form finding brought their nodes to the found shape: from it,
      // they hold them where they are.
      if (!step.boundary_given && !have_state_)
        for (PrescribedMotion& p : m.prescribed) p.displacement.setZero();
    }
    slot_ = std::move(m);
    MechanicalSystem sys(slot_);
    AnalysisSettings settings = step.analysis;
    settings.time.t0 = t_;
    settings.time.t_end = t_ + step.analysis.time.t_end;
    // A static step's time is a load level: the output interval, shared by the steps and often
    // set for a dynamic one, does not cut its load steps. Its states are written at the first
    // load step at or past each output time, and at its end.
    double every = 0, next_output = 0;
    if (settings.type == AnalysisSettings::Type::kStatic && settings.time.output_interval > 0) {
      every = settings.time.output_interval;
      settings.time.output_interval = 0;  // the loop lands on the step's end only
      next_output = (std::floor(t_ / every + 1e-9) + 1) * every;
    }
    State start;
    if (have_state_) {
      start = carry_in(sys, t_, carried_, reason_);
      // Several processes: each checks its piece's nodes, and all stop together.
      if (!processes::all(reason_.empty())) {
        if (reason_.empty())
          reason_ = "a node of another process would jump at the start of the step";
        return false;
      }
    }
    if (obs_.begin) obs_.begin(static_cast<int>(k), sys);
    State last = start;
    // The loads' state integrated in time (a gas chamber's) goes on when the step holds the
    // loads before it; loads of its own start afresh.
    const bool carry_loads = have_state_ && !step.loads_given && !carried_loads_.empty();
    // The laws' history per point (plasticity) goes on whatever the step's loads.
    if (have_state_ && !carried_history_.empty()) sys.restore_law_history(carried_history_);
    const auto observe = [&](const StepSnapshot& snap) {
      last = snap.state;
      if (k > 0 && snap.step.step == 0) return true;  // the end of the step before
      Energies E = snap.energy;
      E.external_work += before_.external_work;
      E.damping += before_.damping;
      AcceptedStep accepted = snap.step;
      if (every > 0 && accepted.step > 0 && accepted.t >= next_output * (1 - 1e-12)) {
        accepted.output_time = true;
        next_output = (std::floor(accepted.t / every + 1e-9) + 1) * every;
      }
      return !obs_.step ||
             obs_.step(static_cast<int>(k),
                       StepSnapshot{accepted, snap.system, snap.state, E, snap.checkpoint});
    };
    o.result =
        run_analysis(slot_, sys, settings, {.step = observe, .warning = obs_.warn, .form = &o.form},
                     {.state = have_state_ ? &start : nullptr,
                      .loads = carry_loads ? &carried_loads_ : nullptr});
    const TimeLoopResult& loop = o.result.loop;
    o.t_end = loop.completed ? settings.time.t_end : loop.t;
    out_.energy = o.result.energy;
    out_.energy.external_work += before_.external_work;
    out_.energy.damping += before_.damping;
    if (!loop.completed) {
      out_.stopped = loop.stopped;
      reason_ = loop.reason.empty() ? "stopped" : loop.reason;
      return false;
    }
    t_ = settings.time.t_end;
    if (settings.type == AnalysisSettings::Type::kFormFinding) {
      // The found shape is the reference from here on: the state and the account start again.
      found_ = o.form.shape;
      have_state_ = false;
      before_ = Energies{};
      out_.energy = Energies{};
      return true;
    }
    before_.external_work = out_.energy.external_work;
    before_.damping = out_.energy.damping;
    carried_ = nodal(sys, t_, last);
    carried_loads_ = sys.save_load_state();
    carried_history_ = sys.save_law_history();
    if (settings.equilibrium()) {  // an equilibrium is at rest, whatever came before it
      carried_.V.setZero();
      carried_.A.setZero();
    }
    have_state_ = true;
    return true;
  }

  std::vector<AnalysisStep>& steps_;
  const PreparedSteps& prepared_;
  Model& slot_;
  const StageObserver& obs_;
  StagedResult out_;
  std::string reason_;
  double t_ = 0;
  Energies before_;  ///< work and damping of the steps done (since the last form finding)
  NodalState carried_;
  std::vector<double> carried_loads_;    ///< MechanicalSystem::save_load_state at the end
  std::vector<double> carried_history_;  ///< MechanicalSystem::save_law_history at the end
  bool have_state_ = false;              ///< false: the step starts at rest on its reference
  std::optional<NodePositions> found_;
};

}  // namespace

PreparedSteps prepare_steps(std::vector<AnalysisStep>& steps) {
  PreparedSteps out;
  double t = 0;  // where step k starts
  for (size_t k = 0; k < steps.size(); ++k) {
    AnalysisStep& step = steps[k];
    try {
      shift_functions(step.model, t);
      if (k > 0 && !step.loads_given) hold_loads(step.model, steps[k - 1].model, t);
      if (k > 0 && !step.boundary_given) hold_boundary(step.model, steps[k - 1].model, t);
    } catch (const std::exception& e) {  // lists that do not go on: the step fails there
      out.failed = static_cast<int>(k);
      out.reason = e.what();
      return out;
    }
    t += step.analysis.time.t_end;
  }
  return out;
}

StagedResult run_stages(std::vector<AnalysisStep>& steps, const PreparedSteps& prepared,
                        Model& slot, const StageObserver& obs) {
  return StageRunner(steps, prepared, slot, obs).run();
}

StagedResult run_stages(std::vector<AnalysisStep>& steps, Model& slot, const StageObserver& obs) {
  const PreparedSteps prepared = prepare_steps(steps);
  return StageRunner(steps, prepared, slot, obs).run();
}

}  // namespace velum
