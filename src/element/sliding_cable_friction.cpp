#include "velum/element/sliding_cable_friction.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace velum::sliding_cable {
namespace {

// What an interior node does in the current iterate of the slip solve.
enum Mode : int { kStick = 0, kForward = 1, kBackward = 2, kFrozen = 3 };
constexpr int kMaxIterations = 60;

// Slips are solved over the whole chain's nodes (k values, the ends held at zero): node i
// between segment i − 1 (before it) and segment i (after it). A forward slip moves material
// from segment i − 1 into segment i: the material in segment j is g (L0_j + s_j − s_{j+1}).

void resize(FrictionWork& w, Eigen::Index k) {
  const auto n = static_cast<size_t>(k);
  for (auto* v : {&w.s, &w.s_old, &w.s_from, &w.step, &w.T, &w.a, &w.h, &w.lj, &w.c, &w.theta, &w.F,
                  &w.lo, &w.di, &w.up, &w.w})
    v->resize(n);
  w.mode.resize(n);
  w.e.resize(3 * n);
}

// Segment lengths and unit vectors, each interior node's wrap angle θ and capstan ratio e^(μθ).
void geometry(const Chain& x, double mu, FrictionWork& w) {
  const Eigen::Index n = x.cols() - 1;
  for (Eigen::Index j = 0; j < n; ++j) {
    const Vec3 d = x.col(j + 1) - x.col(j);
    const double l = d.norm();
    w.lj[j] = l;
    Eigen::Map<Vec3>(w.e.data() + 3 * j) = d / l;
  }
  for (Eigen::Index i = 1; i < n; ++i) {
    const Eigen::Map<const Vec3> e1(w.e.data() + 3 * (i - 1)), e2(w.e.data() + 3 * i);
    w.theta[i] = std::atan2(e1.cross(e2).norm(), e1.dot(e2));
    w.c[i] = std::exp(mu * w.theta[i]);
  }
}

// Each segment's force T_j, a_j = ∂T_j/∂l_j and h_j = −∂T_j/∂s_j = ∂T_j/∂s_{j+1} at the slips
// w.s; false when a segment holds no material.
bool segments(const FrictionChain& c, double area, const CableLaw& law, FrictionWork& w,
              Eigen::Index n) {
  for (Eigen::Index j = 0; j < n; ++j) {
    const double L = c.g * (c.L0[j] + w.s[j] - w.s[j + 1]);
    if (!(L > 0)) return false;
    const double lam = w.lj[j] / L;
    const double eps = 0.5 * (lam * lam - 1);
    const double S = law.stress(eps);
    w.T[j] = area * S * lam;
    w.a[j] = area * (law.tangent(eps) * lam * lam + S) / L;
    w.h[j] = c.g * lam * w.a[j];
  }
  return true;
}

// The tridiagonal Jacobian of the nodes' equations with respect to the slips (rows 1..n−1):
// forward φ = T_i − c T_{i−1}, backward φ = T_{i−1} − c T_i, stick and frozen rows the slip
// itself. `reg` keeps a run of slipping nodes between two slack segments solvable (its shift
// moves material between slack segments only).
void jacobian(FrictionWork& w, Eigen::Index n, double reg) {
  for (Eigen::Index i = 1; i < n; ++i) {
    const double c = w.c[i], hb = w.h[i - 1], ha = w.h[i];
    switch (w.mode[i]) {
      case kForward:
        w.lo[i] = c * hb, w.di[i] = -ha - c * hb - reg, w.up[i] = ha;
        break;
      case kBackward:
        w.lo[i] = -hb, w.di[i] = hb + c * ha + reg, w.up[i] = -c * ha;
        break;
      default:
        w.lo[i] = 0, w.di[i] = 1, w.up[i] = 0;
    }
  }
}

// Thomas elimination of the tridiagonal rows 1..n−1 (their diagonal dominates weakly: no
// pivoting); w.w holds the eliminated upper diagonal, w.di the pivots afterwards.
void factor(FrictionWork& w, Eigen::Index n) {
  for (Eigen::Index i = 1; i < n; ++i) {
    if (i > 1) w.di[i] -= w.lo[i] * w.w[i - 1];
    w.w[i] = w.up[i] / w.di[i];
  }
}

// Solves the factored system for b (entries 1..n−1 at stride `stride`), in place.
void solve(const FrictionWork& w, Eigen::Index n, double* b, Eigen::Index stride) {
  for (Eigen::Index i = 1; i < n; ++i) {
    if (i > 1) b[i * stride] -= w.lo[i] * b[(i - 1) * stride];
    b[i * stride] /= w.di[i];
  }
  for (Eigen::Index i = n - 2; i >= 1; --i) b[i * stride] -= w.w[i] * b[(i + 1) * stride];
}

// Each node's mode at the slips w.s (segments() done), its Newton row's value in w.F (φ where
// it slips, the slip itself where it sticks) and the complementarity residual
// s_i − s_i,old − max(0, Δ + ρφ⁺) − min(0, Δ − ρφ⁻), a length: returns its largest entry and
// adds its squares to `sum`.
double residual(double rho, FrictionWork& w, Eigen::Index n, double& sum) {
  double worst = 0;
  sum = 0;
  for (Eigen::Index i = 1; i < n; ++i) {
    const double d = w.s[i] - w.s_old[i];
    const double pf = w.T[i] - w.c[i] * w.T[i - 1], pb = w.T[i - 1] - w.c[i] * w.T[i];
    double r;
    if (w.h[i - 1] == 0 && w.h[i] == 0)
      w.mode[i] = kFrozen, w.F[i] = 0, r = 0;
    else if (d + rho * pf > 0)
      w.mode[i] = kForward, w.F[i] = pf, r = rho * pf;
    else if (d - rho * pb < 0)
      w.mode[i] = kBackward, w.F[i] = pb, r = rho * pb;
    else
      w.mode[i] = kStick, w.F[i] = d, r = d;
    worst = std::max(worst, std::abs(r));
    sum += r * r;
  }
  return worst;
}

// The slips at x (geometry already computed): semismooth Newton on each node's
// complementarity residual, whose active set says per node whether it sticks or slips which
// way; a step never empties a segment and is halved until the residual falls (a segment going
// slack or taut within a step otherwise sends the active set round a cycle).
bool solve(const FrictionChain& c, double area, const CableLaw& law, FrictionWork& w,
           Eigen::Index n) {
  double Ltot = 0;
  for (Eigen::Index j = 0; j < n; ++j) Ltot += c.L0[j];
  w.s[0] = w.s[n] = 0;
  for (Eigen::Index i = 1; i < n; ++i) w.s[i] = w.s_old[i] = c.committed[i - 1];
  if (!segments(c, area, law, w, n)) return false;
  for (int it = 0; it < kMaxIterations; ++it) {
    double H = 0, Tmax = 0;
    for (Eigen::Index j = 0; j < n; ++j) H = std::max(H, w.h[j]), Tmax = std::max(Tmax, w.T[j]);
    if (H == 0) return true;  // all slack: no node moves the material
    // Converged to a small share of the chain's length (the slips' rounding) or of the slip
    // that changes the largest force by 1e-12 of it.
    const double rho = 1 / H, tol = 1e-14 * Ltot + 1e-12 * Tmax * rho;
    double merit = 0;
    if (residual(rho, w, n, merit) <= tol) return true;
    jacobian(w, n, 1e-12 * H);
    factor(w, n);
    for (Eigen::Index i = 1; i < n; ++i) w.step[i] = -w.F[i];
    solve(w, n, w.step.data(), 1);
    w.step[0] = w.step[n] = 0;
    double alpha = 1;
    for (Eigen::Index j = 0; j < n; ++j) {
      const double L = c.L0[j] + w.s[j] - w.s[j + 1], dL = w.step[j] - w.step[j + 1];
      if (dL < -0.9 * L) alpha = std::min(alpha, -0.9 * L / dL);
    }
    std::copy(w.s.begin(), w.s.end(), w.s_from.begin());
    for (int cut = 0; cut < 40; ++cut, alpha *= 0.5) {
      for (Eigen::Index i = 1; i < n; ++i) w.s[i] = w.s_from[i] + alpha * w.step[i];
      double trial = 0;
      if (!segments(c, area, law, w, n)) continue;
      residual(rho, w, n, trial);
      if (trial <= (1 - 1e-4 * alpha) * merit) break;
    }
    if (!segments(c, area, law, w, n)) return false;
  }
  return false;
}

}  // namespace

bool solve_slips(const Chain& x, const FrictionChain& c, double area, const CableLaw& law,
                 std::span<double> slips, FrictionWork& w) {
  const Eigen::Index k = x.cols(), n = k - 1;
  resize(w, k);
  geometry(x, c.mu, w);
  const bool ok = solve(c, area, law, w, n);
  for (Eigen::Index i = 1; i < n; ++i) slips[i - 1] = w.s[i];
  return ok;
}

bool friction_force_tangent(const Chain& x, const FrictionChain& c, double area,
                            const CableLaw& law, VectorMap r, MatrixMap* K, std::span<double> slips,
                            FrictionWork& w) {
  const Eigen::Index k = x.cols(), n = k - 1, nd = 3 * k;
  resize(w, k);
  geometry(x, c.mu, w);
  const bool ok = solve(c, area, law, w, n);
  for (Eigen::Index i = 1; i < n; ++i) slips[i - 1] = w.s[i];
  if (!ok) {
    r.setConstant(std::numeric_limits<double>::quiet_NaN());
    if (K) K->setZero();
    return false;
  }
  r.setZero();
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Map<const Vec3> e(w.e.data() + 3 * j);
    r.segment<3>(3 * (j + 1)) += w.T[j] * e;
    r.segment<3>(3 * j) -= w.T[j] * e;
  }
  if (!K) return true;
  MatrixMap& Km = *K;
  Km.setZero();
  // Each segment on its own: a_j ∂l_j ⊗ ∂l_j + T_j (I − e eᵀ) / l_j.
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Map<const Vec3> e(w.e.data() + 3 * j);
    const Mat3 G =
        w.a[j] * e * e.transpose() + (w.T[j] / w.lj[j]) * (Mat3::Identity() - e * e.transpose());
    Km.block<3, 3>(3 * j, 3 * j) += G;
    Km.block<3, 3>(3 * (j + 1), 3 * (j + 1)) += G;
    Km.block<3, 3>(3 * j, 3 * (j + 1)) -= G;
    Km.block<3, 3>(3 * (j + 1), 3 * j) -= G;
  }
  bool slipping = false;
  for (Eigen::Index i = 1; i < n; ++i)
    slipping = slipping || w.mode[i] == kForward || w.mode[i] == kBackward;
  if (!slipping) return true;
  // The slips' change with x: J ds = −B dx, B the capstan conditions' x-derivatives (through
  // the segments' lengths and the wrap angle); rows of the nodes that stick are zero.
  double H = 0;
  for (Eigen::Index j = 0; j < n; ++j) H = std::max(H, w.h[j]);
  jacobian(w, n, 1e-12 * H);
  factor(w, n);
  w.D.assign(static_cast<size_t>(k * nd), 0.0);  // k × nd, column-major; rows 0 and n stay 0
  Eigen::Map<Eigen::MatrixXd> D(w.D.data(), k, nd);
  for (Eigen::Index i = 1; i < n; ++i) {
    if (w.mode[i] != kForward && w.mode[i] != kBackward) continue;
    const bool fwd = w.mode[i] == kForward;
    const double ci = w.c[i];
    // ∂φ/∂l_{i−1}, ∂φ/∂l_i and ∂φ/∂θ.
    const double dlb = fwd ? -ci * w.a[i - 1] : w.a[i - 1];
    const double dla = fwd ? w.a[i] : -ci * w.a[i];
    const double dth = -c.mu * ci * (fwd ? w.T[i - 1] : w.T[i]);
    const Eigen::Map<const Vec3> eb(w.e.data() + 3 * (i - 1)), ea(w.e.data() + 3 * i);
    Vec3 gb = Vec3::Zero(), ga = Vec3::Zero();  // ∂θ/∂x_{i−1} and −∂θ/∂x_{i+1}
    const double sn = std::sin(w.theta[i]), cs = std::cos(w.theta[i]);
    if (sn > 1e-12 && dth != 0) {
      gb = (ea - cs * eb) / (sn * w.lj[i - 1]);
      ga = (eb - cs * ea) / (sn * w.lj[i]);
    }
    // Row i of −B: ∂l_{i−1} = e_{i−1} at i, −e_{i−1} at i−1; ∂l_i = e_i at i+1, −e_i at i.
    D.block<1, 3>(i, 3 * (i - 1)) -= (-dlb * eb + dth * gb).transpose();
    D.block<1, 3>(i, 3 * i) -= (dlb * eb - dla * ea + dth * (ga - gb)).transpose();
    D.block<1, 3>(i, 3 * (i + 1)) -= (dla * ea - dth * ga).transpose();
  }
  for (Eigen::Index col = 0; col < nd; ++col) solve(w, n, D.col(col).data(), 1);
  // dT_j/dx gains h_j (D_{j+1} − D_j): scattered along ∂l_j.
  for (Eigen::Index j = 0; j < n; ++j) {
    if (w.h[j] == 0) continue;
    const Eigen::Map<const Vec3> e(w.e.data() + 3 * j);
    for (Eigen::Index col = 0; col < nd; ++col) {
      const double dT = w.h[j] * (D(j + 1, col) - D(j, col));
      if (dT == 0) continue;
      Km.block<3, 1>(3 * (j + 1), col) += dT * e;
      Km.block<3, 1>(3 * j, col) -= dT * e;
    }
  }
  return true;
}

double friction_strain_energy(const Chain& x, const FrictionChain& c, double area,
                              const CableLaw& law, FrictionWork& w) {
  const Eigen::Index k = x.cols(), n = k - 1;
  resize(w, k);
  geometry(x, c.mu, w);
  if (!solve(c, area, law, w, n)) return std::numeric_limits<double>::quiet_NaN();
  double U = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double L = c.g * (c.L0[j] + w.s[j] - w.s[j + 1]);
    U += area * L * law.energy(strain(w.lj[j], L));
  }
  return U;
}

double friction_mean_force(const Chain& x, const FrictionChain& c, double area, const CableLaw& law,
                           FrictionWork& w) {
  const Eigen::Index k = x.cols(), n = k - 1;
  resize(w, k);
  geometry(x, c.mu, w);
  if (!solve(c, area, law, w, n)) return std::numeric_limits<double>::quiet_NaN();
  double Tl = 0, l = 0;
  for (Eigen::Index j = 0; j < n; ++j) Tl += w.T[j] * w.lj[j], l += w.lj[j];
  return Tl / l;
}

void frictionless_slips(const Chain& x, std::span<const double> L0, std::span<double> slips) {
  const Eigen::Index n = x.cols() - 1;
  double l = 0, Ltot = 0;
  for (Eigen::Index j = 0; j < n; ++j) l += (x.col(j + 1) - x.col(j)).norm(), Ltot += L0[j];
  double s = 0;
  for (Eigen::Index j = 0; j + 1 < n; ++j) {
    s += L0[j] - (x.col(j + 1) - x.col(j)).norm() * Ltot / l;
    slips[j] = s;
  }
}

}  // namespace velum::sliding_cable
