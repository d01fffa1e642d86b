// Pressures on membrane elements: a follower pressure (through the block's internal pass when
// it covers the whole block) and a pressure along a fixed direction.
#include "velum/load/pressure_load.hpp"

#include "velum/assembly/assembler.hpp"
#include "velum/model/model.hpp"

namespace velum {
namespace {

// A pressure's element pass: its forces added to F (this process's share summed apart, then
// added, on several processes), its load stiffness subtracted from K.
template <class Kernel>
void add_pressure_pass(const Assembler& a, int block, const Assembler::ElementColors& colors,
                       const Kernel& kernel, NodePositions& scratch, LoadOutput& out) {
  const bool shared = a.sums_shares();
  NodePositions& F = shared ? scratch : out.F;
  if (shared) scratch.setZero(3, out.F.cols());
  a.add_element_loads(block, colors, kernel, F, out.K);
  if (shared) {
    a.sum_shares(scratch);
    out.F += scratch;
  }
}

template <class Self>
std::unique_ptr<Load> held_pressure(const Self& self, double t, const Model& owner) {
  auto h = std::make_unique<Self>(self);
  h->value = self.value * owner.function_value(self.function, t);
  h->function = -1;
  return h;
}

class FollowerPressure final : public Load, public PressureLoad {
 public:
  explicit FollowerPressure(PressureLoad p) : PressureLoad(std::move(p)) {}
  std::string_view kind() const override { return "pressure"; }
  LoadOrder order() const override { return LoadOrder::kSurface; }
  std::unique_ptr<Load> clone() const override { return std::make_unique<FollowerPressure>(*this); }
  std::unique_ptr<Load> held(double t, const Model& owner, Model&) const override {
    return held_pressure(*this, t, owner);
  }
  std::unique_ptr<LoadTerm> bind(const LoadSite& site) const override;
};

class FollowerPressureTerm final : public LoadTerm {
 public:
  FollowerPressureTerm(const FollowerPressure& load, const LoadSite& site)
      : load_(load), site_(site), colors_(site.assembler.own_colors(load.block, load.elements)) {
    const ElementBlock& b = *site.model.blocks[static_cast<size_t>(load.block)];
    std::vector<char> seen(static_cast<size_t>(b.size()), 0);
    int distinct = 0;
    for (int e : load.elements) distinct += seen[e] ? 0 : (seen[e] = 1);
    covers_block_ = distinct == b.size();
  }
  bool whole_block_pressure(double t, int& block, double& p) const override {
    if (!covers_block_) return false;
    block = load_.block;
    p = load_.value * site_.model.function_value(load_.function, t);
    return true;
  }
  void add(const LoadState& s, LoadOutput& out) override {
    if (s.fused && covers_block_) return;  // in the block's internal pass
    const double p = load_.value * site_.model.function_value(load_.function, s.t);
    if (p == 0) return;
    const SurfaceBlock& b = *site_.model.blocks[static_cast<size_t>(load_.block)]->surface();
    add_pressure_pass(
        site_.assembler, load_.block, colors_,
        [&](std::span<const int> elems, double* f, double* Ke) {
          b.pressure(elems, s.x, p, f, Ke);
        },
        scratch_, out);
  }

 private:
  const FollowerPressure& load_;
  LoadSite site_;
  Assembler::ElementColors colors_;
  bool covers_block_ = false;
  NodePositions scratch_;
};

std::unique_ptr<LoadTerm> FollowerPressure::bind(const LoadSite& site) const {
  return std::make_unique<FollowerPressureTerm>(*this, site);
}

class DirectedPressure final : public Load, public PressureLoad {
 public:
  explicit DirectedPressure(PressureLoad p) : PressureLoad(std::move(p)) {}
  std::string_view kind() const override { return "pressure"; }
  LoadOrder order() const override { return LoadOrder::kSurface; }
  std::unique_ptr<Load> clone() const override { return std::make_unique<DirectedPressure>(*this); }
  std::unique_ptr<Load> held(double t, const Model& owner, Model&) const override {
    return held_pressure(*this, t, owner);
  }
  std::unique_ptr<LoadTerm> bind(const LoadSite& site) const override;
};

class DirectedPressureTerm final : public LoadTerm {
 public:
  DirectedPressureTerm(const DirectedPressure& load, const LoadSite& site)
      : load_(load), site_(site), colors_(site.assembler.own_colors(load.block, load.elements)) {}
  void add(const LoadState& s, LoadOutput& out) override {
    const double p = load_.value * site_.model.function_value(load_.function, s.t);
    if (p == 0) return;
    const SurfaceBlock& b = *site_.model.blocks[static_cast<size_t>(load_.block)]->surface();
    add_pressure_pass(
        site_.assembler, load_.block, colors_,
        [&](std::span<const int> elems, double* f, double* Ke) {
          b.directed_pressure(elems, s.x, p, load_.direction, load_.projected, f, Ke);
        },
        scratch_, out);
  }

 private:
  const DirectedPressure& load_;
  LoadSite site_;
  Assembler::ElementColors colors_;
  NodePositions scratch_;
};

std::unique_ptr<LoadTerm> DirectedPressure::bind(const LoadSite& site) const {
  return std::make_unique<DirectedPressureTerm>(*this, site);
}

}  // namespace

std::unique_ptr<Load> make_load(PressureLoad p) {
  if (p.fixed_direction) return std::make_unique<DirectedPressure>(std::move(p));
  return std::make_unique<FollowerPressure>(std::move(p));
}

}  // namespace velum
