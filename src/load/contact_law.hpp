// The contact law at one node against a rigid surface: the normal force of the augmented
// penalty (with a viscous part on the normal velocity while in touch, where damped), Coulomb
// friction with a tangential penalty on the slip since the anchor (stick) and the return to
// the cone (slip), and its consistent derivatives ∂f/∂x (unsymmetric in slip) and ∂f/∂v.
// Fixed size, allocation-free: called for every node of a contact set at every residual.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "velum/math/types.hpp"

namespace velum::contact {

/// Penetrations past this many tolerances go through the contact thickness (the default
/// tolerance is 1% of it): the answer is not one of contact.
inline constexpr double kThroughRatio = 100;

/// The largest penetration over its tolerance at any accepted step, and when: a contact whose
/// last state is apart (a sheet bouncing on a body) may have gone deep on the way. Carried
/// through checkpoints, so that a restarted run's end check sees the whole run's.
struct PeakPenetration {
  double ratio = 0, time = 0;
  void note(double r, double t) {
    if (r > ratio) ratio = r, time = t;
  }
  /// At the end of a contact's saved state, behind a tag: a checkpoint written before it was
  /// carried (2026-12-07) has the next load's length there, a count, never the tag.
  static constexpr double kTag = -0x1.5eedp+1000;
  void save(std::vector<double>& out) const { out.insert(out.end(), {kTag, ratio, time}); }
  size_t restore(const std::vector<double>& in, size_t at) {
    if (at + 3 > in.size() || in[at] != kTag) return at;  // an older checkpoint: from here on
    ratio = in[at + 1], time = in[at + 2];
    return at + 3;
  }
};

/// A contact's end-of-run check (LoadTerm::end_check) from its largest penetration over its
/// tolerance at the last accepted step (`ratio`): past kThroughRatio why the run fails, past 1
/// a warning. Then the largest over the run (`peak`; its time NaN where not known: another
/// process's): past kThroughRatio a warning, since a sheet a body passed through ends apart
/// from it, on the wrong side, which the last step cannot tell from contact kept; past 1 (and
/// deeper than the last step's) a warning too, since every accepted state should keep within
/// the tolerance (an impact's transient penetration often does not). `what` names
/// the contact ("contact 0 with 'floor'"), `where` the penetration ("inside the body, through
/// the contact thickness").
inline std::string penetration_check(double ratio, const PeakPenetration& peak,
                                     const std::string& what, std::string_view where,
                                     const std::function<void(std::string)>& warn) {
  if (ratio > kThroughRatio)
    return fmt::format(
        "{} not kept: a node is {:.3g} tolerances {}: the penalty is too soft for the load "
        "(raise penalty_scale)",
        what, ratio, where);
  if (ratio > 1)
    warn(fmt::format("{} penetrates {:.3g} times its tolerance at the end (raise penalty_scale)",
                     what, ratio));
  const std::string when =
      std::isnan(peak.time) ? std::string() : fmt::format(" at t = {:.6g}", peak.time);
  if (peak.ratio > kThroughRatio)
    warn(fmt::format(
        "{}: a node went {:.3g} tolerances {}{}, apart again at the end: the penalty is too soft "
        "there (raise penalty_scale)",
        what, peak.ratio, where, when));
  else if (peak.ratio > 1 && peak.ratio > ratio)
    warn(
        fmt::format("{}: a node went {:.3g} times its tolerance deep{} (an accepted state; the "
                    "tolerance: 1% of the thickness or 1e-3 of the element size): raise "
                    "penalty_scale for less",
                    what, peak.ratio, when));
  return {};
}

enum class Status : int { kOpen = 0, kStick = 1, kSlip = 2 };

struct NodeInput {
  double g = 0;            ///< gap beyond the contact thickness (positive: apart)
  Vec3 n = Vec3::UnitZ();  ///< the surface's outward unit normal at the node
  Mat3 H = Mat3::Zero();   ///< ∂n/∂x
  Vec3 w = Vec3::Zero();   ///< the node's position minus its anchor's (friction)
  double lambda = 0;       ///< the normal multiplier (force) of the last accepted step
  double k = 0;            ///< the penalty (force per length)
  double mu = 0;           ///< the friction coefficient
  double c = 0;            ///< the normal damping (force per velocity; 0: none)
  Vec3 v = Vec3::Zero();   ///< the node's velocity relative to the body's point it is at
};

struct NodeResult {
  Vec3 f = Vec3::Zero();     ///< the force on the node
  Mat3 D = Mat3::Zero();     ///< ∂f/∂x (filled when asked)
  Mat3 Dv = Mat3::Zero();    ///< ∂f/∂v, v the relative velocity (filled when asked, c > 0)
  double p = 0;              ///< the normal force
  Vec3 slip = Vec3::Zero();  ///< the elastic slip the tangential force stands for (f_T = −k slip)
  Status status = Status::kOpen;
};

/// f = p n + f_T with p = max(0, λ − k g − c n·v) while λ − k g > 0 (in touch; 0 apart: the
/// damping acts in touch only and never pulls); f_T = −k e (e = P w, P = I − n nᵀ) while
/// |k e| <= μ p, else μ p t̂ (t̂ = −e/|e|).
inline NodeResult node_force(const NodeInput& in, bool tangent) {
  NodeResult r;
  const double elastic = in.lambda - in.k * in.g;
  if (elastic <= 0) return r;
  const double vn = in.n.dot(in.v);
  const double p = elastic - in.c * vn;
  if (p <= 0) return r;  // in touch but leaving faster than the damping lets it push
  r.p = p;
  r.status = Status::kStick;
  r.f = p * in.n;
  // ∂p/∂x = −k n − c Hᵀ v (the normal turns under the velocity); ∂p/∂v = −c n.
  const Vec3 dp = -in.k * in.n - in.c * (in.H.transpose() * in.v);
  if (tangent) r.D = in.n * dp.transpose() + p * in.H;
  if (tangent && in.c > 0) r.Dv = -in.c * in.n * in.n.transpose();
  if (in.mu <= 0) {
    r.status = Status::kSlip;  // frictionless: the node slides freely
    return r;
  }
  const Mat3 P = Mat3::Identity() - in.n * in.n.transpose();
  const Vec3 e = P * in.w;
  const double en = e.norm();
  const double limit = in.mu * p;
  // ∂e/∂x = P − (n·w) H − n wᵀ H
  Mat3 De = Mat3::Zero();
  if (tangent) De = P - in.n.dot(in.w) * in.H - in.n * (in.H * in.w).transpose();
  if (in.k * en <= limit) {
    r.f += -in.k * e;
    r.slip = e;
    if (tangent) r.D += -in.k * De;
    return r;
  }
  r.status = Status::kSlip;
  const Vec3 t = -e / en;
  r.f += limit * t;
  r.slip = -(limit / in.k) * t;
  if (tangent) {
    r.D += in.mu * t * dp.transpose() - (limit / en) * (Mat3::Identity() - t * t.transpose()) * De;
    if (in.c > 0) r.Dv += -in.mu * in.c * t * in.n.transpose();
  }
  return r;
}

}  // namespace velum::contact
