// The term of a gas chamber with gas flow (GasLoad::flows()), bound to an assembler: its
// pressure from the gas state of its group of chambers joined by orifices (gas_flow.hpp),
// the follower load p − ambient with its stiffness, and the low-rank column of p(V, A).
#pragma once

#include <memory>

#include "velum/load/gas_load.hpp"

namespace velum {

std::unique_ptr<LoadTerm> make_gas_flow_term(const GasLoad& load, const LoadSite& site);

}  // namespace velum
