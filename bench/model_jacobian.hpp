// The Jacobian of a model file's first step, as its analysis builds it: the stiffness at rest
// of a static model, or cu K + ca M with its integrator's coefficients for a dynamic one (K +
// 4 M / Δt² for the trapezoidal Newmark). Shared by the factorisation benchmarks, which take the
// file from an environment variable.
#pragma once

#include <memory>

#include "velum/analysis/analysis.hpp"
#include "velum/analysis/mechanical_system.hpp"
#include "velum/io/model_reader.hpp"
#include "velum/time/integrators.hpp"

namespace velum::bench {

inline SparseMatrix model_jacobian(const char* file) {
  const io::ModelInput input = io::read_model(file);
  double stiffness = 1.0, mass = 0.0;
  if (!input.analysis.equilibrium()) {
    const std::unique_ptr<TimeIntegrator> integrator = make_integrator(input.analysis);
    if (const auto* implicit = dynamic_cast<const GeneralizedAlpha*>(integrator.get())) {
      const Vec3 shift = implicit->shift(input.analysis.time.step);
      stiffness = shift[0];
      mass = shift[2];
    }
  }
  MechanicalSystem sys(input.model);
  VecX u = VecX::Zero(sys.size()), v = u, a = u, r;
  SparseMatrix J;
  sys.evaluate(0.0, u, v, a, stiffness, 0.0, mass, r, &J);
  return J;
}

}  // namespace velum::bench
