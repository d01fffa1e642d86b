// Concrete element blocks: the fixed-size kernels of element/ behind the ElementBlock interface.
#include <fmt/format.h>
#include <Eigen/Cholesky>

#include <algorithm>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "velum/element/cable.hpp"
#include "velum/element/membrane.hpp"
#include "velum/element/membrane_explicit.hpp"
#include "velum/model/element_block.hpp"

namespace velum {
namespace {

template <int N>
Eigen::Matrix<double, 3, N> gather(const NodePositions& x, std::span<const int> nodes) {
  Eigen::Matrix<double, 3, N> out;
  for (int i = 0; i < N; ++i) out.col(i) = x.col(nodes[i]);
  return out;
}

// Asks for the next element's record while this one is computed. A membrane's record (its
// points' D, G, T, weights: 648 bytes for a Quad4) spans eleven cache lines and is read once a
// pass, in the assembly's colour order (groups of 16 consecutive elements), from memory on a
// large mesh: without the prefetch the passes wait on memory for every record (with the
// rule's pointer moved to the record's head, below, both residual and tangent passes gained).
template <class Record>
void prefetch(const Record& r) {
  const char* p = reinterpret_cast<const char*>(&r);
  for (size_t b = 0; b < sizeof(Record); b += 64) __builtin_prefetch(p + b);
}

/// The kernels' constitutive policy for a sheet law: the constant D precomputed at set-up
/// wherever the law is affine (the fast path), the law itself at each point otherwise.
template <class Law>
Law points_policy(const SheetLaw& law);
template <>
ElasticPoints points_policy<ElasticPoints>(const SheetLaw&) {
  return {};
}
template <>
PrestressedPoints points_policy<PrestressedPoints>(const SheetLaw& law) {
  return {law.prestress()};
}

template <class Shape, class Law>
class MembraneBlock final : public SurfaceBlock {
  using K = Membrane<Shape>;
  static constexpr int kN = Shape::kNodes;
  static constexpr bool kHistory = std::is_same_v<Law, HistoryLawPoints>;
  static constexpr bool kPrestressed = std::is_same_v<Law, PrestressedPoints>;
  // An affine law: the explicit step takes MembraneExplicit's kernel and records.
  static constexpr bool kAffine = kPrestressed || std::is_same_v<Law, ElasticPoints>;

 public:
  MembraneBlock(std::string set, std::vector<int> conn, const NodePositions& X, const SheetLaw& law,
                double density, double t0, const SheetAxes* axes, shape::Integration integration,
                BlockSetupReport& report)
      : SurfaceBlock(shape::info_of<Shape>(), std::move(set), std::move(conn), density),
        t0_(t0),
        axes_(axes ? std::optional<SheetAxes>(*axes) : std::nullopt),
        law_(std::make_unique<SheetLaw>(law)),
        integration_(integration) {
    if constexpr (std::is_same_v<Law, LawPoints>) {
      policy_.law = law_.get();
    } else if constexpr (kHistory) {
      policy_.law = law_.get();
      policy_.size = law.state_size();
    } else {
      policy_ = points_policy<Law>(law);
    }
    const int ne = size();
    points_.resize(ne);
    Xref_.resize(ne);
    for (int e = 0; e < ne; ++e) {
      const auto Xe = gather<kN>(X, nodes(e));
      Xref_[e] = Xe;
      const Vec3 n = K::centre_normal(Xe);
      double quality = 1.0;
      const SheetAxes a = axes ? project_axes(*axes, n, &quality) : default_axes(n);
      if (quality < report.poor_axes_quality) {
        report.poor_axes_quality = quality;
        report.poor_axes_element = e;
      }
      // Axes given for the sector are projected per point inside setup; default axes are
      // already in this element's plane.
      const double jac =
          K::setup(Xe, law.reference_stiffness(), axes ? *axes : a, t0, points_[e], integration);
      if (e == 0 || jac < report.worst_jacobian) {
        report.worst_jacobian = jac;
        report.worst_element = e;
      }
    }
    if constexpr (kHistory) {
      const size_t n = static_cast<size_t>(policy_.size);
      history_.resize(static_cast<size_t>(ne) * Shape::kPoints * n);
      for (size_t k = 0; k < history_.size(); k += n)
        law_->base().initial_state(std::span<double>(history_.data() + k, n));
    }
  }

  bool prestressed() const override { return law_->has_prestress(); }

  size_t history_size() const override { return history_.size(); }
  size_t history_per_element() const override {
    if constexpr (kHistory)
      return Shape::kPoints * static_cast<size_t>(policy_.size);
    else
      return 0;
  }
  void commit_history(const NodePositions& x) override {
    if constexpr (kHistory) {
      const size_t n = static_cast<size_t>(policy_.size);
      for (int e = 0; e < size(); ++e) {
        if (!holds(e)) continue;
        const auto& pts = points_[slot(e)];
        const auto xe = gather<kN>(x, nodes(e));
        double* h = history_.data() + static_cast<size_t>(slot(e)) * Shape::kPoints * n;
        for (int q = 0; q < Shape::kPoints; ++q) {
          const Eigen::Matrix<double, 3, 2> g = xe * pts.shapes->dN[q];
          const Vec3 E = sheet_strain_map(pts[q].T) * K::strain(pts[q], g);
          law_->base().update_state(E, std::span<double>(h + q * n, n));
        }
      }
    }
  }
  void save_history(std::vector<double>& out) const override {
    out.insert(out.end(), history_.begin(), history_.end());
  }
  size_t restore_history(const std::vector<double>& in, size_t at) override {
    if (at + history_.size() > in.size())
      throw std::invalid_argument(
          fmt::format("the saved history of set '{}' is cut short", set_name()));
    std::copy(in.begin() + static_cast<std::ptrdiff_t>(at),
              in.begin() + static_cast<std::ptrdiff_t>(at + history_.size()), history_.begin());
    return at + history_.size();
  }
  Vec3 sheet_prestress() const override { return law_->prestress(); }
  Mat3 sheet_stiffness() const override { return law_->reference_stiffness(); }
  std::unique_ptr<ElementBlock> rebuilt(std::vector<int> connectivity, const NodePositions& X,
                                        double stabilizer,
                                        std::span<const int> listed) const override {
    BlockSetupReport report;
    const bool any = !connectivity.empty();  // a piece may hold none of the block's elements
    const SheetAxes* axes = axes_ ? &*axes_ : nullptr;
    std::unique_ptr<ElementBlock> out;
    if (stabilizer > 0 && law_->has_prestress()) {
      const SheetLaw ff = form_finding_law(*law_, stabilizer);
      out = make_membrane_block(Shape::kName, set_name(), std::move(connectivity), X, ff, density(),
                                t0_, axes, integration_, report);
    } else {
      out = make_membrane_block(Shape::kName, set_name(), std::move(connectivity), X, *law_,
                                density(), t0_, axes, integration_, report);
    }
    if (any && !(report.worst_jacobian > 0))
      throw std::invalid_argument(fmt::format(
          "{} element {} of set '{}' degenerates (zero or negative area) on the new reference",
          Shape::kName, element_number(report.worst_element, listed), set_name()));
    return out;
  }
  bool tension_field() const override { return law_->wrinkling(); }
  bool thins() const override { return law_->thins(); }
  bool yields() const override { return law_->yields(); }

  void internal(std::span<const int> elements, const NodePositions& x, double* r,
                double* Kout) const override {
    forces<false>(elements, x, 0.0, r, Kout, nullptr, nullptr);
  }
  void internal_and_pressure(std::span<const int> elements, const NodePositions& x, double p,
                             double* r, double* Kout, double* f, double* Kp) const override {
    forces<true>(elements, x, p, r, Kout, f, Kp);
  }
  void explicit_forces(std::span<const int> elements, const NodePositions& x, double p,
                       NodePositions& F, NodePositions& Fp) const override {
    using Nodes = typename K::Nodes;
    Nodes r, f;
    auto add = [&](std::span<const int> nodes, const Nodes& v, NodePositions& to) {
      for (int n = 0; n < kN; ++n) to.col(nodes[n]) += v.col(n);
    };
    if constexpr (kAffine) {
      const auto& records = explicit_records();
      const auto& shapes = ExplicitShapes<Shape>::of(integration_);
      for (size_t i = 0; i < elements.size(); ++i) {
        if (i + 1 < elements.size()) prefetch(records[slot(elements[i + 1])]);
        const auto nodes = this->nodes(elements[i]);
        const auto& rec = records[slot(elements[i])];
        if (p != 0) {
          MembraneExplicit<Shape>::template force<true>(shapes, rec, gather<kN>(x, nodes), p, r, f);
          add(nodes, f, Fp);
        } else {
          MembraneExplicit<Shape>::template force<false>(shapes, rec, gather<kN>(x, nodes), p, r,
                                                         f);
        }
        add(nodes, r, F);
      }
    } else {
      typename K::Vector re, fe;
      for (size_t i = 0; i < elements.size(); ++i) {
        if (i + 1 < elements.size()) prefetch(points_[slot(elements[i + 1])]);
        const int e = elements[i];
        const auto nodes = this->nodes(e);
        const auto xe = gather<kN>(x, nodes);
        if (p != 0) {
          K::force_and_pressure(points_[slot(e)], policy_at(slot(e)), xe, p, re, fe);
          add(nodes, Eigen::Map<const Nodes>(fe.data()), Fp);
        } else {
          K::force(points_[slot(e)], policy_at(slot(e)), xe, re);
        }
        add(nodes, Eigen::Map<const Nodes>(re.data()), F);
      }
    }
  }

  void pressure(std::span<const int> elements, const NodePositions& x, double p, double* f,
                double* Kout) const override {
    typename K::Vector fe;
    for (size_t i = 0; i < elements.size(); ++i) {
      const int e = elements[i];
      const auto xe = gather<kN>(x, nodes(e));
      if (Kout) {
        K::pressure_force_tangent(
            points_[slot(e)], xe, p, fe,
            *reinterpret_cast<typename K::Matrix*>(Kout + i * K::kDofs * K::kDofs));
      } else {
        K::pressure_force(points_[slot(e)], xe, p, fe);
      }
      Eigen::Map<typename K::Vector>(f + i * K::kDofs) = fe;
    }
  }

  void directed_pressure(std::span<const int> elements, const NodePositions& x, double p,
                         const Vec3& d, bool projected, double* f, double* Kout) const override {
    typename K::Vector fe;
    for (size_t i = 0; i < elements.size(); ++i) {
      const int e = elements[i];
      const auto xe = gather<kN>(x, nodes(e));
      if (Kout) {
        K::directed_pressure_force_tangent(
            points_[slot(e)], xe, p, d, projected, fe,
            *reinterpret_cast<typename K::Matrix*>(Kout + i * K::kDofs * K::kDofs));
      } else {
        K::directed_pressure_force(points_[slot(e)], xe, p, d, projected, fe);
      }
      Eigen::Map<typename K::Vector>(f + i * K::kDofs) = fe;
    }
  }

  void mass(int e, double* M) const override {
    Eigen::Map<typename K::NodeMatrix> out(M);
    out = density() * K::mass(points_[slot(e)]);  // recomputed: a static run never asks
  }
  void tension_stiffness(int e, double* T) const override {
    Eigen::Map<typename K::NodeMatrix> out(T);
    out = K::tension_stiffness(points_[slot(e)]);
  }
  double measure(int e) const override {
    double A = 0;
    for (const auto& p : points_[slot(e)].at) A += p.t0dA;
    return A / t0_;
  }

  double strain_energy(std::span<const int> elements, const NodePositions& x) const override {
    double U = 0;
    for (size_t i = 0; i < elements.size(); ++i) {
      if (i + 1 < elements.size()) prefetch(points_[slot(elements[i + 1])]);
      U += K::strain_energy(points_[slot(elements[i])], policy_at(slot(elements[i])),
                            gather<kN>(x, nodes(elements[i])));
    }
    return U;
  }
  int first_inverted(std::span<const int> elements, const NodePositions& from,
                     const NodePositions& to) const override {
    const auto& shapes = PointShapes<Shape>::of(integration_);  // every element's rule
    for (int e : elements)
      if (!K::keeps_orientation(shapes, gather<kN>(from, nodes(e)), gather<kN>(to, nodes(e))))
        return e;
    return -1;
  }

  void keep_only(std::span<const int> elements) override {
    if constexpr (kHistory) {
      const size_t n = Shape::kPoints * static_cast<size_t>(policy_.size);
      std::vector<double> h;
      h.reserve(elements.size() * n);
      for (int e : elements) {
        const auto from = history_.begin() + static_cast<std::ptrdiff_t>(slot(e) * n);
        h.insert(h.end(), from, from + static_cast<std::ptrdiff_t>(n));
      }
      history_ = std::move(h);
    }
    points_ = kept(points_, elements);  // the others' storage freed
    if constexpr (kAffine) {
      explicit_ = {};  // rebuilt from the kept points on the next explicit step
      explicit_once_ = std::make_unique<std::once_flag>();
    }
    Xref_ = kept(Xref_, elements);
    set_kept(elements);
  }

  ElementOutput output(int e, const NodePositions& x) const override {
    // At the element centre: ξ = (1/3, 1/3) for triangles, (0, 0) for quadrilaterals.
    const std::array<double, 2> c = Shape::kTriangle ? std::array<double, 2>{1.0 / 3, 1.0 / 3}
                                                     : std::array<double, 2>{0.0, 0.0};
    ElementOutput out;
    out.stress = output_at(e, c, x);
    out.thickness = t0_;
    const Vec3& E = out.stress.strain;  // tensor E12: the law takes 2 E12
    out.current_thickness = t0_ * law_->thickness_ratio(Vec3(E[0], E[1], 2 * E[2]));
    if constexpr (kHistory) {
      // The committed history's equivalent plastic strain, averaged over the points.
      const size_t n = static_cast<size_t>(policy_.size);
      const double* h = history_.data() + static_cast<size_t>(slot(e)) * Shape::kPoints * n;
      for (int q = 0; q < Shape::kPoints; ++q)
        out.plastic_strain += law_->plastic_strain(std::span<const double>(h + q * n, n));
      out.plastic_strain /= Shape::kPoints;
    }
    return out;
  }

  bool locate(int e, const Vec3& P, std::array<double, 2>& xi) const override {
    // Closest point on the reference surface by Gauss-Newton from the element centre.
    const auto Xe = Xref_cols(e);
    constexpr bool kTriangle = Shape::kTriangle;
    Vec2 r = kTriangle ? Vec2(1.0 / 3, 1.0 / 3) : Vec2(0, 0);
    typename Shape::Values N;
    typename Shape::Derivs dN;
    for (int it = 0; it < 20; ++it) {
      Shape::eval(r[0], r[1], N, dN);
      const Eigen::Matrix<double, 3, 2> G = Xe * dN;
      const Vec3 d = P - Xe * N;
      const Vec2 step = (G.transpose() * G).ldlt().solve(G.transpose() * d);
      r += step;
      if (step.norm() < 1e-13) break;
    }
    Shape::eval(r[0], r[1], N, dN);
    const double h = (Xe.col(1) - Xe.col(0)).norm();
    const double tol = 1e-7;  // in ξ: points on element edges and corners must be found
    const bool inside = kTriangle ? (r[0] >= -tol && r[1] >= -tol && r[0] + r[1] <= 1 + tol)
                                  : (std::abs(r[0]) <= 1 + tol && std::abs(r[1]) <= 1 + tol);
    if (!inside || (P - Xe * N).norm() > 1e-6 * h) return false;
    xi = {r[0], r[1]};
    return true;
  }

  MembraneStress output_at(int e, const std::array<double, 2>& xi,
                           const NodePositions& x) const override {
    // Everything at xi itself, as set-up does at an integration point: the reference metric
    // from the reference positions, the sheet axes projected onto the tangent plane there, and
    // the section's law (the same stress the kernels integrate, at any point of the element).
    typename Shape::Values N;
    typename Shape::Derivs dN;
    Shape::eval(xi[0], xi[1], N, dN);
    const auto xe = gather<kN>(x, nodes(e));
    const Eigen::Matrix<double, 3, 2> g = xe * dN;
    const Eigen::Matrix<double, 3, 2> G = Xref_cols(e) * dN;
    const Mat2 Gcov = G.transpose() * G;
    const Vec3 Gm(Gcov(0, 0), Gcov(1, 1), Gcov(0, 1));
    const SheetAxes sector = axes_ ? *axes_ : default_axes(K::centre_normal(Xref_cols(e)));
    const SheetAxes m = project_axes(sector, G.col(0).cross(G.col(1)).normalized());
    const Eigen::Matrix<double, 3, 2> Gcontra = G * Gcov.inverse();  // G^α
    Mat2 T;
    for (int al = 0; al < 2; ++al) {
      T(0, al) = m.m1.dot(Gcontra.col(al));
      T(1, al) = m.m2.dot(Gcontra.col(al));
    }
    const Vec3 strain(0.5 * (g.col(0).squaredNorm() - Gm[0]),
                      0.5 * (g.col(1).squaredNorm() - Gm[1]), g.col(0).dot(g.col(1)) - Gm[2]);
    const Mat3 A = sheet_strain_map(T);
    SheetResponse r;
    if constexpr (kHistory) {
      // The history of the integration point nearest to xi (on the reference surface).
      const auto& shapes = PointShapes<Shape>::of(integration_);
      const Vec3 P = Xref_cols(e) * N;
      int nearest = 0;
      for (int q = 1; q < Shape::kPoints; ++q)
        if ((Xref_cols(e) * shapes.N[q] - P).squaredNorm() <
            (Xref_cols(e) * shapes.N[nearest] - P).squaredNorm())
          nearest = q;
      const size_t n = static_cast<size_t>(policy_.size);
      const size_t at =
          (static_cast<size_t>(slot(e)) * Shape::kPoints + static_cast<size_t>(nearest)) * n;
      law_->evaluate(A * strain, std::span<const double>(history_.data() + at, n), r);
    } else {
      law_->evaluate(A * strain, r);
    }
    MembraneStress out = membrane_stress(g, A.transpose() * r.S, Gm, T);
    out.wrinkle_state = static_cast<int>(r.state);
    if (r.state == WrinkleState::kWrinkled) {
      // The tension direction n = cos θ m1 + sin θ m2, as deformed: F n = g_α T(a,α) n_a.
      const Vec2 n(std::cos(r.angle), std::sin(r.angle));
      out.wrinkle_dir = (g * (T.transpose() * n)).normalized();
    }
    return out;
  }

 private:
  // The internal forces (and tangents, when Kout) of `elements`, with the pressure p's forces
  // (and load stiffnesses) in the same pass when kPressure.
  template <bool kPressure>
  void forces(std::span<const int> elements, const NodePositions& x, double p, double* r,
              double* Kout, double* f, double* Kp) const {
    typename K::Vector re, fe;
    for (size_t i = 0; i < elements.size(); ++i) {
      if (i + 1 < elements.size()) prefetch(points_[slot(elements[i + 1])]);
      const auto& pts = points_[slot(elements[i])];
      const auto& law = policy_at(slot(elements[i]));
      const auto xe = gather<kN>(x, nodes(elements[i]));
      using Matrix = typename K::Matrix;
      if (Kout) {
        K::force_tangent(pts, law, xe, re,
                         *reinterpret_cast<Matrix*>(Kout + i * K::kDofs * K::kDofs));
        if constexpr (kPressure)
          K::pressure_force_tangent(pts, xe, p, fe,
                                    *reinterpret_cast<Matrix*>(Kp + i * K::kDofs * K::kDofs));
      } else if constexpr (kPressure) {
        K::force_and_pressure(pts, law, xe, p, re, fe);
      } else {
        K::force(pts, law, xe, re);
      }
      Eigen::Map<typename K::Vector>(r + i * K::kDofs) = re;
      if constexpr (kPressure) Eigen::Map<typename K::Vector>(f + i * K::kDofs) = fe;
    }
  }

  // The law's policy at the element of slot s: the block's own, or (a law with history) a copy
  // pointing at that element's points and history.
  decltype(auto) policy_at(int s) const {
    if constexpr (kHistory) {
      Law p = policy_;
      p.first = &points_[static_cast<size_t>(s)].at[0];
      p.history = history_.data() +
                  static_cast<size_t>(s) * Shape::kPoints * static_cast<size_t>(policy_.size);
      return p;
    } else {
      return static_cast<const Law&>(policy_);
    }
  }

  const Eigen::Matrix<double, 3, kN>& Xref_cols(int e) const { return Xref_[slot(e)]; }

  double t0_;
  std::optional<SheetAxes> axes_;  // the section's axes; none: the default per element
  std::unique_ptr<SheetLaw> law_;  // owned here: the policy points to it (stable address)
  Law policy_;
  std::vector<double> history_;     // a law with history: committed, per held element and point
  shape::Integration integration_;  // kept for on_reference (form finding)
  std::vector<typename K::Points> points_;
  // An affine law: the explicit step's records per held element (MembraneExplicit), built
  // from points_ on the first explicit step (an implicit run never holds them; the step's
  // threads may all ask at once).
  const std::vector<ExplicitPoints<Shape>>& explicit_records() const {
    std::call_once(*explicit_once_, [this] {
      explicit_.resize(points_.size());
      const Vec3 S0 = kPrestressed ? law_->prestress() : Vec3::Zero();
      for (size_t k = 0; k < points_.size(); ++k)
        MembraneExplicit<Shape>::record(points_[k], S0, explicit_[k]);
    });
    return explicit_;
  }
  mutable std::vector<ExplicitPoints<Shape>> explicit_;
  mutable std::unique_ptr<std::once_flag> explicit_once_ = std::make_unique<std::once_flag>();
  std::vector<Eigen::Matrix<double, 3, kN>, Eigen::aligned_allocator<Eigen::Matrix<double, 3, kN>>>
      Xref_;  // reference coordinates per element (locate, output_at)
};

template <class Shape>
class CableBlock final : public ElementBlock {
  using K = Cable<Shape>;
  static constexpr int kN = Shape::kNodes;

 public:
  CableBlock(std::string set, std::vector<int> conn, const NodePositions& X, const CableLaw& law,
             double density, double area, shape::Integration integration, BlockSetupReport& report)
      : ElementBlock(shape::info_of<Shape>(), std::move(set), std::move(conn), density),
        law_(law),
        area_(area),
        integration_(integration) {
    const int ne = size();
    points_.resize(ne);
    for (int e = 0; e < ne; ++e) {
      const double len = K::setup(gather<kN>(X, nodes(e)), law.E, area, points_[e], integration);
      if (e == 0 || len < report.worst_jacobian) {
        report.worst_jacobian = len;
        report.worst_element = e;
      }
    }
  }

  bool prestressed() const override { return law_.S0 != 0; }
  std::unique_ptr<ElementBlock> rebuilt(std::vector<int> connectivity, const NodePositions& X,
                                        double stabilizer,
                                        std::span<const int> listed) const override {
    BlockSetupReport report;
    const bool any = !connectivity.empty();  // a piece may hold none of the block's elements
    CableLaw law = law_;
    if (stabilizer > 0 && law_.S0 > 0) law.E = stabilizer * law_.S0;
    auto out = make_cable_block(Shape::kName, set_name(), std::move(connectivity), X, law,
                                density(), area_, integration_, report);
    if (any && !(report.worst_jacobian > 0))
      throw std::invalid_argument(
          fmt::format("{} element {} of set '{}' has zero length on the new reference",
                      Shape::kName, element_number(report.worst_element, listed), set_name()));
    return out;
  }
  void internal(std::span<const int> elements, const NodePositions& x, double* r,
                double* Kout) const override {
    typename K::Vector re;
    for (size_t i = 0; i < elements.size(); ++i) {
      const int e = elements[i];
      const auto xe = gather<kN>(x, nodes(e));
      if (Kout) {
        K::force_tangent(points_[slot(e)], law_, xe, re,
                         *reinterpret_cast<typename K::Matrix*>(Kout + i * K::kDofs * K::kDofs));
      } else {
        K::force(points_[slot(e)], law_, xe, re);
      }
      Eigen::Map<typename K::Vector>(r + i * K::kDofs) = re;
    }
  }
  void mass(int e, double* M) const override {
    Eigen::Map<typename K::NodeMatrix> out(M);
    out = (density() * area_) * K::mass(points_[slot(e)]);
  }
  void tension_stiffness(int e, double* T) const override {
    Eigen::Map<typename K::NodeMatrix> out(T);
    out = area_ * K::tension_stiffness(points_[slot(e)]);
  }
  double measure(int e) const override { return K::length(points_[slot(e)]); }
  double strain_energy(std::span<const int> elements, const NodePositions& x) const override {
    double U = 0;
    for (int e : elements) U += K::strain_energy(points_[slot(e)], law_, gather<kN>(x, nodes(e)));
    return U;
  }
  int first_inverted(std::span<const int> elements, const NodePositions& from,
                     const NodePositions& to) const override {
    for (int e : elements)
      if (!K::keeps_orientation(points_[slot(e)], gather<kN>(from, nodes(e)),
                                gather<kN>(to, nodes(e))))
        return e;
    return -1;
  }
  void keep_only(std::span<const int> elements) override {
    points_ = kept(points_, elements);  // the others' storage freed
    set_kept(elements);
  }
  ElementOutput output(int e, const NodePositions& x) const override {
    ElementOutput out;
    out.cable_force = K::true_force(points_[slot(e)], law_, gather<kN>(x, nodes(e)));
    return out;
  }

 private:
  CableLaw law_;
  double area_;
  shape::Integration integration_;
  std::vector<typename K::Points> points_;
};

}  // namespace

std::unique_ptr<ElementBlock> ElementBlock::on_reference(const NodePositions& X,
                                                         double stabilizer) const {
  if (slot_.empty()) return rebuilt(connectivity_, X, stabilizer, {});
  // A piece: the held elements only (the others have no nodes here), then every element's
  // numbering back, their data at the same slots.
  std::vector<int> held, conn;
  for (int e = 0; e < size(); ++e)
    if (holds(e)) {
      held.push_back(e);
      const auto nodes = this->nodes(e);
      conn.insert(conn.end(), nodes.begin(), nodes.end());
    }
  auto out = rebuilt(std::move(conn), X, stabilizer, held);
  out->connectivity_ = connectivity_;
  out->slot_ = slot_;
  return out;
}

void ElementBlock::keep_piece(std::span<const int> elements, const std::vector<int>& local_of) {
  keep_only(elements);
  const int n = nodes_per_element();
  std::vector<int> renumbered(connectivity_.size(), -1);
  for (int e : elements)
    for (int k = 0; k < n; ++k) {
      const size_t at = static_cast<size_t>(e) * static_cast<size_t>(n) + static_cast<size_t>(k);
      renumbered[at] = local_of[static_cast<size_t>(connectivity_[at])];
    }
  connectivity_ = std::move(renumbered);
}

void ElementBlock::spread(int total, std::span<const int> elements) {
  if (!slot_.empty() || static_cast<size_t>(size()) != elements.size())
    throw std::logic_error("ElementBlock::spread: not a block of the listed elements only");
  const auto n = static_cast<size_t>(nodes_per_element());
  std::vector<int> spread(static_cast<size_t>(total) * n, -1);
  for (size_t i = 0; i < elements.size(); ++i)
    std::copy_n(connectivity_.begin() + static_cast<std::ptrdiff_t>(i * n), n,
                spread.begin() + static_cast<std::ptrdiff_t>(static_cast<size_t>(elements[i]) * n));
  connectivity_ = std::move(spread);
  set_kept(elements);
}

void ElementBlock::pressure(std::span<const int> elements, const NodePositions& x, double p,
                            double* f, double* K) const {
  if (!surface()) throw std::logic_error(fmt::format("pressure on a {} block", type_name()));
  surface()->pressure(elements, x, p, f, K);
}

MembraneStress ElementBlock::output_at(int e, const std::array<double, 2>& xi,
                                       const NodePositions& x) const {
  if (!surface()) throw std::logic_error(fmt::format("surface output of a {} block", type_name()));
  return surface()->output_at(e, xi, x);
}

std::unique_ptr<ElementBlock> make_membrane_block(std::string_view type, std::string set,
                                                  std::vector<int> conn, const NodePositions& X,
                                                  const SheetLaw& law, double density, double t0,
                                                  const SheetAxes* axes,
                                                  shape::Integration integration,
                                                  BlockSetupReport& report) {
  auto build = [&]<class S>(S) -> std::unique_ptr<ElementBlock> {
    if (integration == shape::Integration::kNodal && !S::kNodalRule)
      throw std::invalid_argument(fmt::format(
          "nodal integration is available for tri3, quad4 and quad9, not {}", S::kName));
    auto make = [&]<class Law>(Law) -> std::unique_ptr<ElementBlock> {
      return std::make_unique<MembraneBlock<S, Law>>(std::move(set), std::move(conn), X, law,
                                                     density, t0, axes, integration, report);
    };
    if (law.state_size() > 0) return make(HistoryLawPoints{});
    if (!law.affine()) return make(LawPoints{});
    if (law.has_prestress()) return make(PrestressedPoints{});
    return make(ElasticPoints{});
  };
  const shape::ShapeInfo* info = shape::find(type);
  if (!info || !info->surface())
    throw std::invalid_argument("unknown membrane element type '" + std::string(type) + "'");
  return shape::with_shape(*info, [&]<class S>(S) -> std::unique_ptr<ElementBlock> {
    if constexpr (S::kDim == 2)
      return build(S{});
    else
      return nullptr;  // a surface row names a surface shape (shape_info_test)
  });
}

std::unique_ptr<ElementBlock> make_cable_block(std::string_view type, std::string set,
                                               std::vector<int> conn, const NodePositions& X,
                                               const CableLaw& law, double density, double area,
                                               shape::Integration integration,
                                               BlockSetupReport& report) {
  const shape::ShapeInfo* info = shape::find(type);
  if (!info || !info->line())
    throw std::invalid_argument("unknown cable element type '" + std::string(type) + "'");
  return shape::with_shape(*info, [&]<class S>(S) -> std::unique_ptr<ElementBlock> {
    if constexpr (S::kDim == 1)
      return std::make_unique<CableBlock<S>>(std::move(set), std::move(conn), X, law, density, area,
                                             integration, report);
    else
      return nullptr;  // a line row names a line shape (shape_info_test)
  });
}

}  // namespace velum
