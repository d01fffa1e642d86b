// Set-up and volume of enclosed-gas chambers (the gas load's set-up, implemented with it in
// src/load/): the checks that the listed membrane elements with the symmetry planes through the
// origin close a volume with normals pointing out of the gas, and the chamber volume at any
// configuration. Units the user's.
#pragma once

#include <functional>

#include "velum/model/model.hpp"

namespace velum {

/// Checks chamber `gas` of `model` and sets gas.V0, the volume where the sheet starts (the
/// reference coordinates moved by the start displacement model.U0, if any): the checks below
/// are made there too.
/// Every edge must be shared by exactly two of the listed elements, traversed in opposite
/// directions (consistent normals), or lie on a plane through the origin on which a symmetry
/// or fix boundary condition holds its nodes; the volume must be positive (normals out of
/// the gas). Throws std::invalid_argument saying what is wrong and where (user node ids;
/// elements by `element_id(block, element)`, default: the element's position in its block
/// from 1).
void set_up_gas_chamber(const Model& model, GasLoad& gas,
                        const std::function<long(int block, int element)>& element_id = {});

/// The chamber's volume at node positions x (3 x nodes).
double gas_chamber_volume(const Model& model, const GasLoad& gas, const NodePositions& x);

}  // namespace velum
