// Form finding (docs/fabric-structures.md): the shape in equilibrium with the prescribed
// prestress of membranes and cables, the fixed nodes held, by the updated reference strategy
// (Bletzinger and Ramm 1999; Wüchner and Bletzinger 2005). Each update solves, by Newton, the
// equilibrium of the model whose reference is the current shape and whose sheets and cables
// carry their prestress plus a stabilizing elastic law (a fraction of the prestress in
// stiffness: it holds the in-plane mesh and limits the stride), then moves the reference to
// the solution. The elastic stress vanishes when the updates stop moving the shape: the found
// shape carries exactly the prescribed prestress as its Cauchy stress (2nd Piola-Kirchhoff
// and Cauchy stress coincide on the reference) in equilibrium with the loads.
#pragma once

#include "velum/analysis/analysis.hpp"

namespace velum {

/// Runs form finding on `model` (its blocks are replaced, at each converged load level, by the
/// same sections set up on the found shape, so that `view`, a MechanicalSystem on `model`,
/// shows the found shape and its stresses; the model's X stays the shape it started from,
/// so displacements measure the change of shape). Load levels are the time loop's steps (the
/// loads' time functions applied; fixed steps). The observer sees each level's found shape.
AnalysisResult run_form_finding(Model& model, MechanicalSystem& view,
                                const AnalysisSettings& settings,
                                const std::function<bool(const StepSnapshot&)>& observer = {},
                                const std::function<void(const std::string&)>& on_warning = {},
                                FormFindingReport* report = nullptr);

}  // namespace velum
