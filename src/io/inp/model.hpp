// What a deck describes, as read from its keyword blocks: the mesh (mesh.cpp), the materials,
// sections and orientations (properties.cpp), and the step with its boundary conditions, loads
// and amplitudes (step.cpp). yaml_writer.cpp turns it into a Velum model.
#pragma once

#include <map>
#include <optional>
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

struct Step {
  bool present = false;
  bool dynamic = false;
  double initial = 1, period = 1, min_inc = 0, max_inc = 0;
  bool direct = false;       ///< fixed increments
  double alpha = -0.05;      ///< HHT (Abaqus sign: -1/3 ... 0)
  bool ramp_default = true;  ///< loads without an amplitude: ramp (static) or step (dynamic)
  int file = 0, line = 0;
  std::map<std::pair<long, int>, Constraint> constraints;  ///< (node, component 0-2)
  std::map<std::pair<long, int>, NodeLoad> loads;
  std::vector<Pressure> pressures;
  std::vector<Gravity> gravity;
  std::map<std::string, Amplitude> amplitudes;  ///< by canonical name
};

/// Reads *BOUNDARY (model data and step), *AMPLITUDE, *SURFACE, *STEP with *STATIC or
/// *DYNAMIC, *CLOAD, *DLOAD, *DSLOAD and *END STEP.
Step read_step(const std::vector<Keyword>& keywords, const Mesh& mesh, std::vector<bool>& used,
               Diagnostics& diag);

/// Reports every keyword not marked used: a warning for those that cannot change the answer
/// (output requests, *HEADING), an error for the others.
void report_unread(const std::vector<Keyword>& keywords, const std::vector<bool>& used,
                   Diagnostics& diag, const std::string& why);

/// The Velum model as YAML text.
std::string write_yaml(const std::string& title, const Mesh& mesh, const Properties& props,
                       const Step& step, Diagnostics& diag);

}  // namespace velum::io::inp
