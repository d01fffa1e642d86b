// What a deck describes, as read from its keyword blocks: the mesh (mesh.cpp), the materials,
// sections and orientations (properties.cpp), and the step with its boundary conditions, loads
// and amplitudes (step.cpp). yaml_writer.cpp turns it into a Velum model.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "deck.hpp"
#include "velum/io/mesh_data.hpp"

namespace velum::io::inp {

struct Element {
  long id = 0;
  std::string type;         ///< Velum's: tri3 tri6 quad4 quad8 quad9 cable2 cable3
  std::vector<long> nodes;  ///< in Velum's (Gmsh's) node order
  int file = 0, line = 0;
};

/// A node set or element set: ids in the order first given, each once.
struct Set {
  std::string name;  ///< as spelled where defined
  std::vector<long> ids;
  int file = 0, line = 0;
};

struct Mesh {
  std::vector<MeshNode> nodes;
  std::map<long, size_t> node_at;
  std::vector<Element> elements;
  std::map<long, size_t> element_at;
  std::vector<Set> nsets, elsets;
  std::map<std::string, size_t> nset_at, elset_at;  ///< by canonical name
  /// The elements of *ELEMENT blocks without ELSET=, in order.
  std::vector<long> unnamed_elements;

  const Set* nset(const std::string& name) const;
  const Set* elset(const std::string& name) const;
};

/// Reads *NODE, *ELEMENT, *NSET and *ELSET blocks; `used[i]` is set for each block read.
Mesh read_mesh(const std::vector<Keyword>& keywords, std::vector<bool>& used, Diagnostics& diag);

struct Material {
  std::string name;
  int file = 0, line = 0;
  enum class Law { kNone, kIsotropic, kOrthotropic, kMatrix } law = Law::kNone;
  double E = 0, nu = 0;                      ///< isotropic
  double E1 = 0, E2 = 0, nu12 = 0, G12 = 0;  ///< orthotropic (plane stress)
  Mat3 Q = Mat3::Zero();                     ///< matrix: plane-stress stiffness, engineering Voigt
  std::optional<double> density;
  bool no_compression = false;
  std::string elastic_type;  ///< as given on *ELASTIC, for messages
  int elastic_line = 0;
};

struct Orientation {
  std::string name;
  int file = 0, line = 0;
  bool by_nodes = false;
  Vec3 a = Vec3::UnitX(), b = Vec3::UnitY(), c = Vec3::Zero();  ///< points (or node ids)
  long na = 0, nb = 0, nc = 0;
  double angle = 0;  ///< additional rotation about the sheet normal, degrees
};

struct Section {
  bool membrane = true;
  std::string elset, material, orientation;  ///< canonical names
  double size = 1;                           ///< thickness or area
  int file = 0, line = 0;
};

/// Reads *MATERIAL (with *ELASTIC, *DENSITY, *NO COMPRESSION), *ORIENTATION, *MEMBRANE
/// SECTION and *SOLID SECTION.
struct Properties {
  std::vector<Material> materials;
  std::map<std::string, size_t> material_at;
  std::vector<Orientation> orientations;
  std::map<std::string, size_t> orientation_at;
  std::vector<Section> sections;
};
Properties read_properties(const std::vector<Keyword>& keywords, std::vector<bool>& used,
                           Diagnostics& diag);

/// A time function: an *AMPLITUDE table, or the step's default ramp.
struct Amplitude {
  std::string name;
  std::vector<std::pair<double, double>> points;
  bool total_time = false;  ///< TIME=TOTAL TIME (else step time)
  /// Its value at time t (the first and last values held outside the table).
  double at(double t) const;
};

/// One node's motion in one component: fixed, or prescribed (value times an amplitude).
struct Constraint {
  bool prescribed = false;
  double value = 0;
  std::string amplitude;  ///< "" : the step's default
  std::string where;      ///< "file:line" of the data line, for messages
};

struct NodeLoad {  ///< *CLOAD, per node and component (the last line given wins)
  double value = 0;
  std::string amplitude;
  std::string where;
};

struct Pressure {  ///< on the elements of one set, Velum's sign (along g1 x g2)
  std::vector<long> elements;
  double value = 0;
  std::string amplitude;
  std::string where;
};

struct Gravity {
  Vec3 acceleration = Vec3::Zero();
  std::string amplitude;
  std::string where;
};

/// A history column from an output request (*NODE PRINT, *NODE OUTPUT under *OUTPUT,
/// HISTORY, *ENERGY OUTPUT): a quantity of the model file's output.history.
struct HistoryColumn {
  std::string name;      ///< the column, e.g. U2_N3, RF1_LEFT, ALLKE
  std::string quantity;  ///< displacement, velocity, position, reaction, kinetic_energy, ...
  long node = 0;         ///< displacement, velocity, position
  std::string set;       ///< reaction: the node set (summed over it) ...
  long set_node = 0;     ///< ... or one node
  int component = -1;    ///< 0-2; -1: none
  std::string where;
};

struct Step {
  bool present = false;
  bool dynamic = false;
  double initial = 1, period = 1, min_inc = 0, max_inc = 0;
  bool direct = false;       ///< fixed increments
  double alpha = -0.05;      ///< HHT (Abaqus sign: -1/3 ... 0)
  bool ramp_default = true;  ///< loads without an amplitude: ramp (static) or step (dynamic)
  /// *STATIC, RIKS: arc length (analysis.path), the loads scaled by the load proportionality
  /// factor up to `max_lpf` (the loads as given: 1), at most `max_steps` increments (INC=).
  bool riks = false;
  double max_lpf = 1;
  long max_steps = 0;  ///< 0: Velum's default
  std::string name;    ///< NAME= of the *STEP
  /// OP=NEW: the step removes what the steps before it applied (boundary conditions, point
  /// loads, distributed loads, surface loads) before its own.
  bool new_boundary = false, new_cloads = false, new_dloads = false, new_dsloads = false;
  int file = 0, line = 0;
  std::map<std::pair<long, int>, Constraint> constraints;  ///< (node, component 0-2)
  std::map<std::pair<long, int>, NodeLoad> loads;
  std::vector<std::pair<std::pair<long, int>, NodeLoad>> held_loads;  ///< complete_steps
  std::vector<Pressure> pressures;
  std::vector<Gravity> gravity;
  std::map<std::string, Amplitude> amplitudes;  ///< by canonical name
  std::vector<HistoryColumn> history;           ///< from the output requests
  /// *INITIAL CONDITIONS, TYPE=STRESS: per element id, [S11, S22, S12] in the material axes
  /// (a truss: S11 only), the sections' prestress.
  std::map<long, Vec3> initial_stress;
};

/// Reads *BOUNDARY (model data and step), *AMPLITUDE, *SURFACE, *STEP with *STATIC or
/// *DYNAMIC, *CLOAD, *DLOAD, *DSLOAD and *END STEP, the output requests and *INITIAL
/// CONDITIONS: one Step per *STEP, each with what it gives itself (the first also the model
/// data's boundary conditions, the initial stress and every step's output requests; the last
/// every amplitude).
std::vector<Step> read_step(const std::vector<Keyword>& keywords, const Mesh& mesh,
                            std::vector<bool>& used, Diagnostics& diag);

/// Steps 2, 3, ... of a deck as complete steps of a Velum `steps:` list (Abaqus's propagation:
/// what a step does not redefine is held at its value at the end of the step before; a load
/// redefined under a ramp goes on from that value). Held items get the amplitude "=held"
/// (constant); a point load held beside its redefinition is in `held_loads`.
std::vector<Step> complete_steps(const std::vector<Step>& steps, Diagnostics& diag);

/// The output requests (*OUTPUT, *NODE PRINT, *NODE OUTPUT, *ENERGY OUTPUT) of every step as
/// the run's history columns, each once (output_requests.cpp).
class OutputRequests {
 public:
  OutputRequests(const Mesh& mesh, Diagnostics& diag) : mesh_(mesh), diag_(diag) {}
  /// Reads `k` when it is an output request (true), else false.
  bool read(const Keyword& k);
  std::vector<HistoryColumn> columns;

 private:
  static constexpr size_t kMaxNodeColumns = 50;  ///< per request: the first nodes of a set
  void output(const Keyword& k);
  void node_output(const Keyword& k);
  void energy_output(const Keyword& k);
  void column(HistoryColumn c);
  const Mesh& mesh_;
  Diagnostics& diag_;
  bool field_output_ = false;
  std::set<std::string> names_;
};

/// Reports every keyword not marked used: a warning for those that cannot change the answer
/// (output requests, *HEADING), an error for the others.
void report_unread(const std::vector<Keyword>& keywords, const std::vector<bool>& used,
                   Diagnostics& diag, const std::string& why);

/// The Velum model as YAML text.
std::string write_yaml(const std::string& title, const Mesh& mesh, const Properties& props,
                       const std::vector<Step>& steps, Diagnostics& diag);

}  // namespace velum::io::inp
