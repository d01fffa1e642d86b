#include "velum/analysis/analysis.hpp"

#include "velum/analysis/form_finding.hpp"
#include "velum/analysis/plausibility.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "explicit_step.hpp"
#include "velum/math/threads.hpp"
#include "velum/parallel/processes.hpp"

namespace velum {

std::unique_ptr<TimeIntegrator> make_integrator(const AnalysisSettings& s) {
  std::unique_ptr<TimeIntegrator> out;
  if (s.type == AnalysisSettings::Type::kStatic) {
    out = std::make_unique<StaticNewton>(s.predictor == AnalysisSettings::Predictor::kExtrapolate);
  } else if (s.type == AnalysisSettings::Type::kRelaxation) {
    auto dr = std::make_unique<DynamicRelaxation>();
    dr->relaxation = s.relaxation;
    out = std::move(dr);
  } else if (s.scheme == "generalized-alpha")
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

namespace {

// Watches the inertia of static equilibria: one warning each time the path enters an unstable
// stretch (a negative eigenvalue of the tangent stiffness), one when it leaves it.
class StabilityWatch {
 public:
  StabilityWatch(const std::function<void(std::string)>& warn, bool following)
      : warn_(warn), following_(following) {}
  void observe(const AcceptedStep& st) {
    const int neg = st.report ? st.report->negative_pivots : -1;
    // From a stable equilibrium to a stable one through iterations whose tangent was
    // indefinite: under load control that is how a step jumps over a limit point onto the far
    // branch of a snap-through (the pivots at the two ends cannot tell).
    const int seen = st.report ? st.report->negative_pivots_seen : -1;
    if (!following_ && st.report && st.report->branch_jump && !jump_told_) {
      jump_told_ = true;
      warn_(fmt::format(
          "the step to t = {:.6g} (step {}) went from a stable equilibrium to a stable one "
          "through iterations whose tangent stiffness was indefinite ({} negative eigenvalue{}): "
          "the load may have passed a limit point and the step jumped to another branch "
          "(a snap-through; said once). Check with smaller steps, or follow the path with "
          "analysis.path (arc_length or displacement)",
          st.t, st.step, seen, seen == 1 ? "" : "s"));
    }
    if (neg < 0 || neg == last_) return;
    if (neg > 0 && last_ <= 0)
      warn_(fmt::format(
          "unstable equilibrium from t = {:.6g} (step {}): the tangent stiffness has {} negative "
          "eigenvalue{} (past a limit or bifurcation point){}",
          st.t, st.step, neg, neg == 1 ? "" : "s",
          following_ ? ""
                     : "; a load step may jump to another branch. Follow the path with "
                       "analysis.path (arc_length or displacement)"));
    else if (neg == 0 && last_ > 0)
      warn_(fmt::format("stable again from t = {:.6g} (step {})", st.t, st.step));
    last_ = neg;
  }
  int last() const { return last_; }
  void restore(int last) { last_ = last; }

 private:
  std::function<void(std::string)> warn_;
  bool following_;  ///< path following: the path is followed already
  int last_ = 0;
  bool jump_told_ = false;
};

// The energy balance, step by step: the work of the loads by the trapezoidal rule on
// Fext·ΔU (full vectors: loads on prescribed nodes included), the work of prescribed motions
// likewise on the reactions (R·ΔU at eliminated components), the work of sections that change
// in time (MechanicalSystem::section_work), the damping work on the mass-proportional
// Rayleigh force, the loads' work on their own states (a free body's rotation, whose kinetic
// energy counts with the nodes'). The work is booked every step (book); the energies held (kinetic,
// strain) when settle() is called: every step in implicit runs, every few steps and at every output
// in explicit ones (march below).
class EnergyAccount {
 public:
  // `reuse`: book the work from the forces of the step's own evaluation when the system says
  // they are those of the accepted state (explicit steps end on one evaluation).
  EnergyAccount(MechanicalSystem& sys, bool dynamic, double t0, const State& s, Energies& E,
                bool reuse)
      : sys_(sys),
        dynamic_(dynamic),
        prescribed_(!sys.model().prescribed.empty()),
        reuse_(reuse && sys.external_forces_reusable()) {
    U_prev_ = sys.displacements(t0, s.u);
    F_prev_ = sys.external_forces(t0, s.u, s.v);
    if (prescribed_) R_prev_ = sys.reactions(t0, s.u, s.v);
    v_prev_ = s.v;
    E.kinetic = dynamic_ ? sys.kinetic_energy(s.v) + sys.load_kinetic_energy() : 0.0;
    E.strain = sys.strain_energy(t0, s.u);
    held0_ = E.kinetic + E.strain;
    if (reuse_) equations_from_nodes();
  }
  // Books the work (and the damping work) of the step that ended in `cur`.
  void book(const AcceptedStep& st, const State& cur, Energies& E) {
    // Several processes: each process books the work of its share of the forces (nonzero
    // only at nodes it holds) and its share of v·Mv; both summed in one reduction.
    double sums[2] = {0, 0};  // the work, v·Mv
    double& dW = sums[0];
    const double alpha = sys_.model().rayleigh_mass;
    if (alpha != 0) sums[1] = sys_.mass_product_share(cur.v);
    NodePositions U;  // the displacements, where the work is booked on the nodes
    if (reuse_) {
      // Free components only: the others do not move (nothing is prescribed). On several
      // processes the forces are this process's share over its local equations (ghosts
      // included), the displacements whole there.
      dW = book_equations(cur.u);
    } else {
      U = sys_.displacements(st.t, cur.u);
      NodePositions F = sys_.external_forces(st.t, cur.u, cur.v);
      dW = 0.5 * ((F + F_prev_).array() * (U - U_prev_).array()).sum();
      if (prescribed_) {
        NodePositions R = sys_.reactions(st.t, cur.u, cur.v);
        dW += 0.5 * ((R + R_prev_).array() * (U - U_prev_).array()).sum();
        R_prev_ = std::move(R);
      }
      F_prev_ = std::move(F);
    }
    sys_.sum_over_processes(sums, alpha != 0 ? 2 : 1);
    // Whole on every process: the loads' work on their own states (a free body's rotation)
    // and that of sections changing in time (reefing lines, cuts).
    dW += sys_.load_state_work();
    if (!reuse_) {
      dW += sys_.section_work(st.t - st.h, U_prev_, st.t, U);
      U_prev_ = std::move(U);
    }
    E.external_work += dW;
    work_scale_ += std::abs(dW);
    peak_work_ = std::max(peak_work_, std::abs(E.external_work));
    // v·Mv once per step with damping, kept for the next step's damping work and the kinetic
    // energy.
    vmv_now_ = kUnknown;
    if (alpha != 0) {
      vmv_now_ = sums[1];
      if (std::isnan(vmv_prev_)) vmv_prev_ = sys_.dot(v_prev_, sys_.mass_times(v_prev_));
      E.damping += 0.5 * st.h * alpha * (vmv_now_ + vmv_prev_);
      vmv_prev_ = vmv_now_;
      v_prev_ = cur.v;
    }
  }
  // The energies held at `cur`, the last state booked (its time t); returns the full
  // displacements there.
  NodePositions settle(double t, const State& cur, Energies& E) {
    if (dynamic_) {
      const double vmv = std::isnan(vmv_now_) ? sys_.dot(cur.v, sys_.mass_times(cur.v)) : vmv_now_;
      E.kinetic = (sys_.squared_norm(cur.v) != 0 ? 0.5 * vmv : 0.0)  // kinetic_energy()
                  + sys_.load_kinetic_energy();
      vmv_prev_ = vmv;
    }
    E.strain = sys_.strain_energy(t, cur.u);
    v_prev_ = cur.v;
    if (reuse_) {  // the nodal arrays a checkpoint saves
      U_prev_ = sys_.displacements(t, cur.u);
      F_prev_ = sys_.last_external();
    }
    if (const double created = held(E) - E.external_work; created > peak_created_)
      peak_created_ = created, peak_t_ = t;
    return U_prev_;
  }
  /// The balance at the end, measured against the net work and the most work ever done.
  EnergyBalance balance(const Energies& E) const {
    return {.held = held(E),
            .work = E.external_work,
            .peak_work = peak_work_,
            .peak_created = peak_created_,
            .peak_t = peak_t_,
            .held_start = held0_};
  }
  /// Kinetic + strain + damping energy, changes since the start.
  double held(const Energies& E) const { return E.kinetic + E.strain + E.damping - held0_; }
  /// What was held at the start (held() is a change from it).
  double held_start() const { return held0_; }
  double work_scale() const { return work_scale_; }
  /// Whether the balance is a test: in dynamics. Static load steps are equilibria in between
  /// which the trapezoidal work is only as good as the steps are fine (a softening truss in
  /// one step: 29% off), and no blow-up hides there.
  bool balanced() const { return dynamic_; }
  // On several processes (a collective call) the whole arrays on the first process, as one
  // process keeps them: each node's displacement and forces from the process keeping it (the
  // forces' shares completed at the shared nodes first).
  void save(std::vector<double>& m) const {
    m.insert(m.end(), {held0_, work_scale_, peak_work_, peak_created_, peak_t_});
    if (!sys_.distributed()) {
      for (const NodePositions* P : {&U_prev_, &F_prev_, &R_prev_}) put(m, P->data(), P->size());
      put(m, v_prev_.data(), v_prev_.size());
      return;
    }
    const Assembler& a = sys_.assembler();
    for (const NodePositions* P : {&U_prev_, &F_prev_, &R_prev_}) {
      NodePositions W = *P;
      if (W.size() == 0) {  // no reactions kept (alike on every process)
        put(m, W.data(), 0);
        continue;
      }
      if (P != &U_prev_) a.sum_at_shared_nodes(W);  // the forces' shares completed
      W = a.gather_nodes(W);
      put(m, W.data(), W.size());
    }
    const VecX v = sys_.to_global(v_prev_);
    put(m, v.data(), v.size());
  }
  // Reads what save() wrote from m[at]; returns the position after it.
  size_t restore(const std::vector<double>& m, size_t at) {
    held0_ = m.at(at), work_scale_ = m.at(at + 1);
    peak_work_ = m.at(at + 2), peak_created_ = m.at(at + 3), peak_t_ = m.at(at + 4);
    at += 5;
    for (NodePositions* P : {&U_prev_, &F_prev_, &R_prev_}) {
      const auto n = static_cast<Eigen::Index>(m.at(at));
      P->resize(3, n / 3);
      at = take(m, at, P->data(), n);
    }
    v_prev_.resize(static_cast<Eigen::Index>(m.at(at)));
    vmv_prev_ = kUnknown;
    at = take(m, at, v_prev_.data(), v_prev_.size());
    if (sys_.distributed()) {  // back to this process's nodes, shares and equations
      const Assembler& a = sys_.assembler();
      for (NodePositions* P : {&U_prev_, &F_prev_, &R_prev_})
        if (P->size() != 0) *P = a.piece_of(*P);
      for (NodePositions* P : {&F_prev_, &R_prev_}) a.keep_kept_nodes(*P);
      v_prev_ = sys_.to_local(v_prev_);
    }
    if (reuse_) equations_from_nodes();
    return at;
  }

 private:
  static void put(std::vector<double>& m, const double* x, Eigen::Index n) {
    m.push_back(static_cast<double>(n));
    m.insert(m.end(), x, x + n);
  }
  static size_t take(const std::vector<double>& m, size_t at, double* x, Eigen::Index n) {
    if (static_cast<Eigen::Index>(m.at(at)) != n || m.size() < at + 1 + n)
      throw std::invalid_argument("checkpoint: the energy account does not fit this model");
    std::copy(m.begin() + static_cast<long>(at) + 1, m.begin() + static_cast<long>(at) + 1 + n, x);
    return at + 1 + static_cast<size_t>(n);
  }

  // ½ (f + f_prev)·(u − u_prev) over the equations, f the last evaluation's external forces;
  // then f_prev = f, u_prev = u. Where no node has a frame of its own, one pass shared
  // between the threads (fixed blocks: the same bits whatever their number).
  double book_equations(const VecX& u) {
    const DofMap& dofs = sys_.dofs();
    if (dofs.has_frames()) {
      dofs.gather(sys_.last_external(), f_);
      const double dW = 0.5 * (f_ + f_prev_).dot(u - u_prev_);
      f_.swap(f_prev_);
      u_prev_ = u;
      return dW;
    }
    const double* F = sys_.last_external().data();
    const int* eq = dofs.equations();
    double* fp = f_prev_.data();
    double* up = u_prev_.data();
    const double* un = u.data();
    return 0.5 * parallel_sum(3L * dofs.num_nodes(), [&](long first, long last) {
             double sum = 0;
             for (long k = first; k < last; ++k)
               if (const int e = eq[k]; e >= 0) {
                 sum += (F[k] + fp[e]) * (un[e] - up[e]);
                 fp[e] = F[k];
                 up[e] = un[e];
               }
             return sum;
           });
  }
  // The last state's free displacements and external forces (reuse_), from the nodal arrays.
  void equations_from_nodes() {
    sys_.dofs().gather(U_prev_, u_prev_);
    sys_.dofs().gather(F_prev_, f_prev_);
  }

  MechanicalSystem& sys_;
  bool dynamic_, prescribed_, reuse_;
  NodePositions U_prev_, F_prev_, R_prev_;
  VecX v_prev_;
  VecX u_prev_, f_prev_, f_;                                   ///< reuse_: in equations
  double vmv_now_ = std::numeric_limits<double>::quiet_NaN();  ///< this step's v·Mv, if known
  static constexpr double kUnknown = std::numeric_limits<double>::quiet_NaN();
  double vmv_prev_ = kUnknown;  ///< v_prev_ · M v_prev_, once known
  double held0_ = 0, work_scale_ = 0;
  double peak_work_ = 0;     ///< the largest |work done| reached
  double peak_created_ = 0;  ///< the largest energy created (held − work) and when
  double peak_t_ = 0;
};

// Generalized-α keeps a share ρ∞ of the highest frequencies; on a slack sheet going taut (a
// bag inflated from its fold, with or without wrinkling) those in-plane modes gain energy
// step after step, and smaller steps do not stop it (the 15 x 15 slack bag under 2 kPa: 152 J
// created against 6.6 J of work at ρ∞ 0.8 with a step of 1e-4, none at ρ∞ 0.5; inflated by gas
// with wrinkling it needed ρ∞ 0). Central difference at a safety above the default meets its
// nonlinear resonances (docs/performance.md). A failed energy balance says which.
std::string energy_failure_hint(const AnalysisSettings& settings, const std::string& why) {
  if (why.find("energy balance fails") == std::string::npos ||
      settings.type != AnalysisSettings::Type::kDynamic)
    return {};
  // The step is at most safety x 2/ω_max: the stiffest mode's h ω up to 2 safety.
  using Step = ExplicitStepSettings;
  if (const double safety = settings.explicit_step.safety;
      settings.explicit_steps() && 2 * safety > Step::kBelowResonances)
    return fmt::format(
        "; central difference at safety {:g} puts the stiffest mode at h ω up to {:.2f}, among its "
        "nonlinear resonances (h ω = √2, √3), where a struck sheet gains energy: "
        "analysis.integrator.safety {:g} (the default) stays below them (docs/performance.md, "
        "\"Nonlinear resonance\")",
        safety, 2 * safety, Step::kDefaultSafety);
  if (settings.scheme != "generalized-alpha" || settings.rho_inf <= 0.5) return {};
  return fmt::format(
      "; generalized-alpha with rho_inf {:g} keeps most of the highest frequencies, which a "
      "slack or wrinkling sheet going taut can pump: analysis.integrator.rho_inf: 0 damps them "
      "(docs/wrinkling.md)",
      settings.rho_inf);
}

// Load stepping, relaxation, dynamics (the time loop) and path following: the analyses that
// march a fixed model, with one energy account, stability watch and plausibility check.
AnalysisResult march(MechanicalSystem& sys, const AnalysisSettings& settings,
                     const std::function<bool(const StepSnapshot&)>& observer,
                     const std::function<void(const std::string&)>& on_warning, const State* start,
                     const Checkpoint* resume, const std::vector<double>* loads = nullptr) {
  AnalysisResult result;
  auto warn = [&](std::string w) {
    if (on_warning) on_warning(w);
    result.warnings.push_back(std::move(w));
  };
  StabilityWatch stability(warn, settings.type == AnalysisSettings::Type::kStatic &&
                                     settings.path.method != PathSettings::Method::kLoadControl);
  auto integrator = make_integrator(settings);
  auto solver = make_solver(sys, settings);
  result.integrator = integrator->name();
  result.solver = std::string(solver->name());
  result.dofs = static_cast<int>(sys.global_size());

  State s;
  s.u = VecX::Zero(sys.size());
  s.v = VecX::Zero(sys.size());
  s.a = VecX::Zero(sys.size());
  // At rest where the sheet starts: at its reference, or displaced from it by the model's
  // reference positions.
  if (sys.model().U0.size()) sys.dofs().gather(sys.model().U0, s.u);
  if (start) s = *start;
  if (!start && !resume) {
    NodePositions V0 = NodePositions::Zero(3, sys.model().num_nodes());
    for (const InitialVelocity& iv : sys.model().initial_velocities)
      for (int n : iv.nodes) V0.col(n) = iv.velocity;
    if (!sys.model().initial_velocities.empty()) sys.dofs().gather(V0, s.v);
  }
  if (resume) {
    s = resume->state;
    s.u = sys.to_local(s.u), s.v = sys.to_local(s.v), s.a = sys.to_local(s.a);
  }
  // The loads' state integrated in time (a gas chamber's): from the checkpoint, from the step
  // before, or afresh at the start.
  if (resume && !resume->loads.empty())
    sys.restore_load_state(resume->loads);
  else if (loads)
    sys.restore_load_state(*loads);
  else
    sys.start_loads(settings.time.t0, s.u, s.v);

  TimeLoopSettings loop = settings.time;
  // Central difference: the step is safety x the stable step (capped by time.step), estimated
  // at the start (after mass scaling) and, from the current state, at every trust check.
  const bool explicit_run = !integrator->implicit();
  ExplicitStepControl explicit_step(sys, settings, result.explicit_step, warn);
  if (resume) {
    loop.step = resume->loop.step;
  } else if (explicit_run) {
    loop.step = explicit_step.start(loop.t0, s);
    result.stable_step = result.explicit_step.first;
  }
  if (explicit_run) {
    loop.adaptive = false;
    // min_step plays no part without step control, but stretches a step that would stop
    // short of an output time by up to it: kept far below any step the run may set.
    loop.min_step = std::min(loop.min_step, 1e-6 * loop.step);
  }

  Energies& E = result.energy;
  // Explicit steps cost little beside the trust checks (the inversion check, the energies
  // held, plausibility: each a pass over the elements or nodes): they run every
  // kExplicitCheckInterval steps, at every output time, checkpoint and the end; the work of the
  // loads is booked every step. Implicit steps check every step.
  const int check_interval = integrator->implicit() ? 1 : kExplicitCheckInterval;
  int unchecked = 0;  ///< steps since the last check
  EnergyAccount energy(sys, settings.type == AnalysisSettings::Type::kDynamic, loop.t0, s, E,
                       !integrator->implicit());
  PlausibilityCheck plausible(sys.model());
  plausible.share_nodes(sys.assembler());
  plausible.set_kinetic_start(E.kinetic);  // the start's (or the checkpoint's, on a restart)
  std::string implausible;

  const bool dynamic = settings.type == AnalysisSettings::Type::kDynamic;
  VecX u_last = s.u;
  double t_last = loop.t0;
  bool warned_fold = false;
  if (resume) {  // the memory laid out by make_checkpoint below
    E = resume->energy;
    result.warnings = resume->warnings;
    integrator->restore(sys, resume->integrator);
    const std::vector<double>& m = resume->analysis;
    if (m.size() < 3) throw std::invalid_argument("checkpoint: no analysis memory");
    stability.restore(static_cast<int>(m[0]));
    warned_fold = m[1] != 0;
    t_last = m[2];
    const size_t at = energy.restore(m, 3);
    if (explicit_run) explicit_step.restore(m, at);
  } else {
    AcceptedStep first{.t = loop.t0, .output_time = true};
    if (observer && !observer(StepSnapshot{first, sys, s, E})) return result;
  }
  const AcceptedStep* current = nullptr;
  const State* current_state = nullptr;
  const std::function<Checkpoint()> make_checkpoint = [&] {
    Checkpoint c;
    const AcceptedStep& st = *current;
    c.loop = {.t = st.t,
              .step = loop.step,
              .steps = st.step,
              .iterations = st.total_iterations,
              .factorizations = st.total_factorizations,
              .cutbacks = st.cutbacks,
              .control = st.control ? *st.control : StepControlState{}};
    // Central difference: the step the run goes on with (set at this step's check).
    if (explicit_run) c.loop.control.h = loop.step;
    c.state = *current_state;
    if (unchecked != 0) energy.settle(st.t, *current_state, E);  // what the checkpoint saves
    if (sys.distributed()) {  // whole, in the global numbering, on the first process
      c.state.u = sys.to_global(c.state.u);
      c.state.v = sys.to_global(c.state.v);
      c.state.a = sys.to_global(c.state.a);
    }
    c.energy = E;
    c.integrator = integrator->save(sys);
    c.analysis = {static_cast<double>(stability.last()), warned_fold ? 1.0 : 0.0, t_last};
    energy.save(c.analysis);
    if (explicit_run) explicit_step.save(c.analysis);
    c.loads = sys.save_load_state();
    c.warnings = result.warnings;
    return c;
  };
  auto on_step = [&](const AcceptedStep& st, const State& cur) {
    // Before anything reads the loads at the new state; an explicit step's state is that of
    // its one evaluation (its positions kept).
    sys.accept(st.t, cur.u, cur.v, !integrator->implicit());
    stability.observe(st);
    energy.book(st, cur, E);
    current = &st, current_state = &cur;
    if (++unchecked < check_interval && !st.output_time)
      return !observer ||
             observer(StepSnapshot{st, sys, cur, E, st.control ? &make_checkpoint : nullptr});
    unchecked = 0;
    if (dynamic && !warned_fold) {  // static steps never accept one (integrators.cpp)
      if (std::string inv = sys.inverted_element(t_last, u_last, st.t, cur.u); !inv.empty()) {
        warned_fold = true;
        warn(inv +
             " (folded through zero area or length): results near it are those of a "
             "collapsed element");
      }
      u_last = cur.u, t_last = st.t;
    }
    const NodePositions U = energy.settle(st.t, cur, E);
    implausible = plausible.check(st.t, U, cur, energy.balanced(), energy.held(E), E.external_work,
                                  energy.work_scale(), energy.held_start());
    if (!implausible.empty()) return false;
    if (explicit_run && st.next_step) {
      loop.step = explicit_step.update(st.t, st.h, cur, loop.step);
      *st.next_step = loop.step;
    }
    return !observer ||
           observer(StepSnapshot{st, sys, cur, E, st.control ? &make_checkpoint : nullptr});
  };
  if (settings.type == AnalysisSettings::Type::kStatic &&
      settings.path.method != PathSettings::Method::kLoadControl) {
    PathSettings path = settings.path;
    // (Under mpirun set from the whole model before it was shared out.)
    // A component that cannot be controlled leaves equation < 0: run_path_following says so.
    (void)resolve_path_equation(path, sys.model(), sys.dofs());
    result.integrator = path.method == PathSettings::Method::kDisplacement ? "displacement control"
                        : path.constraint == PathSettings::Constraint::kRiks
                            ? "arc length (Riks)"
                            : "arc length (Crisfield)";
    result.loop = run_path_following(sys, *solver, settings.newton, loop, path, s, on_step);
  } else {
    result.loop = run_time_loop(sys, *integrator, *solver, loop, s, on_step,
                                resume ? &resume->loop : nullptr);
  }
  // A run that stopped between checks: the energies of its last state.
  if (unchecked != 0 && implausible.empty()) energy.settle(result.loop.t, s, E);
  if (!implausible.empty()) {
    result.loop.stopped = false;
    result.loop.reason = implausible + energy_failure_hint(settings, implausible);
  }
  if (result.loop.completed && energy.balanced()) {
    if (std::string off = plausible.final_balance(result.loop.t, energy.balance(E), warn);
        !off.empty()) {
      result.loop.completed = false;
      result.loop.reason = off + energy_failure_hint(settings, off);
    }
  }
  if (result.loop.completed)
    for (const auto& term : sys.loads())
      if (std::string wrong = term->end_check(warn); !wrong.empty()) {
        result.loop.completed = false;
        result.loop.reason = std::move(wrong);
        break;
      }
  result.solver = std::string(solver->name());  // what `auto` settled on
  result.factorizations = solver->factorizations();
  result.analyses = solver->analyses();
  return result;
}

}  // namespace

AnalysisResult run_analysis(Model& model, MechanicalSystem& system,
                            const AnalysisSettings& settings, const AnalysisObservers& observers,
                            const AnalysisStart& from) {
  switch (settings.type) {
    case AnalysisSettings::Type::kFormFinding:
      return run_form_finding(model, system, settings, observers.step, observers.warning,
                              observers.form);
    case AnalysisSettings::Type::kStatic:
    case AnalysisSettings::Type::kDynamic:
    case AnalysisSettings::Type::kRelaxation:
      break;
  }
  return march(system, settings, observers.step, observers.warning, from.state, from.resume,
               from.loads);
}

AnalysisResult run_analysis(MechanicalSystem& system, const AnalysisSettings& settings,
                            const std::function<bool(const StepSnapshot&)>& observer,
                            const std::function<void(const std::string&)>& on_warning,
                            const State* start, const Checkpoint* resume) {
  if (settings.type == AnalysisSettings::Type::kFormFinding)
    throw std::invalid_argument(
        "form finding moves its model's reference: run_analysis(model, system, ...)");
  return march(system, settings, observer, on_warning, start, resume);
}

std::string resolve_path_equation(PathSettings& path, const Model& model, const DofMap& dofs) {
  if (path.method != PathSettings::Method::kDisplacement || path.equation >= 0) return {};
  path.equation = dofs.global_equation(path.node, path.component);
  if (path.equation >= 0) return {};
  return fmt::format(
      "analysis.path: node {} {} is fixed, prescribed or normal to a symmetry plane: "
      "displacement control needs a free component",
      model.node_ids[static_cast<size_t>(path.node)], "xyz"[path.component]);
}

namespace {

const AnalysisTypeInfo& info_of(AnalysisSettings::Type t) {
  for (const AnalysisTypeInfo& i : kAnalysisTypes)
    if (i.type == t) return i;
  throw std::logic_error("an analysis type without its row in kAnalysisTypes");
}

}  // namespace

std::string AnalysisSettings::type_name() const {
  return info_of(type).name;
}

std::string AnalysisSettings::method() const {
  const AnalysisTypeInfo& i = info_of(type);
  return *i.method ? i.method : scheme;
}

std::string AnalysisSettings::run_name() const {
  if (type == Type::kStatic && path.method != PathSettings::Method::kLoadControl)
    return path.method == PathSettings::Method::kDisplacement
               ? "path following (displacement control)"
           : path.constraint == PathSettings::Constraint::kRiks
               ? "path following (arc length, Riks)"
               : "path following (arc length, cylindrical)";
  const AnalysisTypeInfo& i = info_of(type);
  return *i.run ? std::string(i.run) : "dynamic run (" + scheme + ")";
}

}  // namespace velum
