// A block of elements of one shape sharing one section (material, thickness or area, axes).
// Virtual dispatch happens once per call on a block, never per element: each call computes
// a list of elements and writes their fixed-size results, element after element, into
// caller-provided buffers (the assembler scatters them; blocks never see global storage).
#pragma once

#include <cassert>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "velum/element/stress_output.hpp"
#include "velum/material/axes.hpp"
#include "velum/material/cable_law.hpp"
#include "velum/material/sheet_law.hpp"
#include "velum/model/time_function.hpp"
#include "velum/shape/shape_info.hpp"

namespace velum {

/// Current node positions, one column per node (3 x nodes), global Cartesian.
using NodePositions = Eigen::Matrix<double, 3, Eigen::Dynamic>;

/// Membranes are the surface blocks (ElementBlock::surface() non-null), cables the others.
enum class ElementKind { kMembrane, kCable };

struct ElementOutput {
  MembraneStress stress;   ///< membranes: at the element centre (ξ of the centroid)
  double thickness = 0;    ///< membranes: the reference thickness t0 (σ t0 = force per length)
  double cable_force = 0;  ///< cables: true axial force, mean over the points
  double current_thickness = 0;  ///< membranes: the thickness as deformed (t0 unless the law thins)
  double plastic_strain = 0;     ///< membranes: equivalent plastic strain, mean over the points
};

class SurfaceBlock;
class SlidingChains;

/// What every block answers. A capability only some blocks have (loads on a surface, points
/// located on it) is its own interface, reached through an accessor that is null elsewhere:
/// surface(). A new element kind is a class implementing these (and its capabilities).
class ElementBlock {
 public:
  virtual ~ElementBlock() = default;

  /// The shape's row (shape_info.hpp): node count, edges, file-format ids, lumping.
  const shape::ShapeInfo& shape() const { return *shape_; }
  std::string_view type_name() const { return shape_->name; }  ///< tri3 ... quad9, cable2, cable3
  /// The surface capability (membranes), or null (lines).
  virtual const SurfaceBlock* surface() const { return nullptr; }
  ElementKind kind() const { return surface() ? ElementKind::kMembrane : ElementKind::kCable; }
  /// The sliding capability (sliding_cable chains: the material's slip), or null.
  virtual const SlidingChains* sliding() const { return nullptr; }
  int nodes_per_element() const { return shape_->nodes; }
  int dofs_per_element() const { return 3 * nodes_per_element(); }
  int size() const { return static_cast<int>(connectivity_.size()) / nodes_per_element(); }
  /// Node indices (0-based, into the model's node arrays) of element e.
  std::span<const int> nodes(int e) const {
    const int n = nodes_per_element();
    return {connectivity_.data() + static_cast<size_t>(e) * n, static_cast<size_t>(n)};
  }
  const std::vector<int>& connectivity() const { return connectivity_; }
  const std::string& set_name() const { return set_name_; }
  double density() const { return density_; }

  /// Internal forces (stride dofs) and, when K is non-null, tangents (stride dofs², column-major)
  /// of the listed elements.
  virtual void internal(std::span<const int> elements, const NodePositions& x, double* r,
                        double* K) const = 0;
  /// Consistent mass of element e including density (scalar nodes x nodes, column-major).
  virtual void mass(int e, double* M) const = 0;
  /// Geometric stiffness of a uniform unit tension (a unit 2nd PK stress in every direction of
  /// the reference surface, or along the reference line, times the thickness or area) of
  /// element e (scalar nodes x nodes, column-major, to be multiplied by I3).
  virtual void tension_stiffness(int e, double* K) const = 0;
  /// Reference measure (area for membranes, length for cables) of element e.
  virtual double measure(int e) const = 0;
  /// Strain energy of the listed elements (summed in their order).
  virtual double strain_energy(std::span<const int> elements, const NodePositions& x) const = 0;
  /// The first of the listed elements (ascending) that turns inside out between configurations
  /// `from` and `to` (a surface normal or a line's axis reversing, or collapsing to zero, at a
  /// point), or -1.
  virtual int first_inverted(std::span<const int> elements, const NodePositions& from,
                             const NodePositions& to) const = 0;
  virtual ElementOutput output(int e, const NodePositions& x) const = 0;

  /// surface()->pressure(...) and surface()->output_at(...), for code holding a block it
  /// knows to be a surface; std::logic_error on a line block.
  void pressure(std::span<const int> elements, const NodePositions& x, double p, double* f,
                double* K) const;
  MembraneStress output_at(int e, const std::array<double, 2>& xi, const NodePositions& x) const;

  /// The same block (elements, section) set up on the reference configuration X (form
  /// finding updates the reference to the current shape). With `stabilizer` > 0, the
  /// form-finding law instead of the section's: the prestress kept, the elastic law scaled so
  /// that its largest stiffness is `stabilizer` times the largest prestress component
  /// (membranes) or E A = `stabilizer` times the prestress force (cables), no wrinkling; a
  /// section without prestress keeps its law. After keep_only, only the held elements are set
  /// up (the new block holds the same ones). Throws std::invalid_argument when an element
  /// degenerates on X.
  std::unique_ptr<ElementBlock> on_reference(const NodePositions& X, double stabilizer) const;
  /// Whether the section carries a prestress.
  virtual bool prestressed() const = 0;

  // A law with a history per integration point (SheetLawBase::state_size: plasticity). The
  // forces are evaluated from the history committed at the last accepted step (a trial state
  // never stored: a step that fails leaves it as it was); MechanicalSystem::accept commits it
  // at the accepted positions; checkpoints and staged runs carry it as numbers.
  // A section that changes in time (a reefing line's length, a cut line): the time of the
  // positions it is next evaluated at, set with them (MechanicalSystem). Others ignore it.
  virtual void set_time(double /*t*/) {}
  /// Whether the section changes in time (its strain energy then changes at fixed positions:
  /// work done on the model that the energy account books).
  virtual bool changes_in_time() const { return false; }

  /// Doubles of history held (0: the law keeps none).
  virtual size_t history_size() const { return 0; }
  /// Doubles of history per element, held or not (the same on every process; 0: none):
  /// history_size() is this times the held elements, saved in ascending element order.
  virtual size_t history_per_element() const { return 0; }
  /// Advances each held point's history to the positions x of an accepted step.
  virtual void commit_history(const NodePositions& /*x*/) {}
  /// The held history, appended to `out`; and read back from `in` at `at` (returns the position
  /// after it; std::invalid_argument when it does not fit).
  virtual void save_history(std::vector<double>& /*out*/) const {}
  virtual size_t restore_history(const std::vector<double>& /*in*/, size_t at) { return at; }
  /// The section's prestress in the sheet axes [s11, s22, s12] (membranes; zero for cables):
  /// form finding names a warp ≠ fill one when it finds no equilibrium shape.
  virtual Vec3 sheet_prestress() const { return Vec3::Zero(); }
  /// The section's law's stiffness at zero strain in the sheet axes (Voigt, engineering shear;
  /// membranes; zero for cables): cutting patterns flatten a panel for its own law.
  virtual Mat3 sheet_stiffness() const { return Mat3::Zero(); }

  /// Keeps the section data (integration points, reference geometry) of the listed elements
  /// only (ascending), freeing the others': under mpirun a process computes its own elements
  /// only (docs/parallel.md). Afterwards only the listed elements may be asked for anything
  /// but their nodes; on_reference builds the listed ones only.
  virtual void keep_only(std::span<const int> elements) = 0;
  /// Whether element e's section data is held (every element until keep_only).
  bool holds(int e) const { return slot_.empty() || slot_[static_cast<size_t>(e)] >= 0; }
  /// On a process's piece of a shared model (share_model): keep_only(elements), then those
  /// elements' nodes renumbered through `local_of` (a node of the whole model -> the piece's);
  /// the other elements keep their index but no nodes (-1): only the listed ones may be asked
  /// for anything afterwards.
  void keep_piece(std::span<const int> elements, const std::vector<int>& local_of);
  /// A block built from the listed elements only (a part read: docs/parallel.md), their
  /// section data at 0, 1, ..., spread to the whole block's `total` elements: the listed ones
  /// (ascending) at their index there, the others without nodes (-1) or data, as keep_piece
  /// leaves a piece's block.
  void spread(int total, std::span<const int> elements);

 protected:
  ElementBlock(const shape::ShapeInfo& shape, std::string set_name, std::vector<int> connectivity,
               double density)
      : shape_(&shape),
        set_name_(std::move(set_name)),
        connectivity_(std::move(connectivity)),
        density_(density) {}
  /// Where element e's section data is stored (e itself until keep_only).
  int slot(int e) const {
    assert(holds(e) && "an element whose section data this process does not hold");
    return slot_.empty() ? e : slot_[static_cast<size_t>(e)];
  }
  /// The entries of per-element `data` (indexed by slot) of `elements`, in their order: a
  /// block's keep_only stores these, then calls set_kept.
  template <class Vector>
  Vector kept(const Vector& data, std::span<const int> elements) const {
    Vector out;
    out.reserve(elements.size());
    for (int e : elements) out.push_back(data[static_cast<size_t>(slot(e))]);
    return out;
  }
  /// on_reference's work: the block set up on X with `connectivity` (every element's, or the
  /// held ones' only); `listed`, when not empty, numbers those elements in this block (for
  /// messages).
  virtual std::unique_ptr<ElementBlock> rebuilt(std::vector<int> connectivity,
                                                const NodePositions& X, double stabilizer,
                                                std::span<const int> listed) const = 0;
  /// Element number (1-based, in this block) of the i-th set up of a `listed` list.
  static int element_number(int i, std::span<const int> listed) {
    return 1 + (listed.empty() ? i : listed[static_cast<size_t>(i)]);
  }
  /// Records that the section data of `elements` (ascending) now sits at 0, 1, ...
  void set_kept(std::span<const int> elements) {
    slot_.assign(static_cast<size_t>(size()), -1);
    for (size_t i = 0; i < elements.size(); ++i)
      slot_[static_cast<size_t>(elements[i])] = static_cast<int>(i);
  }

 private:
  const shape::ShapeInfo* shape_;  // a row of kShapeTable (static storage)
  std::string set_name_;
  std::vector<int> connectivity_;
  double density_;
  std::vector<int> slot_;  // element -> its section data (-1: not held); empty: itself
};

/// The surface capability: loads on the surface and points located on it (membranes).
class SurfaceBlock : public ElementBlock {
 public:
  const SurfaceBlock* surface() const final { return this; }
  /// True when the law is a tension field (wrinkling): outputs carry its state.
  virtual bool tension_field() const { return false; }
  /// True when the law changes the thickness (outputs carry the current thickness).
  virtual bool thins() const { return false; }
  /// True when the law yields (outputs carry the equivalent plastic strain).
  virtual bool yields() const { return false; }
  /// Follower pressure forces and (when K non-null) load stiffness df/dx.
  virtual void pressure(std::span<const int> elements, const NodePositions& x, double p, double* f,
                        double* K) const = 0;
  /// internal() and pressure() of the same elements in one pass, for blocks whose kernels
  /// share work between them (a membrane's points serve both).
  virtual void internal_and_pressure(std::span<const int> elements, const NodePositions& x,
                                     double p, double* r, double* K, double* f, double* Kp) const {
    internal(elements, x, r, K);
    pressure(elements, x, p, f, Kp);
  }
  /// internal_and_pressure() without tangents for an explicit step, each element's forces
  /// added straight into the node arrays: its internal forces into F, the follower pressure
  /// p's into Fp (p == 0: none, Fp untouched). No two of `elements` may share a node with an
  /// element another thread runs at the same time (a colour of the assembly). A block may take
  /// its own fast path here, which may differ from the implicit passes' forces at round-off
  /// (the implicit results stay those of internal_and_pressure).
  virtual void explicit_forces(std::span<const int> elements, const NodePositions& x, double p,
                               NodePositions& F, NodePositions& Fp) const = 0;
  /// Pressure p along the fixed unit direction d, per area projected normal to d
  /// (`projected`) or per current area, and (when K non-null) its load stiffness.
  virtual void directed_pressure(std::span<const int> elements, const NodePositions& x, double p,
                                 const Vec3& d, bool projected, double* f, double* K) const = 0;
  /// Natural coordinates of the reference point P inside element e, if it lies there (used to
  /// locate history points). Returns false otherwise.
  virtual bool locate(int e, const Vec3& P, std::array<double, 2>& xi) const = 0;
  /// Output at natural coordinates xi of element e.
  virtual MembraneStress output_at(int e, const std::array<double, 2>& xi,
                                   const NodePositions& x) const = 0;

 protected:
  using ElementBlock::ElementBlock;
};

/// The sliding capability (docs/cables.md): the material of a chain slips through its
/// interior nodes.
class SlidingChains {
 public:
  /// Reference (unreefed) length of material that has moved through interior node j (1 .. k−2,
  /// its place in the chain) of chain e at positions x, from the segment before it into the
  /// one after it (negative: the other way), since the reference state.
  virtual double slip(int e, int j, const NodePositions& x) const = 0;

 protected:
  ~SlidingChains() = default;
};

/// Diagnostics of a block's set-up: the worst element found, for validation messages.
struct BlockSetupReport {
  int worst_element = -1;  ///< element with the smallest Jacobian / length
  double worst_jacobian = 0;
  int poor_axes_element = -1;  ///< element where the projected m1 is shortest
  double poor_axes_quality = 1;
};

/// Membrane block of the surface shape named `type` (shape_info.hpp). `axes` are the sector axes,
/// or null for the default (global x projected). Throws std::invalid_argument for an unknown
/// type or a nodal integration the shape has no rule for; `report` receives degenerate
/// elements (the caller decides how to complain).
std::unique_ptr<ElementBlock> make_membrane_block(
    std::string_view type, std::string set_name, std::vector<int> connectivity,
    const NodePositions& X, const SheetLaw& law, double density, double thickness,
    const SheetAxes* axes, shape::Integration integration, BlockSetupReport& report);

/// Cable block of the line shape named `type` (cable2, cable3).
std::unique_ptr<ElementBlock> make_cable_block(std::string_view type, std::string set_name,
                                               std::vector<int> connectivity,
                                               const NodePositions& X, const CableLaw& law,
                                               double density, double area,
                                               shape::Integration integration,
                                               BlockSetupReport& report);

/// What a sliding cable's section adds to its law: Coulomb friction at the interior nodes (the
/// capstan ratio e^(μθ)), a reefing factor in time (the line's material length over its
/// reference length, > 0) and the time the line is cut (no force from then on).
struct SlidingCableSection {
  double friction = 0;
  std::optional<TimeFunction> reefing;
  double cut_time = std::numeric_limits<double>::infinity();
};

/// Sliding cable block (docs/cables.md): each element one chain of `chain_nodes` nodes (>= 3)
/// whose material slides over its interior nodes. Throws std::invalid_argument for fewer nodes.
std::unique_ptr<ElementBlock> make_sliding_cable_block(std::string set_name, int chain_nodes,
                                                       std::vector<int> connectivity,
                                                       const NodePositions& X, const CableLaw& law,
                                                       double density, double area,
                                                       BlockSetupReport& report,
                                                       const SlidingCableSection& section = {});

}  // namespace velum
