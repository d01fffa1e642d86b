// Gravity: the consistent mass times the acceleration, made once.
#include "velum/load/gravity_load.hpp"

#include "nodal_vector.hpp"
#include "velum/model/model.hpp"

namespace velum {
namespace {

class Gravity final : public Load, public GravityLoad {
 public:
  explicit Gravity(GravityLoad p) : GravityLoad(p) {}
  std::string_view kind() const override { return "gravity"; }
  LoadOrder order() const override { return LoadOrder::kBody; }
  std::unique_ptr<Load> clone() const override { return std::make_unique<Gravity>(*this); }
  std::unique_ptr<Load> held(double t, const Model& owner, Model&) const override {
    auto h = std::make_unique<Gravity>(*this);
    h->acceleration = acceleration * owner.function_value(function, t);
    h->function = -1;
    return h;
  }
  std::unique_ptr<LoadTerm> bind(const LoadSite& site) const override;
};

class GravityTerm final : public LoadTerm {
 public:
  GravityTerm(const Gravity& load, const LoadSite& site)
      : load_(load), site_(site), F_(site.assembler.gravity_forces(load.acceleration)) {}
  void add(const LoadState& s, LoadOutput& out) override {
    add_nodal_vector(site_.assembler, site_.model.function_value(load_.function, s.t), F_, out.F);
  }

 private:
  const Gravity& load_;
  LoadSite site_;
  NodePositions F_;
};

std::unique_ptr<LoadTerm> Gravity::bind(const LoadSite& site) const {
  return std::make_unique<GravityTerm>(*this, site);
}

}  // namespace

std::unique_ptr<Load> make_load(GravityLoad p) {
  return std::make_unique<Gravity>(p);
}

}  // namespace velum
