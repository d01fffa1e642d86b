// Whether a run's answer can be true, checked after each accepted step (docs/trust.md): no
// non-finite value, no deformation beyond a multiple of the model's size, no energy created
// from nothing. A converged Newton iteration says the equations hold, not that the answer is
// physical: an unstable explicit step, a blow-up with damping or a material in the wrong units
// all converge.
#pragma once

#include <functional>
#include <string>

#include "velum/assembly/assembler.hpp"
#include "velum/model/model.hpp"
#include "velum/time/integrators.hpp"

namespace velum {

struct PlausibilityLimits {
  /// Largest node distance from the mean displacement (the rigid translation), in bounding-box
  /// diagonals of the reference model, before the run fails.
  double spread = 10;
  /// The energy the system holds and has dissipated (kinetic + strain + damping, changes since
  /// the start) may exceed the work done on it (external loads and prescribed motions) by this
  /// multiple of the work's magnitude before the run fails (a blow-up creates orders of
  /// magnitude; generalized-α's overshoot in its first steps 75% of the little work done)...
  double energy_fail = 10;
  /// ... and at the end of the run by this fraction before a warning.
  double energy_warn = 0.1;
  /// ... and fails when it exceeds it by this multiple (as energy_fail during the run: a
  /// folded element creates about as much as the work, 111% on the small C9 canopy, which
  /// stays a warning).
  double energy_fail_end = 10;
};

/// A run's energy account at its end (changes since its start).
struct EnergyBalance {
  double held = 0;          ///< kinetic + strain + damping energy
  double work = 0;          ///< net work done on the model
  double peak_work = 0;     ///< the largest |work done| reached during the run
  double peak_created = 0;  ///< the largest held − work reached, at time peak_t
  double peak_t = 0;
  double held_start = 0;  ///< held at the start (its round-off)
};

class PlausibilityCheck {
 public:
  explicit PlausibilityCheck(const Model& model, PlausibilityLimits limits = {});
  /// After an accepted step at t: U the full displacements; with `energy`, `held` the energy
  /// in the system and dissipated (changes since the start), `work` the work done on it and
  /// `work_scale` the sum of the magnitudes of its increments, `held_start` the energy held at
  /// the start (`held` is a difference from it, and carries its round-off). Empty when
  /// plausible, else why not (the run fails).
  std::string check(double t, const NodePositions& U, const State& s, bool energy, double held,
                    double work, double work_scale, double held_start = 0) const;
  /// The balance at the end of a run that completed, against the net work and the most work
  /// ever done (not the sum of the magnitudes of the work increments, which an oscillation
  /// grows without end): a warning (to `warn`) when the solution created more than
  /// energy_warn of it, at the end or at any time before (an energy spike: an element that
  /// folded); returns why the run fails when it created more than energy_fail_end of it at
  /// the end (empty: it does not).
  std::string final_balance(double t, const EnergyBalance& b,
                            const std::function<void(std::string)>& warn) const;
  double model_size() const { return size_; }
  /// The kinetic energy at the run's start (an initial velocity; alike on every process): with
  /// no load doing work, the energy the solution moves between kinetic and strain, with the
  /// integrator's own error. The energy-created limits scale with it beside the work.
  void set_kinetic_start(double kinetic) { kinetic_start_ = std::abs(kinetic); }
  /// Several processes: each holds the displacements of its own nodes only; the checks
  /// count each node on the process keeping it (Assembler::keeps_node) and reduce.
  void share_nodes(const Assembler& a) { assembler_ = &a; }

 private:
  PlausibilityLimits limits_;
  double size_ = 0;
  double stored_ = 0;
  double kinetic_start_ = 0;  ///< the prestress's energy per unit strain (the energy floor's)
  const Assembler* assembler_ = nullptr;
};

}  // namespace velum
