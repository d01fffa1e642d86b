// A coated fabric's measured response as a sheet law (a stress map, after LS-DYNA MAT_034's
// and Radioss LAW58's): the warp and fill 2nd PK stresses S11(E11, E22), S22(E11, E22) given
// on a grid of the two strains and interpolated by bicubic Hermite patches with monotone
// (PCHIP) slopes, C1 everywhere (linear beyond the grid); the shear stress S12(γ), γ = 2 E12,
// a monotone cubic through a tabulated curve (odd in γ) or G12 γ. Optionally an unloading
// branch per direction: straight, of a given modulus, from the largest strain reached (kept per
// integration point). Wrinkling and a prestress come from the section's wrappers. Sheet axes,
// engineering Voigt; units the user's.
#pragma once

#include <string>
#include <vector>

#include "velum/material/monotone_cubic.hpp"
#include "velum/material/sheet_law_base.hpp"

namespace velum {

/// The data of a stress map. S11 and S22 are row-major over (E22, E11): value k = j n1 + i at
/// (e1[i], e2[j]), n1 = e1.size().
struct StressMapData {
  std::vector<double> e1, e2;      ///< grid axes (warp, fill strain), strictly increasing
  std::vector<double> S11, S22;    ///< warp and fill stress at the grid points
  std::vector<double> gamma, S12;  ///< shear curve from γ = 0 (S12 = 0), or empty with G12
  double G12 = 0;                  ///< linear shear when no curve is given
  /// Unloading moduli (warp, fill), dS11/dE11 and dS22/dE22 below the largest strain reached
  /// in that direction; 0: that direction unloads along the map.
  double unloading[2] = {0, 0};
};

class StressMapSheetLaw final : public SheetLawBase {
 public:
  /// Checks the data (a MaterialError naming what is wrong): axes of at least two strictly
  /// increasing values holding 0, tables of the grid's size, S11 increasing along E11 and S22
  /// along E22, zero stress at zero strain, positive stiffness at zero strain, a shear curve
  /// from (0, 0) increasing (or G12 > 0).
  StressMapSheetLaw(std::string name, StressMapData data);

  const StressMapData& data() const { return data_; }

  const std::string& name() const override { return name_; }
  void evaluate(const Vec3& E, std::span<const double> h, SheetResponse& out) const override;
  /// The work of S along the straight path from zero strain to E at the history h (the strain
  /// energy when the map derives from one, as a map tabulated from an elastic law does; with
  /// an unloading branch an account of the stress, not a potential).
  double energy(const Vec3& E, std::span<const double> h) const override;
  bool affine() const override { return false; }
  const Mat3& reference_stiffness() const override { return C0_; }
  /// With an unloading modulus: the largest warp and fill strains reached (from 0).
  int state_size() const override { return unloads() ? 2 : 0; }
  void initial_state(std::span<double> h) const override;
  void update_state(const Vec3& E, std::span<double> h) const override;
  std::unique_ptr<SheetLawBase> clone() const override {
    return std::make_unique<StressMapSheetLaw>(*this);
  }

  /// Stress and tangent at E without the interface's history (none).
  void evaluate(const Vec3& E, SheetResponse& out) const;

 private:
  /// Nodal values of one field for the bicubic patches: f, ∂f/∂E11, ∂f/∂E22, ∂²f/∂E11∂E22.
  struct Field {
    std::vector<double> f, fx, fy, fxy;
  };
  Field make_field(const std::vector<double>& values) const;
  double shear(double gamma, double* dS) const;
  bool unloads() const { return data_.unloading[0] > 0 || data_.unloading[1] > 0; }

  std::string name_;
  StressMapData data_;
  Field S11_, S22_;
  MonotoneCubic shear_;
  Mat3 C0_ = Mat3::Zero();
};

}  // namespace velum
