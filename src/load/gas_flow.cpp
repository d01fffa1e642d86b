// Gas flow between chambers: the first law of each chamber over a step by the trapezoidal rule,
// solved by a small Newton with forward-mode derivatives (a fixed-capacity dual number: no
// allocation), and the pressures' derivatives by the implicit function theorem.
#include "velum/load/gas_flow.hpp"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unsupported/Eigen/AutoDiff>

namespace velum::gas {
namespace {

constexpr int kMaxVariables = 64;
using Deriv = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxVariables, 1>;
using AD = Eigen::AutoDiffScalar<Deriv>;
constexpr double kLinear = 1e-3;  // the last stretch below r = 1 where Φ is made linear

double value_of(double x) {
  return x;
}
double value_of(const AD& x) {
  return x.value();
}

// f(x) for a value and slope of f at x: a constant keeps its (empty) derivatives.
double chain(double fx, double /*slope*/, double /*x*/) {
  return fx;
}
AD chain(double fx, double slope, const AD& x) {
  return AD(fx, slope * x.derivatives());
}

struct ValueSlope {
  double v = 0, d = 0;
};

ValueSlope exact_phi(double g, double r) {
  if (g == 1) {
    const double s = std::sqrt(-2 * std::log(r));
    return {r * s, s - 1 / s};
  }
  const double c = 2 * g / (g - 1);
  const double F = std::pow(r, 2 / g) - std::pow(r, (g + 1) / g);
  const double dF = (2 / g) * std::pow(r, 2 / g - 1) - ((g + 1) / g) * std::pow(r, 1 / g);
  const double phi = std::sqrt(c * F);
  return {phi, c * dF / (2 * phi)};
}

double critical_ratio(double g) {
  return g == 1 ? std::exp(-0.5) : std::pow(2 / (g + 1), g / (g - 1));
}

double choked_phi(double g) {
  return g == 1 ? std::exp(-0.5) : std::sqrt(g) * std::pow(2 / (g + 1), (g + 1) / (2 * (g - 1)));
}

ValueSlope phi(double g, double r) {
  if (r <= critical_ratio(g)) return {choked_phi(g), 0};
  if (r >= 1) return {0, 0};
  const double r1 = 1 - kLinear;
  if (r > r1) {
    const double p1 = exact_phi(g, r1).v;
    return {p1 * (1 - r) / kLinear, -p1 / kLinear};
  }
  return exact_phi(g, r);
}

// Mass flow through an orifice from (ρu, pu) to pd < pu.
template <class S>
S orifice_rate(double gamma, double CdA, const S& rho_u, const S& p_u, const S& p_d) {
  using std::sqrt;
  const S r = p_d / p_u;
  const ValueSlope f = phi(gamma, value_of(r));
  return CdA * sqrt(rho_u * p_u) * chain(f.v, f.d, r);
}

}  // namespace

double orifice_function(double gamma, double r) {
  return phi(gamma, r).v;
}

Network::Network(std::vector<Chamber> chambers, std::vector<Orifice> orifices)
    : chambers_(std::move(chambers)), orifices_(std::move(orifices)) {
  const int n = static_cast<int>(chambers_.size());
  for (int c = 0; c < n; ++c) {
    first_inflator_.push_back(static_cast<int>(flow_.size()));
    for (int j = 0; j < chambers_[c].inflators; ++j)
      flow_.push_back({Flow::Kind::kInflator, c, -1, inflators_++});
  }
  int vents = 0;
  for (int c = 0; c < n; ++c) {
    first_vent_.push_back(static_cast<int>(flow_.size()));
    for (size_t j = 0; j < chambers_[c].vents.size(); ++j)
      flow_.push_back({Flow::Kind::kVent, c, -1, vents++});
  }
  for (int c = 0; c < n; ++c) {
    first_leak_.push_back(static_cast<int>(flow_.size()));
    for (size_t j = 0; j < chambers_[c].leaks.size(); ++j)
      flow_.push_back({Flow::Kind::kLeak, c, -1, leaks_++});
  }
  first_orifice_ = static_cast<int>(flow_.size());
  for (size_t j = 0; j < orifices_.size(); ++j)
    flow_.push_back(
        {Flow::Kind::kOrifice, orifices_[j].from, orifices_[j].to, static_cast<int>(j)});
  if (3 * n + leaks_ > kMaxVariables)
    throw std::invalid_argument(
        "too many chambers and leaking sets joined by orifices (3 per chamber plus 1 per leaking "
        "set must stay within 64)");
  open_.assign(static_cast<size_t>(vents), 0);
  account_.resize(static_cast<size_t>(n));
}

namespace {

// The rates of every flow (mass and enthalpy) at the chambers' state (m, E, V) and leaking
// areas A; `open` says which vents are open.
template <class S>
void rates(const std::vector<Chamber>& ch, const std::vector<Orifice>& orifices,
           const std::vector<S>& m, const std::vector<S>& E, const std::vector<S>& V,
           const std::vector<S>& A, const Inputs& in, const std::vector<char>& open,
           std::vector<S>& rate, std::vector<S>& enthalpy) {
  using std::sqrt;
  const size_t n = ch.size();
  rate.clear(), enthalpy.clear();
  std::vector<S> rho(n), p(n), h(n);
  for (size_t c = 0; c < n; ++c) {
    rho[c] = m[c] / V[c];
    p[c] = E[c] / V[c];
    const double g = ch[c].gamma;
    if (g == 1)
      h[c] = S(0.0) * m[c];
    else
      h[c] = (g / (g - 1)) * E[c] / m[c];  // cp T
  }
  size_t k = 0;
  for (size_t c = 0; c < n; ++c)
    for (int j = 0; j < ch[c].inflators; ++j, ++k) {
      const double g = ch[c].gamma;
      const double cp = g == 1 ? 0.0 : g * ch[c].R / (g - 1);
      rate.push_back(S(in.inflow[k]) + S(0.0) * m[c]);
      enthalpy.push_back(S(in.inflow[k] * cp * in.inflow_T[k]) + S(0.0) * m[c]);
    }
  size_t v = 0;
  for (size_t c = 0; c < n; ++c)
    for (const Vent& vent : ch[c].vents) {
      S r = S(0.0) * m[c];
      if (open[v++] && value_of(p[c]) > ch[c].ambient)
        r = orifice_rate(ch[c].gamma, vent.discharge * vent.area, rho[c], p[c],
                         S(S(ch[c].ambient) + S(0.0) * m[c]));
      rate.push_back(r);
      enthalpy.push_back(r * h[c]);
    }
  size_t a = 0;
  for (size_t c = 0; c < n; ++c)
    for (const Leak& leak : ch[c].leaks) {
      S r = S(0.0) * m[c];
      if (value_of(p[c]) > ch[c].ambient) {
        const S dp = p[c] - ch[c].ambient;
        const double k2 = leak.permeability;
        S u = k2 * dp;
        if (leak.quadratic != 0)
          u = 2 * k2 * dp / (1 + sqrt(1 + 4 * leak.quadratic * k2 * k2 * dp));
        r = rho[c] * u * A[a];
      }
      ++a;
      rate.push_back(r);
      enthalpy.push_back(r * h[c]);
    }
  for (const Orifice& o : orifices) {
    const auto f = static_cast<size_t>(o.from), t = static_cast<size_t>(o.to);
    S r = S(0.0) * m[f];
    S q = r;
    const double CdA = o.discharge * o.area;
    if (value_of(p[f]) > value_of(p[t])) {
      r = orifice_rate(ch[f].gamma, CdA, rho[f], p[f], p[t]);
      q = r * h[f];
    } else if (value_of(p[t]) > value_of(p[f])) {
      r = -orifice_rate(ch[t].gamma, CdA, rho[t], p[t], p[f]);
      q = r * h[t];
    }
    rate.push_back(r);
    enthalpy.push_back(q);
  }
}

}  // namespace

void Network::start(double t0, const Inputs& in) {
  const size_t n = chambers_.size();
  t_ = t0;
  V_.assign(in.V.begin(), in.V.end());
  now_.m.resize(n), now_.E.resize(n), now_.p.resize(n);
  for (size_t c = 0; c < n; ++c) {
    const Chamber& ch = chambers_[c];
    now_.E[c] = ch.initial_pressure * V_[c];
    now_.m[c] = now_.E[c] / (ch.R * ch.temperature);
    now_.p[c] = ch.initial_pressure;
  }
  size_t v = 0;
  for (size_t c = 0; c < n; ++c)
    for (const Vent& vent : chambers_[c].vents)
      open_[v++] = now_.p[c] - chambers_[c].ambient >= vent.open_pressure || t0 >= vent.open_time;
  std::vector<double> A(in.A.begin(), in.A.end());
  rates(chambers_, orifices_, now_.m, now_.E, V_, A, in, open_, now_.rate, now_.enthalpy);
  for (size_t c = 0; c < n; ++c) {
    account_[c] = Account{};
    account_[c].mass0 = now_.m[c];
    const double g = chambers_[c].gamma;
    account_[c].U0 = g == 1 ? 0.0 : now_.E[c] / (g - 1);
  }
  now_.ok = true;
}

void Network::solve(double t, const Inputs& in, bool derivatives, Solution& out) const {
  const int n = chambers();
  const int nz = 2 * n, nv = 3 * n + leaks_;
  out.ok = false;
  out.iterations = 0;
  if (now_.m.size() != chambers_.size()) return;  // not started
  for (int c = 0; c < n; ++c)
    if (!(in.V[c] > 0)) return;
  const double h = t - t_;
  // Vents open at t: latched, or past their time.
  std::vector<char> open = open_;
  {
    size_t v = 0;
    for (const Chamber& ch : chambers_)
      for (const Vent& vent : ch.vents) {
        if (t >= vent.open_time) open[v] = 1;
        ++v;
      }
  }
  // The committed rates, summed per chamber.
  std::vector<double> dm0(n, 0.0), dh0(n, 0.0);
  auto add_net = [&](auto& dm, auto& dH, const auto& rate, const auto& enthalpy) {
    for (size_t f = 0; f < flow_.size(); ++f) {
      const Flow& fl = flow_[f];
      switch (fl.kind) {
        case Flow::Kind::kInflator:
          dm[fl.chamber] += rate[f], dH[fl.chamber] += enthalpy[f];
          break;
        case Flow::Kind::kVent:
        case Flow::Kind::kLeak:
          dm[fl.chamber] -= rate[f], dH[fl.chamber] -= enthalpy[f];
          break;
        case Flow::Kind::kOrifice:
          dm[fl.chamber] -= rate[f], dH[fl.chamber] -= enthalpy[f];
          dm[fl.other] += rate[f], dH[fl.other] += enthalpy[f];
          break;
      }
    }
  };
  add_net(dm0, dh0, now_.rate, now_.enthalpy);

  // The residual and its derivatives at z (m, E per chamber) with V and A as variables.
  VecX z(nz);
  for (int c = 0; c < n; ++c) z[2 * c] = now_.m[c], z[2 * c + 1] = now_.E[c];
  MatX Jz(nz, nz), Jy(nz, nv - nz);
  VecX R(nz);
  std::vector<AD> m(n), E(n), V(n), A(leaks_), rate, enthalpy;
  auto residual = [&](const VecX& zz) {
    for (int c = 0; c < n; ++c) {
      m[c] = AD(zz[2 * c], nv, 2 * c);
      E[c] = AD(zz[2 * c + 1], nv, 2 * c + 1);
      V[c] = AD(in.V[c], nv, nz + c);
    }
    for (int k = 0; k < leaks_; ++k) A[k] = AD(in.A[k], nv, 3 * n + k);
    rates(chambers_, orifices_, m, E, V, A, in, open, rate, enthalpy);
    std::vector<AD> dm(n, AD(0.0, Deriv::Zero(nv))), dH(n, AD(0.0, Deriv::Zero(nv)));
    add_net(dm, dH, rate, enthalpy);
    for (int c = 0; c < n; ++c) {
      const Chamber& ch = chambers_[c];
      const AD Rm = m[c] - now_.m[c] - 0.5 * h * (dm0[c] + dm[c]);
      AD RE;
      if (ch.gamma == 1) {
        RE = E[c] - ch.R * ch.temperature * m[c];
      } else {
        const AD p = E[c] / V[c];
        RE = (E[c] - now_.E[c]) / (ch.gamma - 1) - 0.5 * h * (dh0[c] + dH[c]) +
             0.5 * (now_.p[c] + p) * (V[c] - V_[c]);
      }
      R[2 * c] = Rm.value(), R[2 * c + 1] = RE.value();
      Jz.row(2 * c) = Rm.derivatives().head(nz).transpose();
      Jz.row(2 * c + 1) = RE.derivatives().head(nz).transpose();
      Jy.row(2 * c) = Rm.derivatives().tail(nv - nz).transpose();
      Jy.row(2 * c + 1) = RE.derivatives().tail(nv - nz).transpose();
    }
  };

  Eigen::PartialPivLU<MatX> lu;
  bool converged = false;
  for (int it = 0; it < 50 && !converged; ++it) {
    residual(z);
    if (!R.allFinite()) return;
    lu.compute(Jz);
    const VecX dz = lu.solve(-R);
    if (!dz.allFinite()) return;
    double change = 0;
    for (int i = 0; i < nz; ++i) change = std::max(change, std::abs(dz[i]) / std::abs(z[i]));
    double s = 1;
    for (int cut = 0; cut < 40; ++cut, s *= 0.5) {
      bool positive = true;
      for (int i = 0; i < nz; ++i) positive = positive && z[i] + s * dz[i] > 0;
      if (positive) break;
    }
    z += s * dz;
    out.iterations = it + 1;
    converged = s == 1 && change < 1e-13;
  }
  if (!converged) return;
  residual(z);  // rates and derivatives at the solution
  out.m.resize(n), out.E.resize(n), out.p.resize(n);
  for (int c = 0; c < n; ++c) {
    out.m[c] = z[2 * c], out.E[c] = z[2 * c + 1];
    out.p[c] = out.E[c] / in.V[c];
  }
  out.rate.resize(rate.size()), out.enthalpy.resize(rate.size());
  for (size_t f = 0; f < rate.size(); ++f)
    out.rate[f] = rate[f].value(), out.enthalpy[f] = enthalpy[f].value();
  if (derivatives) {
    lu.compute(Jz);
    const MatX dz = -lu.solve(Jy);  // nz x (n + leaks)
    out.dp_dV.resize(n, n);
    out.dp_dA.resize(n, leaks_);
    for (int c = 0; c < n; ++c) {
      for (int j = 0; j < n; ++j)
        out.dp_dV(c, j) = dz(2 * c + 1, j) / in.V[c] - (c == j ? out.p[c] / in.V[c] : 0.0);
      for (int k = 0; k < leaks_; ++k) out.dp_dA(c, k) = dz(2 * c + 1, n + k) / in.V[c];
    }
  }
  out.ok = true;
}

const Solution& Network::commit(double t, const Inputs& in) {
  Solution next;
  solve(t, in, false, next);
  if (!next.ok) throw std::runtime_error("the gas state does not solve at an accepted step");
  const double h = t - t_;
  const size_t n = chambers_.size();
  for (size_t f = 0; f < flow_.size(); ++f) {
    const Flow& fl = flow_[f];
    const double dm = 0.5 * h * (now_.rate[f] + next.rate[f]);
    const double dH = 0.5 * h * (now_.enthalpy[f] + next.enthalpy[f]);
    auto into = [&](int c, double mass, double energy) {
      Account& a = account_[static_cast<size_t>(c)];
      (mass >= 0 ? a.mass_in : a.mass_out) += std::abs(mass);
      (energy >= 0 ? a.enthalpy_in : a.enthalpy_out) += std::abs(energy);
    };
    switch (fl.kind) {
      case Flow::Kind::kInflator:
        into(fl.chamber, dm, dH);
        break;
      case Flow::Kind::kVent:
      case Flow::Kind::kLeak:
        into(fl.chamber, -dm, -dH);
        break;
      case Flow::Kind::kOrifice:
        into(fl.chamber, -dm, -dH);
        into(fl.other, dm, dH);
        break;
    }
  }
  for (size_t c = 0; c < n; ++c)
    account_[c].work += 0.5 * (now_.p[c] + next.p[c]) * (in.V[c] - V_[c]);
  // Vents that reach their pressure open from here on; the rates at the new state with them.
  bool opened = false;
  size_t v = 0;
  for (size_t c = 0; c < n; ++c)
    for (const Vent& vent : chambers_[c].vents) {
      if (!open_[v] &&
          (next.p[c] - chambers_[c].ambient >= vent.open_pressure || t >= vent.open_time))
        open_[v] = 1, opened = true;
      ++v;
    }
  t_ = t;
  V_.assign(in.V.begin(), in.V.end());
  now_ = std::move(next);
  if (opened) {
    std::vector<double> A(in.A.begin(), in.A.end());
    rates(chambers_, orifices_, now_.m, now_.E, V_, A, in, open_, now_.rate, now_.enthalpy);
  }
  return now_;
}

void Network::save(std::vector<double>& out) const {
  out.push_back(t_);
  for (const auto* v : {&V_, &now_.m, &now_.E, &now_.p, &now_.rate, &now_.enthalpy})
    out.insert(out.end(), v->begin(), v->end());
  for (char o : open_) out.push_back(o);
  for (const Account& a : account_)
    out.insert(out.end(),
               {a.mass0, a.U0, a.mass_in, a.mass_out, a.enthalpy_in, a.enthalpy_out, a.work});
}

size_t Network::restore(const std::vector<double>& in, size_t at) {
  const size_t n = chambers_.size(), F = flow_.size();
  const size_t need = 1 + 4 * n + 2 * F + open_.size() + 7 * n;
  if (at + need > in.size())
    throw std::invalid_argument("checkpoint: the gas state does not fit this model");
  t_ = in[at++];
  for (auto* v : {&V_, &now_.m, &now_.E, &now_.p}) {
    v->assign(in.begin() + static_cast<long>(at), in.begin() + static_cast<long>(at + n));
    at += n;
  }
  for (auto* v : {&now_.rate, &now_.enthalpy}) {
    v->assign(in.begin() + static_cast<long>(at), in.begin() + static_cast<long>(at + F));
    at += F;
  }
  for (char& o : open_) o = in[at++] != 0;
  for (Account& a : account_) {
    a = Account{in[at], in[at + 1], in[at + 2], in[at + 3], in[at + 4], in[at + 5], in[at + 6]};
    at += 7;
  }
  now_.ok = true;
  return at;
}

}  // namespace velum::gas
