// The interface every constitutive law of a membrane sheet implements (THEORY §2): at a point,
// from the Green-Lagrange strain E in the sheet's principal axes (m1, m2) and the point's
// history, the 2nd Piola-Kirchhoff stress S and its tangent C = dS/dE, in engineering Voigt
// (E = [E11, E22, 2 E12], S = [S11, S22, S12]); the energy per unit reference volume. A law
// never sees shape functions or nodes. Units are the user's.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "velum/math/types.hpp"

namespace velum {

enum class WrinkleState : std::uint8_t { kTaut = 0, kWrinkled = 1, kSlack = 2 };

/// What a sheet law returns at one point, in the sheet axes.
struct SheetResponse {
  Vec3 S = Vec3::Zero();  ///< 2nd PK stress [S11, S22, S12]
  Mat3 C = Mat3::Zero();  ///< dS/dE (engineering Voigt)
  WrinkleState state = WrinkleState::kTaut;
  double angle = 0;  ///< wrinkled: angle of the tension (wrinkle) direction from m1, radians
};

/// A sheet law. Immutable once built (a block shares it between threads); the per-point
/// history of a path-dependent law (plasticity, a fabric's unloading branch) lives outside it,
/// `state_size()` doubles per integration point, read at evaluate() and advanced by
/// update_state() once a step is accepted, so that evaluate() stays a function of (E, h).
class SheetLawBase {
 public:
  virtual ~SheetLawBase() = default;

  /// The material's name, for messages.
  virtual const std::string& name() const = 0;

  /// Stress and tangent at the strain E (sheet axes), from the history h committed at the end
  /// of the last accepted step (state_size() values; empty for a law without history).
  virtual void evaluate(const Vec3& E, std::span<const double> h, SheetResponse& out) const = 0;
  /// The stress alone (out.S, out.state, out.angle; out.C is left unspecified): what an
  /// explicit step or a residual without a Jacobian needs. The same S as evaluate(); a law
  /// whose tangent costs much beside its stress (the tension field) skips it here.
  virtual void stress(const Vec3& E, std::span<const double> h, SheetResponse& out) const {
    evaluate(E, h, out);
  }
  /// Energy density W per unit reference volume with dW/dE = S (a free energy for a law with
  /// history); zero in the reference state but for the prestress's work.
  virtual double energy(const Vec3& E, std::span<const double> h) const = 0;

  /// True when S = reference_stiffness() E + prestress() for every E and history: elements
  /// then precompute the stiffness in the convected frame at set-up and never call the law
  /// (the fast path). A law that is not affine is evaluated at every point.
  virtual bool affine() const = 0;
  /// The tangent at E = 0 from the initial history, in the sheet axes: Q of a linear law,
  /// the small-strain stiffness of a hyperelastic one. Elements set up with it, and form
  /// finding scales it into its stabilising law.
  virtual const Mat3& reference_stiffness() const = 0;
  /// The stress at E = 0, S0 (2nd PK, sheet axes): the section's prestress.
  virtual Vec3 prestress() const { return Vec3::Zero(); }
  /// Whether the sheet carries no compression (its points report a WrinkleState).
  virtual bool wrinkling() const { return false; }

  /// The current thickness over the reference thickness at E (1: a law that keeps the
  /// thickness, as the linear law does; 1/√det C for an incompressible sheet). Output only:
  /// the stresses are per unit reference volume whatever the thickness does.
  virtual double thickness_ratio(const Vec3& E, std::span<const double> h) const {
    (void)E;
    (void)h;
    return 1.0;
  }
  /// Whether thickness_ratio() can differ from 1.
  virtual bool thins() const { return false; }
  /// The equivalent plastic strain held in the history h (0 for a law that does not yield).
  /// Output only.
  virtual double plastic_strain(std::span<const double> h) const {
    (void)h;
    return 0.0;
  }
  /// Whether plastic_strain() can differ from 0.
  virtual bool yields() const { return false; }

  /// Doubles of history kept at each integration point (0: none).
  virtual int state_size() const { return 0; }
  /// The history of a point in the reference state.
  virtual void initial_state(std::span<double> h) const { (void)h; }
  /// Advances the history h in place to the end of a step accepted at the strain E.
  virtual void update_state(const Vec3& E, std::span<double> h) const {
    (void)E;
    (void)h;
  }

  /// A copy (a block keeps its own law).
  virtual std::unique_ptr<SheetLawBase> clone() const = 0;

 protected:
  SheetLawBase() = default;
  SheetLawBase(const SheetLawBase&) = default;
  SheetLawBase& operator=(const SheetLawBase&) = default;
};

}  // namespace velum
