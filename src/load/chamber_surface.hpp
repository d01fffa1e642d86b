// The membrane elements that bound a gas chamber (or leak from it), as one bound load sees
// them: their volume with an origin, their area, the derivatives of both and the follower
// traction on them, each summed over the processes. Shared by the gas loads' terms.
#pragma once

#include <memory>
#include <span>
#include <vector>

#include "velum/assembly/assembler.hpp"
#include "velum/element/enclosed_volume.hpp"
#include "velum/load/gas_load.hpp"
#include "velum/model/model.hpp"
#include "velum/parallel/processes.hpp"

namespace velum {

// Listed membrane elements of a model: their volume with an origin, their area, and the
// derivatives of both, summed over the processes.
class ChamberSurface {
 public:
  ChamberSurface(const std::vector<GasLoad::Part>& parts, const LoadSite& site)
      : parts_(parts), site_(site) {
    for (const auto& part : parts) {
      Own& p = own_.emplace_back();
      const ElementBlock& b = *site.model.blocks[static_cast<size_t>(part.block)];
      for (int e : part.elements)
        if (site.assembler.owns(part.block, e)) p.elements.push_back(e);
      p.colors = site.assembler.own_colors(part.block, part.elements);
      p.kernel = make_surface_volume_kernel(b.type_name());
    }
  }
  double volume(const NodePositions& x, const Vec3& o) const {
    double V = 0;
    for (size_t k = 0; k < own_.size(); ++k)
      V += own_[k].kernel->volume(own_[k].elements, connectivity(k), x, o);
    if (site_.model.piece) processes::sum(&V, 1);
    return V;
  }
  double area(const NodePositions& x) const {
    double A = 0;
    for (size_t k = 0; k < own_.size(); ++k)
      A += own_[k].kernel->area(own_[k].elements, connectivity(k), x);
    if (site_.model.piece) processes::sum(&A, 1);
    return A;
  }
  // a = ∂V/∂x (overwritten) and, when K != null, scale ∂²V/∂x² subtracted from K.
  void volume_derivatives(const NodePositions& x, const Vec3& o, double scale, NodePositions& a,
                          SparseMatrix* K) const {
    a.setZero(3, site_.model.num_nodes());
    for (size_t k = 0; k < own_.size(); ++k) {
      const Own& p = own_[k];
      const auto conn = connectivity(k);
      site_.assembler.add_element_loads(
          parts_[k].block, p.colors,
          [&](std::span<const int> elems, double* f, double* H) {
            p.kernel->derivatives(elems, conn, x, o, scale, f, H);
          },
          a, K);
    }
    site_.assembler.sum_shares(a);
  }
  // b = ∂A/∂x (overwritten).
  void area_gradient(const NodePositions& x, NodePositions& b) const {
    b.setZero(3, site_.model.num_nodes());
    for (size_t k = 0; k < own_.size(); ++k) {
      const Own& p = own_[k];
      const auto conn = connectivity(k);
      site_.assembler.add_element_loads(
          parts_[k].block, p.colors,
          [&](std::span<const int> elems, double* f, double*) {
            p.kernel->area_gradient(elems, conn, x, f);
          },
          b, nullptr);
    }
    site_.assembler.sum_shares(b);
  }

  // F += the follower pressure `gauge` on the sheet, f_N = gauge ∫ N (g1 x g2) dξ: ∂V/∂x on
  // every component a symmetry plane leaves free, but without the part normal to the planes at
  // their nodes that the cone volume's open edges add (the octant: −⅔ p A_z). What the
  // supports carry (LoadState::at_supports); `work` is overwritten.
  void add_traction(const NodePositions& x, double gauge, NodePositions& work,
                    NodePositions& F) const {
    work.setZero(3, site_.model.num_nodes());
    for (size_t k = 0; k < own_.size(); ++k) {
      const ElementBlock& b = *site_.model.blocks[static_cast<size_t>(parts_[k].block)];
      site_.assembler.add_element_loads(
          parts_[k].block, own_[k].colors,
          [&](std::span<const int> elems, double* f, double*) {
            b.pressure(elems, x, gauge, f, nullptr);
          },
          work, nullptr);
    }
    site_.assembler.sum_shares(work);
    F += work;
  }

 private:
  std::span<const int> connectivity(size_t k) const {
    return site_.model.blocks[static_cast<size_t>(parts_[k].block)]->connectivity();
  }
  struct Own {
    std::vector<int> elements;
    Assembler::ElementColors colors;
    std::unique_ptr<SurfaceVolumeKernel> kernel;
  };
  std::vector<GasLoad::Part> parts_;
  LoadSite site_;
  std::vector<Own> own_;
};

}  // namespace velum
