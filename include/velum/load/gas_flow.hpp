// Gas flow between chambers of uniform pressure (docs/inflatables.md, "Gas flow"): the mass m and
// pV = m R T of each chamber of a group joined by orifices, integrated over a step by the
// trapezoidal rule from the committed state, given the chambers' volumes and leaking areas at
// the step's end, and the derivatives of the pressures with respect to those volumes and areas
// (the implicit function theorem on the local Newton). Ideal gas, cp = γR/(γ−1); γ = 1 is
// isothermal. Inflators, vents (Wang–Nefske isentropic orifices), fabric leakage (Darcy with
// an optional quadratic term) and orifices between chambers. Needs math only; units the user's.
#pragma once

#include <limits>
#include <span>
#include <vector>

#include "velum/math/types.hpp"

namespace velum::gas {

/// A vent: an orifice to the ambient, closed until its gauge pressure or time is reached.
struct Vent {
  double area = 0, discharge = 1;
  /// Opens (for good) at the end of the first step whose gauge pressure reaches
  /// open_pressure, or from open_time on, whichever comes first (the defaults: always open).
  double open_pressure = -std::numeric_limits<double>::infinity();
  double open_time = std::numeric_limits<double>::infinity();
};

/// Fabric leakage through a set of elements: Δp = u / permeability + quadratic · u².
struct Leak {
  double permeability = 0, quadratic = 0;
};

struct Chamber {
  double gamma = 1.4, R = 287, temperature = 300;  ///< the initial (isothermal: constant) T
  double initial_pressure = 0, ambient = 0;
  int inflators = 0;
  std::vector<Vent> vents;
  std::vector<Leak> leaks;  ///< each with one leaking area (Inputs::A, in chamber order)
};

/// An orifice between two chambers of the group (flow from `from` to `to` positive).
struct Orifice {
  int from = 0, to = 0;
  double area = 0, discharge = 1;
};

/// What the chambers see at the end of a step: volumes, leaking areas (the leaks of every
/// chamber in order), inflator mass flows and temperatures (every chamber's in order).
struct Inputs {
  std::span<const double> V, A, inflow, inflow_T;
};

/// The state at a time: per chamber m, E = pV (= m R T) and p; the mass flow and enthalpy flow
/// of every flow (inflators, vents, leaks, orifices, in that order; each in its own direction:
/// into the chamber, out of it, from `from` to `to`).
struct Solution {
  std::vector<double> m, E, p, rate, enthalpy;
  MatX dp_dV, dp_dA;  ///< n x n and n x leaks (when asked for)
  bool ok = false;
  int iterations = 0;
};

/// The account of a chamber since the start: the masses and energies that crossed its
/// boundary, and its internal energy U = pV/(γ−1) then and now (not for γ = 1).
struct Account {
  double mass0 = 0, U0 = 0;
  double mass_in = 0, mass_out = 0;
  double enthalpy_in = 0, enthalpy_out = 0, work = 0;
};

class Network {
 public:
  Network(std::vector<Chamber> chambers, std::vector<Orifice> orifices);

  int chambers() const { return static_cast<int>(chambers_.size()); }
  int leaks() const { return leaks_; }
  int inflators() const { return inflators_; }
  int flows() const { return static_cast<int>(flow_.size()); }
  const Chamber& chamber(int i) const { return chambers_[static_cast<size_t>(i)]; }

  /// The state at t0: each chamber at its initial pressure and temperature in volume V.
  void start(double t0, const Inputs& in);
  /// The state at t (≥ the committed time) for the inputs at t; derivatives when asked.
  /// Solution::ok false when the local Newton fails or a volume is not positive.
  void solve(double t, const Inputs& in, bool derivatives, Solution& out) const;
  /// Solves at t and makes that the committed state (the step is accepted).
  const Solution& commit(double t, const Inputs& in);

  double committed_time() const { return t_; }
  const Solution& committed() const { return now_; }
  const Account& account(int chamber) const { return account_[static_cast<size_t>(chamber)]; }
  /// Flow index of a chamber's j-th inflator, vent or leak, or of orifice j.
  int inflator_flow(int chamber, int j) const { return first_inflator_[chamber] + j; }
  int vent_flow(int chamber, int j) const { return first_vent_[chamber] + j; }
  int leak_flow(int chamber, int j) const { return first_leak_[chamber] + j; }
  int orifice_flow(int j) const { return first_orifice_ + j; }
  /// The leaking-area index (Inputs::A) of a chamber's j-th leak.
  int leak_area(int chamber, int j) const { return first_leak_[chamber] - first_leak_[0] + j; }

  /// The committed state as numbers (a checkpoint), and back.
  void save(std::vector<double>& out) const;
  /// Reads from `in` at `at`; returns the position after it; throws when it does not fit.
  size_t restore(const std::vector<double>& in, size_t at);

 private:
  struct Flow {
    enum class Kind { kInflator, kVent, kLeak, kOrifice } kind;
    int chamber = 0, other = -1, index = 0;  ///< index: into inflow / vents / leaks / orifices
  };

  std::vector<Chamber> chambers_;
  std::vector<Orifice> orifices_;
  std::vector<Flow> flow_;
  std::vector<int> first_inflator_, first_vent_, first_leak_;
  int first_orifice_ = 0, leaks_ = 0, inflators_ = 0;
  // Committed: its time, volumes, state and rates, vents open, accounts.
  double t_ = 0;
  std::vector<double> V_;
  Solution now_;
  std::vector<char> open_;
  std::vector<Account> account_;
};

/// The isentropic orifice's flow function Φ(r), r = downstream / upstream pressure: mass flow
/// = discharge · area · sqrt(ρ p) · Φ (choked: constant below the critical ratio; linear in
/// 1 − r over the last 1e-3 below r = 1, where the exact one has an infinite slope).
double orifice_function(double gamma, double r);

}  // namespace velum::gas
