// A force on each node of a set.
#include "velum/load/point_load.hpp"

#include "velum/assembly/assembler.hpp"
#include "velum/model/model.hpp"

namespace velum {
namespace {

class PointForce final : public Load, public PointLoad {
 public:
  explicit PointForce(PointLoad p) : PointLoad(std::move(p)) {}
  std::string_view kind() const override { return "point"; }
  LoadOrder order() const override { return LoadOrder::kNodal; }
  std::unique_ptr<Load> clone() const override { return std::make_unique<PointForce>(*this); }
  std::unique_ptr<Load> held(double t, const Model& owner, Model&) const override {
    auto h = std::make_unique<PointForce>(*this);
    h->force = force * owner.function_value(function, t);
    h->function = -1;
    return h;
  }
  bool keep_piece(const Model&, const std::vector<std::vector<int>>&,
                  const std::vector<int>& local_of) override {
    restrict_nodes(nodes, local_of);
    return true;
  }
  std::unique_ptr<LoadTerm> bind(const LoadSite& site) const override;
};

class PointForceTerm final : public LoadTerm {
 public:
  PointForceTerm(const PointForce& load, const LoadSite& site) : load_(load), site_(site) {}
  void add(const LoadState& s, LoadOutput& out) override {
    const Vec3 f = load_.force * site_.model.function_value(load_.function, s.t);
    // A process's share (Assembler::LocalShare): the nodes it keeps only.
    const bool share = site_.assembler.local_share();
    for (int n : load_.nodes)
      if (!share || site_.assembler.keeps_node(n)) out.F.col(n) += f;
  }

 private:
  const PointForce& load_;
  LoadSite site_;
};

std::unique_ptr<LoadTerm> PointForce::bind(const LoadSite& site) const {
  return std::make_unique<PointForceTerm>(*this, site);
}

}  // namespace

std::unique_ptr<Load> make_load(PointLoad p) {
  return std::make_unique<PointForce>(std::move(p));
}

}  // namespace velum
