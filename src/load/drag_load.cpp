// Payload drag f = −½ ρ C_D A |v| v on a node's velocity, and its velocity Jacobian.
#include "velum/load/drag_load.hpp"

#include "velum/assembly/assembler.hpp"
#include "velum/model/model.hpp"
#include "velum/parallel/processes.hpp"

namespace velum {
namespace {

class Drag final : public Load, public DragLoad {
 public:
  explicit Drag(DragLoad p) : DragLoad(p) {}
  std::string_view kind() const override { return "drag"; }
  LoadOrder order() const override { return LoadOrder::kVelocity; }
  std::unique_ptr<Load> clone() const override { return std::make_unique<Drag>(*this); }
  // Drag has no time function: a step holds it as it is.
  std::unique_ptr<Load> held(double, const Model&, Model&) const override { return clone(); }
  bool keep_piece(const Model&, const std::vector<std::vector<int>>&,
                  const std::vector<int>& local_of) override {
    node = local_of[static_cast<size_t>(node)];
    return node >= 0;
  }
  std::string_view counted_as() const override { return {}; }  // with the point masses
  std::unique_ptr<LoadTerm> bind(const LoadSite& site) const override;
};

class DragTerm final : public LoadTerm {
 public:
  DragTerm(const Drag& load, const LoadSite& site) : load_(load), site_(site) {}
  bool uses_velocity() const override { return c() > 0; }
  void add(const LoadState& s, LoadOutput& out) override {
    const double c = this->c();
    const int n = load_.node;
    if (c > 0 && (!site_.assembler.local_share() || site_.assembler.keeps_node(n)))
      out.F.col(n) -= c * s.V.col(n).norm() * s.V.col(n);
  }
  void add_velocity_jacobian(const NodePositions& V, double cv, SparseMatrix& J) const override {
    // Added once, by the first process (its share holds every point mass's node block).
    const double c = this->c();
    if (c <= 0 || processes::rank() != 0) return;
    const int node = load_.node;
    const DofMap& dofs = site_.dofs;
    const Vec3 vn = V.col(node);
    const double s = vn.norm();
    Mat3 D = c * s * Mat3::Identity();
    if (s > 0) D += (c / s) * vn * vn.transpose();
    // Rotate into the node frame if it has one, then add to the equations.
    const int f = dofs.frame(node);
    if (f >= 0) D = dofs.rotation(f) * D * dofs.rotation(f).transpose();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const int a1 = dofs.equation(node, i), a2 = dofs.equation(node, j);
        if (a1 >= 0 && a2 >= 0) J.coeffRef(a1, a2) += cv * D(i, j);
      }
  }

 private:
  double c() const { return 0.5 * load_.rho * load_.cd_area; }
  const Drag& load_;
  LoadSite site_;
};

std::unique_ptr<LoadTerm> Drag::bind(const LoadSite& site) const {
  return std::make_unique<DragTerm>(*this, site);
}

}  // namespace

std::unique_ptr<Load> make_load(DragLoad p) {
  return std::make_unique<Drag>(p);
}

}  // namespace velum
