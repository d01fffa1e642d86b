// Reads a model file (YAML, docs/model-format.md) into a Model, its analysis
// settings and its output settings. Every problem found is reported with the file, the
// 1-based line and the key path; all problems of a file are collected into one InputError.
// Node and element ids are the user's; units are the user's and never converted. A model may
// also come as YAML text, or as a YAML node built in memory (model_reader_yaml.hpp, for the
// Python module): its messages then name the key without a line.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include "velum/analysis/analysis.hpp"
#include "velum/analysis/stages.hpp"
#include "velum/model/model.hpp"

namespace velum::io {

/// One column of history.csv.
struct HistoryEntry {
  enum class Quantity {
    kDisplacement,
    kVelocity,
    kPosition,
    kReaction,
    kFiberAngleChange,
    kStress,
    kKineticEnergy,
    kStrainEnergy,
    kExternalWork,
    kGasVolume,
    kGasPressure,
    kGasTemperature,
    kGasMass,
    kGasMassFlow,
    kContactForce,
    kRigidPosition,
    kRigidVelocity,
    kForce,                ///< a cable element's axial force (cable2, cable3, sliding_cable)
    kSlip,                 ///< a sliding cable's material slip through an interior node
    kContactArea,          ///< the area in contact of a contact entry (or the contacts with a body)
    kRigidRotation,        ///< a rigid body's rotation vector (magnitude: its angle)
    kRigidAngularVelocity  ///< a rigid body's angular velocity (global axes)
  };
  std::string name;
  Quantity quantity = Quantity::kDisplacement;
  int node = -1;  ///< displacement, velocity, position: node index (renumbered on MPI pieces)
  /// slip: the interior node's place in its chain, 1 .. k − 2 (not a node index: it stays as
  /// it is when the model is cut into MPI pieces)
  int chain_place = -1;
  std::vector<int> nodes;          ///< reaction: node indices
  int component = 0;               ///< x y z: 0 1 2; stress: kStressComponents index
  Vec3 point = Vec3::Zero();       ///< fiber_angle_change, stress: reference point
  int block = -1, element = -1;    ///< where the point lies
  std::array<double, 2> xi{0, 0};  ///< natural coordinates of the point there
  bool degrees = true;             ///< fiber_angle_change unit
  int load = -1;                   ///< gas_*: index into Model::gases
  std::string flow;                ///< gas_mass_flow: "vent:0" (inflator, vent, leakage, orifice);
                     ///< contact_force, contact_area, rigid_*: the loads' quantity name
};

/// Components of the `stress` history quantity, in order.
inline constexpr std::array<const char*, 5> kStressComponents = {"max_principal", "min_principal",
                                                                 "s11", "s22", "s12"};

struct OutputSettings {
  std::filesystem::path directory = "out";  ///< relative paths: to the working directory
  double interval = 0;                      ///< simulated time between outputs; 0: each step
  bool fields = true;                       ///< ParaView frames
  std::vector<HistoryEntry> history;
  int checkpoint_steps = 0;        ///< > 0: DIR/checkpoint.bin every so many accepted steps
  double checkpoint_interval = 0;  ///< > 0: ... at the first step past each multiple of it
};

struct MaterialSummary {
  std::string name, type;
};

/// Everything a model file describes.
/// `patterns:` (velum pattern, docs/patterns.md): the element sets flattened into panels and
/// the warp and fill compensation (the strains each flat panel is shrunk by).
struct PatternSettings {
  std::vector<std::string> panels;
  double warp = 0, fill = 0;
  double seam_allowance = 0;  ///< the cut line's offset outside the seam line (length)
  /// `seams:` (velum seams): lines that cut the surface into the panels (then named by
  /// `panels`, or panel_1, panel_2, ...).
  struct Seam {
    std::string where;  ///< "file:line: patterns.seams[i]", for messages
    bool path = false;  ///< `nodes:`: along these nodes as they are; else a geodesic via points
    std::vector<int> nodes;    ///< per point its node index, or -1 for a point by coordinates
    std::vector<Vec3> points;  ///< per point its coordinates (a node's where nodes[k] >= 0)
  };
  std::vector<Seam> seams;
  std::string panels_where;   ///< "file:line: patterns.panels" (or "file: patterns"), for messages
  double seam_tolerance = 0;  ///< how far a seam's point may lie off the shape; 0: automatic
  /// A crossing within this fraction of its edge from a corner goes through the corner (moved
  /// onto the seam where it may); 0: every crossing splits its triangles.
  double seam_snap = 0.45;
};

struct ModelInput {
  std::filesystem::path file;
  std::string title;
  Model model;
  AnalysisSettings analysis;
  OutputSettings output;
  std::vector<MaterialSummary> materials;
  std::vector<std::vector<long>> element_ids;  ///< per block of model.blocks: the user's ids
  std::vector<std::string> block_materials;    ///< per block: the name of its section's material
  std::vector<std::string> warnings;           ///< "file:line: key: text", not fatal
  std::string yaml;            ///< the model's YAML text (DIR/form.yaml is written from it)
  std::string materials_yaml;  ///< `materials` and `sections` as read (a restart must match them)
  /// The rest a restart must match: analysis (but time.end), loads, boundary, ... as read, and
  /// checksums of the node coordinates, elements and supported nodes (restart_fingerprint.hpp)
  std::string restart_yaml;
  std::filesystem::path base_dir;  ///< what relative paths in it start from
  /// A staged model's steps, in order (model, analysis and output above are the first
  /// step's); empty for a model without `steps:`.
  std::vector<AnalysisStep> steps;
  PatternSettings patterns;  ///< empty panels: no `patterns:`
  /// The node sets by name (mesh file's and inline, boxes found), as node indices.
  std::map<std::string, std::vector<int>> node_sets;
  /// A model read in parts (mesh.parts): each node id the file names, in the order read (the
  /// same on every process), whether this process's part holds it, and the message for an id
  /// that no part holds; the run checks them over the processes (each knows its part only).
  struct NamedId {
    bool here = false;
    std::string missing;
  };
  std::vector<NamedId> part_ids;
};

// Limits beyond which a model is refused as bad input (docs/model-format.md, "Limits"): each
// is far above what a sensible model asks and far below what would hang or exhaust a machine.
inline constexpr std::uintmax_t kMaxModelFileBytes = 256u << 20;  ///< the YAML file itself
inline constexpr long kMaxNewtonIterations = 1000;  ///< analysis.newton.max_iterations
inline constexpr double kMaxSteps = 1e7;            ///< time.end / time.step
inline constexpr double kMaxOutputTimes = 1e6;      ///< time.end / output.interval: history rows
inline constexpr double kMaxFrames = 1e4;           ///< ... with fields on: ParaView frames
inline constexpr size_t kMaxHistoryNameBytes = 64;  ///< a history column name
inline constexpr size_t kMaxSuggestionChars = 64;   ///< "did you mean": characters compared
inline constexpr int kMaxYamlDepth = 32;            ///< nesting of mappings and lists

/// Bad input: the list of "file:line: key: problem" messages, all of them.
class InputError : public std::runtime_error {
 public:
  explicit InputError(std::vector<std::string> messages);
  const std::vector<std::string>& messages() const { return messages_; }

 private:
  std::vector<std::string> messages_;
};

/// Reads and validates a model file. Throws InputError.
ModelInput read_model(const std::filesystem::path& file);

/// Where a model that is not a file comes from: the name its messages start with (instead of
/// the file's) and the directory relative mesh and output paths start from.
struct ModelSource {
  std::string name = "model";
  std::filesystem::path base_dir;  ///< empty: the working directory
};

/// Reads and validates a model given as YAML text. Throws InputError.
ModelInput read_model_text(const std::string& yaml, const ModelSource& source);

/// Levenshtein distance (for "did you mean" suggestions).
int edit_distance(std::string_view a, std::string_view b);

}  // namespace velum::io
