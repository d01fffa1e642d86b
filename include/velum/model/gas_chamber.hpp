// Set-up and volume of enclosed-gas chambers: now in the loads' room (load/gas_chamber.hpp).
#pragma once

#include "velum/load/gas_chamber.hpp"
