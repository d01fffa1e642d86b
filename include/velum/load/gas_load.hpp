// Gas enclosed by membrane elements together with the symmetry planes through `origin`
// (load type `gas`, docs/inflatables.md): absolute pressure p = initial_pressure
// (amount(t) V0 / V)^gamma, the sheet loaded by p − ambient as a follower pressure, with the
// rank-one Jacobian term of p(V). With `temperature` and `gas_constant` the chamber holds a mass
// and a temperature instead, fed by inflators and emptied by vents, fabric leakage and orifices
// to other chambers (gas/gas_flow.hpp). Units the user's.
#pragma once

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "velum/load/gas_flow.hpp"
#include "velum/load/load.hpp"

namespace velum {

struct GasLoad {
  struct Part {
    int block = -1;
    std::vector<int> elements;  ///< indices into the block
  };
  std::vector<Part> parts;
  double initial_pressure = 0, ambient = 0, gamma = 1;
  int amount = -1;  ///< time function of the gas amount (relative to the initial), -1: 1
  Vec3 origin = Vec3::Zero();
  double V0 = 0;  ///< initial volume (at the start coordinates), set by set_up_gas_chamber

  // Gas flow (docs/inflatables.md): on when gas_constant > 0.
  double temperature = 0, gas_constant = 0;
  struct Inflator {
    int mass_flow = -1;  ///< time function of the mass flow (times scale)
    double scale = 1;
    double temperature = 0;
    int temperature_function = -1;  ///< >= 0: the temperature is this function's value
  };
  std::vector<Inflator> inflators;
  std::vector<gas::Vent> vents;
  struct Leakage {
    std::vector<Part> parts;  ///< the leaking elements (of the chamber's walls or not)
    double permeability = 0, quadratic = 0;
  };
  std::vector<Leakage> leaks;
  struct Orifice {
    int chamber = -1;  ///< the other gas load, counted from 0 among the gas loads
    double area = 0, discharge = 1;
  };
  std::vector<Orifice> orifices;
  bool flows() const { return gas_constant > 0; }

  /// Absolute pressure at volume V and amount m; NaN when V <= 0 (a chamber turned inside
  /// out has no pressure: the residual turns non-finite and the step is cut).
  double pressure(double V, double m) const {
    return V > 0 ? initial_pressure * std::pow(m * V0 / V, gamma)
                 : std::numeric_limits<double>::quiet_NaN();
  }
};

std::unique_ptr<Load> make_load(GasLoad p);

}  // namespace velum
