// Tension field of an anisotropic elastic sheet (docs/wrinkling.md). With n = (cos θ, sin θ)
// the tension direction and t = (−sin θ, cos θ) across the wrinkles, the wrinkled stress is
// S = S_trial − β Q v_t, where v_t = [t1², t2², 2 t1 t2] is t ⊗ t in engineering Voigt form
// and β the wrinkling strain across the wrinkles. The two conditions of uniaxial tension,
// S_tt = v_t · S = 0 and S_nt = v_nt · S = 0 (v_nt = [n1 t1, n2 t2, n1 t2 + n2 t1]), give
// β = v_t·S_trial / v_tᵀQv_t and, after clearing the denominator, the angle equation
//     H(θ) = (v_tᵀQv_t)(v_nt·S_trial) − (v_t·S_trial)(v_ntᵀQv_t) = 0,
// a trigonometric polynomial with period π and at most six roots there. Its roots are bracketed
// by sampling and refined by a safeguarded Newton method; a root is admissible when β ≤ 0 (a
// contraction) and the tension s = n·S·n > 0; among admissible roots the one of lowest elastic
// energy (W(E − β v_t) = W(E) − ½ β² v_tᵀQv_t: the largest ½ β² v_tᵀQv_t) is the solution.
// This rejects the spurious roots with negative tension that an anisotropic sheet can have.
#include <array>
#include <cmath>
#include <numbers>

#include "velum/material/linear_sheet_law.hpp"

namespace velum {
namespace {

constexpr int kSamples = 36;  // 5° apart: at most six roots in [0, π)

/// The vectors of the wrinkle frame at angle θ (c = cos θ, s = sin θ).
struct WrinkleFrame {
  Vec3 vt, vnt, vn;  ///< t⊗t, sym(n⊗t), n⊗n in engineering Voigt (shear doubled)
  WrinkleFrame(double c, double s)
      : vt(s * s, c * c, -2 * s * c),
        vnt(-c * s, s * c, c * c - s * s),
        vn(c * c, s * s, 2 * c * s) {}
};

class AngleEquation {
 public:
  AngleEquation(const Mat3& Q, const Vec3& St) : Q_(Q), St_(St) {}

  /// H(θ) and, when dH is non-null, dH/dθ.
  double operator()(double theta, double* dH = nullptr) const {
    return at(std::cos(theta), std::sin(theta), dH);
  }
  /// H at each (c[k], s[k]): the same arithmetic in one loop over the samples, which the
  /// compiler runs several samples at a time (the scan was most of the tension field's time).
  std::array<double, kSamples> samples(const std::array<double, kSamples>& c,
                                       const std::array<double, kSamples>& s) const {
    const double q00 = Q_(0, 0), q01 = Q_(0, 1), q02 = Q_(0, 2), q10 = Q_(1, 0), q11 = Q_(1, 1),
                 q12 = Q_(1, 2), q20 = Q_(2, 0), q21 = Q_(2, 1), q22 = Q_(2, 2);
    const double s0 = St_[0], s1 = St_[1], s2 = St_[2];
    std::array<double, kSamples> out;
    for (int k = 0; k < kSamples; ++k) {
      const double ck = c[k], sk = s[k];
      const double t0 = sk * sk, t1 = ck * ck, t2 = -2 * sk * ck;        // v_t
      const double n0 = -ck * sk, n1 = sk * ck, n2 = ck * ck - sk * sk;  // v_nt
      const double u0 = q00 * t0 + q01 * t1 + q02 * t2, u1 = q10 * t0 + q11 * t1 + q12 * t2,
                   u2 = q20 * t0 + q21 * t1 + q22 * t2;  // Q v_t
      const double d = t0 * u0 + t1 * u1 + t2 * u2, a = n0 * s0 + n1 * s1 + n2 * s2,
                   b = t0 * s0 + t1 * s1 + t2 * s2, e = n0 * u0 + n1 * u1 + n2 * u2;
      out[k] = d * a - b * e;
    }
    return out;
  }
  /// The same from c = cos θ, s = sin θ.
  double at(double c, double s, double* dH = nullptr) const {
    const WrinkleFrame f(c, s);
    const Vec3 Qvt = Q_ * f.vt;
    const double d = f.vt.dot(Qvt), a = f.vnt.dot(St_), b = f.vt.dot(St_), e = f.vnt.dot(Qvt);
    if (dH) {
      // v_t' = −2 v_nt and v_nt' = v_t − v_n.
      const Vec3 dvnt = f.vt - f.vn;
      const double dd = -4 * e, da = dvnt.dot(St_), db = -2 * a;
      const double de = dvnt.dot(Qvt) - 2 * f.vnt.dot(Q_ * f.vnt);
      *dH = dd * a + d * da - db * e - b * de;
    }
    return d * a - b * e;
  }

 private:
  const Mat3& Q_;
  const Vec3& St_;
};

/// Root of H in [lo, hi] where H(lo) and H(hi) differ in sign: Newton steps kept inside the
/// shrinking bracket, bisection when a step would leave it or converge too slowly.
double refine_root(const AngleEquation& H, double lo, double hi, double Hlo) {
  double x = 0.5 * (lo + hi);
  double dx_old = hi - lo, dx = dx_old;
  for (int it = 0; it < 100; ++it) {
    double dH = 0;
    const double h = H(x, &dH);
    if (h == 0) return x;
    if ((h < 0) == (Hlo < 0)) {
      lo = x;
      Hlo = h;
    } else {
      hi = x;
    }
    const bool newton_leaves = dH == 0 || ((x - h / dH) - lo) * ((x - h / dH) - hi) > 0;
    if (newton_leaves || std::abs(2 * h) > std::abs(dx_old * dH)) {
      dx_old = dx;
      dx = 0.5 * (hi - lo);
      x = lo + dx;
    } else {
      dx_old = dx;
      dx = h / dH;
      x -= dx;
    }
    if (std::abs(dx) < 1e-15 || hi - lo < 1e-15) return x;
  }
  return x;
}

// cos and sin of the sample angles kπ/kSamples, k = 0 ... kSamples − 1, computed once: the
// scan for roots evaluates H at every sample of every wrinkled point (sincos was a seventh of
// the C9 canopy's assembly).
struct SampleAngles {
  std::array<double, kSamples> c, s;
  SampleAngles() {
    for (int k = 0; k < kSamples; ++k) {
      c[k] = std::cos(k * (std::numbers::pi / kSamples));
      s[k] = std::sin(k * (std::numbers::pi / kSamples));
    }
  }
};
const SampleAngles kSampleAngles;

/// Whether Q is an isotropic sheet's (to round-off, as a rotated isotropic Q comes out): no
/// coupling of shear and stretch, equal stretch stiffness both ways, shear (Q00 − Q01) / 2.
bool isotropic(const Mat3& Q, double scale) {
  const double tol = 1e-12 * scale;
  return std::abs(Q(0, 2)) <= tol && std::abs(Q(1, 2)) <= tol && std::abs(Q(2, 0)) <= tol &&
         std::abs(Q(2, 1)) <= tol && std::abs(Q(0, 0) - Q(1, 1)) <= tol &&
         std::abs(Q(0, 0) - Q(0, 1) - 2 * Q(2, 2)) <= tol;
}

/// An angle with its cosine and sine.
struct Angle {
  double theta, c, s;
};

/// The admissible root of H for an isotropic Q: there v_ntᵀQv_t = 0 at every angle, so
/// H = (v_tᵀQv_t) S_nt vanishes at the trial stress's principal directions only, and of those
/// only the major one can carry tension with β ≤ 0 (along the minor one β ≤ 0 needs σ1 ≤ 0,
/// and then σ2 − ν σ1 ≤ 0). One Newton step on H takes it to the root of Q as given (a Q
/// isotropic to round-off only moves the root by as much). In [0, π), as the scan's roots;
/// cosine and sine from the stress (half-angle formulas) and the step's rotation, so that a
/// point costs one atan2 and no sine or cosine.
Angle isotropic_root(const AngleEquation& H, const Vec3& St, double half_difference,
                     double radius) {
  double c = 1, s = 0;
  if (radius > 0) {
    const double cos2 = half_difference / radius, sin2 = St[2] / radius;  // of 2θ
    if (cos2 >= 0) {
      c = std::sqrt(0.5 * (1 + cos2));
      s = sin2 / (2 * c);
    } else {
      s = std::sqrt(0.5 * (1 - cos2));
      c = sin2 / (2 * s);
    }
  }
  double dH = 0;
  const double h = H.at(c, s, &dH);
  if (const double d = -h / dH; dH != 0 && std::isfinite(d) && d != 0) {
    // Rotated by d: its cosine and sine to round-off from two terms while d is small.
    const bool small = std::abs(d) < 1e-8;
    const double cd = small ? 1 - 0.5 * d * d : std::cos(d), sd = small ? d : std::sin(d);
    const double c1 = c * cd - s * sd, s1 = s * cd + c * sd;
    c = c1;
    s = s1;
  }
  double theta = std::atan2(s, c);
  if (theta < 0) theta += std::numbers::pi, c = -c, s = -s;  // n and −n: the same frame
  if (theta >= std::numbers::pi) theta -= std::numbers::pi, c = -c, s = -s;
  return {theta, c, s};
}

}  // namespace

TensionField tension_field(const Mat3& Q, const Vec3& St, bool tangent) {
  TensionField out;
  // Taut: the trial stress has no negative principal value.
  const double mean = 0.5 * (St[0] + St[1]);
  // (sqrt, not hypot: stresses are far from overflow, and hypot's care was a sixtieth of the C9
  // canopy's run, every membrane point of every evaluation passing here)
  const double half_difference = 0.5 * (St[0] - St[1]);
  const double radius = std::sqrt(half_difference * half_difference + St[2] * St[2]);
  if (mean - radius >= 0) {
    out.S = St;
    if (tangent) out.C = Q;
    out.state = WrinkleState::kTaut;
    return out;
  }
  const AngleEquation H(Q, St);
  const double scale = Q.cwiseAbs().maxCoeff();
  double best_relief = -1, best_theta = 0, best_beta = 0, best_c = 1, best_s = 0;
  // A root of H is a candidate: admissible when β ≤ 0 and the tension is positive, the best
  // of lowest elastic energy (largest relief).
  auto consider = [&](double root, double c, double s) {
    const WrinkleFrame f(c, s);
    const Vec3 Qvt = Q * f.vt;
    const double d = f.vt.dot(Qvt);
    if (d > 1e-12 * scale) {
      const double beta = f.vt.dot(St) / d;
      const double tension = f.vn.dot(St - beta * Qvt);
      const double relief = 0.5 * beta * beta * d;
      if (beta <= 0 && tension > 0 && relief > best_relief) {
        best_relief = relief;
        best_theta = root;
        best_c = c;
        best_s = s;
        best_beta = beta;
      }
    }
  };
  if (isotropic(Q, scale)) {
    const Angle a = isotropic_root(H, St, half_difference, radius);
    consider(a.theta, a.c, a.s);
  } else {
    const double h = std::numbers::pi / kSamples;
    const auto& sample = kSampleAngles;
    const std::array<double, kSamples> Hs = H.samples(sample.c, sample.s);
    double theta0 = 0, H0 = Hs[0];
    for (int k = 1; k <= kSamples; ++k) {
      const double theta1 = k * h;
      const double H1 = Hs[k % kSamples];  // period π
      if (H0 == 0) {
        consider(theta0, std::cos(theta0), std::sin(theta0));
      } else if ((H0 < 0) != (H1 < 0) && H1 != 0) {
        const double root = refine_root(H, theta0, theta1, H0);
        consider(root, std::cos(root), std::sin(root));
      }
      theta0 = theta1;
      H0 = H1;
    }
  }
  if (best_relief < 0) {
    out.state = WrinkleState::kSlack;  // S = 0, C = 0
    return out;
  }

  // Wrinkled: S = S_trial − β Q v_t(θ). The tangent follows from differentiating the two
  // conditions R = [v_t·S, v_nt·S] = 0 with respect to E at fixed (β, θ) and along (β, θ):
  // d(β, θ)/dE = −J⁻¹ ∂R/∂E with ∂R/∂E = [Q v_t, Q v_nt]ᵀ and
  // J = [[−v_tᵀQv_t, 2β v_tᵀQv_nt], [−v_ntᵀQv_t, −s + 2β v_ntᵀQv_nt]]
  // (using S_nt = 0, S_tt = 0 at the root; s = n·S·n).
  const WrinkleFrame f(best_c, best_s);
  const Vec3 Qvt = Q * f.vt;
  const double beta = best_beta;
  out.S = St - beta * Qvt;
  out.state = WrinkleState::kWrinkled;
  out.angle = best_theta;
  out.beta = beta;
  if (!tangent) return out;
  const Vec3 Qvnt = Q * f.vnt;
  const double s = f.vn.dot(out.S);
  Mat2 J;
  J << -f.vt.dot(Qvt), 2 * beta * f.vt.dot(Qvnt), -f.vnt.dot(Qvt), -s + 2 * beta * f.vnt.dot(Qvnt);
  Eigen::Matrix<double, 2, 3> dRdE;
  dRdE.row(0) = Qvt.transpose();
  dRdE.row(1) = Qvnt.transpose();
  const Eigen::Matrix<double, 2, 3> dx = -J.inverse() * dRdE;  // d(β, θ)/dE
  Eigen::Matrix<double, 3, 2> dSdx;
  dSdx.col(0) = -Qvt;
  dSdx.col(1) = 2 * beta * Qvnt;  // −β Q v_t' with v_t' = −2 v_nt
  out.C = Q + dSdx * dx;
  return out;
}

}  // namespace velum
