// The model-file reader: one member per part of the file. Its definitions are split by what
// they read: model_reader.cpp (the file as a whole and the final checks), read_mesh.cpp
// (nodes, elements, node sets), read_materials.cpp (materials; the sheet laws by name through
// sheet_law_table.cpp), read_sections.cpp (sections and the element blocks they make),
// read_loads.cpp (time functions, masses, boundary conditions, loads), read_gas.cpp (enclosed
// gas), read_analysis.cpp (analysis and output) and read_steps.cpp (analysis steps).
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "reader_context.hpp"
#include "velum/io/mesh_data.hpp"
#include "velum/io/mesh_part.hpp"
#include "velum/load/contact_load.hpp"

namespace velum::io::model_file {

struct MaterialDef {
  std::string type;
  bool cable = false;
  std::optional<SheetLaw> law;  ///< membranes: the material's law (sheet_law_table.hpp)
  CableLaw cable_law;
  double density = 0;
  bool ok = false;
  // What a section adds to the material (read_sections.cpp).
  bool wrinkling = false;
  double wrinkling_stiffness = SheetLaw::kDefaultSlackStiffness;  ///< κ of wrinkled/slack points
  Vec3 prestress = Vec3::Zero();  ///< membranes: 2nd PK [s11, s22, s12], sheet axes
  double cable_prestress = 0;     ///< cables: axial force
  SheetLaw sheet_law() const {
    SheetLaw s(*law);
    if (prestress.squaredNorm() > 0) s.with_prestress(prestress);
    if (wrinkling) s.with_wrinkling(wrinkling_stiffness);
    return s;
  }
};

struct ElementSet {
  std::vector<ElementGroup> groups;
  bool from_file = false;
  int dimension = 2;
  bool has_section = false;
};

class Reader : public ReaderContext {
 public:
  using ReaderContext::ReaderContext;

  /// The model in a file, in YAML text, or as a YAML node. Throw InputError.
  ModelInput read_file(const std::filesystem::path& file);
  ModelInput read_text(const std::string& yaml);
  ModelInput read(const Node& root);

 private:
  // model_reader.cpp
  /// A model without steps (or one step's model, which read_steps puts together).
  ModelInput read_one(const Node& root);
  void parse(const Node& root);

  // read_steps.cpp: a model with `steps:`, read once per step.
  ModelInput read_steps(const Node& root);
  void final_checks(const Node& root);
  void check_form_prestress(const Node& root);

  // read_mesh.cpp
  void add_node(long id, const Vec3& x, const Node& at, const std::string& path);
  void parse_mesh(const Node& mesh);
  void parse_reference_positions(const Node& ps);
  /// A row [id, x, y, z] of a node list at `p` (mesh.nodes, positions, references); nullopt,
  /// the error reported, when it is not one.
  std::optional<std::pair<long, Vec3>> node_row(const Node& n, const std::string& p);
  // read_parts.cpp: mesh.parts, a model split by `velum partition` (io/mesh_part.hpp): this
  // process's part only, as nodes, element groups of its own elements and node sets cut to it.
  void parse_parts(const Node& mesh);
  /// Once the blocks are built (build_blocks spread them, part_own_): the piece
  /// (model.piece), the edge loads' edges and the nodes in no element, from the part.
  void finish_part();
  /// Where a history entry's point or element is (the split found it on the whole mesh).
  bool place_from_part(HistoryEntry& he, size_t index) const;
  std::unique_ptr<MeshPart> part_;          ///< the part read (mesh.parts), or null
  bool parts_given_ = false;                ///< mesh.parts given (read or not: ids are not checked)
  size_t step_ = 0;                         ///< the analysis step read (its numbering in the part)
  std::vector<std::vector<int>> part_own_;  ///< per block: its elements of this part
  /// Per element set: its groups' elements of this part and their whole count, in order.
  std::map<std::string, std::vector<std::pair<int, std::vector<int>>>> part_groups_;
  std::map<std::string, std::vector<int>> part_set_nodes_;  ///< element sets' nodes here
  // read_panel_references.cpp: stress-free flat panels per element set (a pattern's round trip)
  void parse_panel_references(const Node& list);
  /// X with the set's panel reference, or null when the set has none (reports missing nodes).
  std::optional<NodePositions> panel_reference_of(const std::string& set, const ElementSet& es,
                                                  const Node& at, const std::string& p);
  void parse_inline_elements(const Node& els, long max_file_id);
  /// Node indices from a node reference: an id, a list of ids, a set name or {box: [...]}.
  std::optional<std::vector<int>> node_list(const Node& n, const std::string& path,
                                            bool allow_names);
  std::optional<std::vector<int>> nodes_of(const Node& map, const char* key,
                                           const std::string& path);

  // read_patterns.cpp
  void parse_patterns(const Node& p);
  void parse_seams(const Node& p);

  // read_materials.cpp
  void parse_materials(const Node& ms);

  // read_sections.cpp
  void parse_sections(const Node& ss);
  std::optional<SheetAxes> parse_axes(const Node& a, const std::string& p);
  bool read_element_nodes(const Node& c, const std::string& ckp, long eid,
                          std::vector<long>& nodes);
  void parse_sliding_cables(const Node& e, const std::string& set, const std::string& p,
                            long& next_id);
  void build_blocks(const std::string& set, const ElementSet& es, const MaterialDef& md,
                    double size, const SheetAxes* axes, shape::Integration integration,
                    const Node& at, const std::string& p,
                    const SlidingCableSection& sliding_section = {});
  // read_sliding.cpp: a sliding_cable section's friction, reefing and cut_time.
  std::optional<SlidingCableSection> parse_sliding_section(const Node& s, const std::string& p,
                                                           const ElementSet& es,
                                                           const MaterialDef& md);

  // read_loads.cpp
  void parse_functions(const Node& fs);
  /// Index of a function named in map[key]; -1 (constant 1) when absent or "step".
  int function_ref(const Node& map, const std::string& path);
  void parse_masses(const Node& ms);
  void parse_boundary(const Node& bs);
  void parse_loads(const Node& ls);
  /// The load types' parsers by the name under `type:`, each adding its loads (add_load).
  using LoadParser = void (Reader::*)(const Node& load, const std::string& path);
  static const std::vector<std::pair<std::string, LoadParser>>& load_parsers();
  void parse_point_load(const Node& l, const std::string& path);
  void parse_edge_load(const Node& l, const std::string& path);
  void parse_pressure_load(const Node& l, const std::string& path);
  void parse_gravity_load(const Node& l, const std::string& path);
  /// Adds a load to the model; its set-up's errors point at `at` (`path`).
  void add_load(std::unique_ptr<Load> load, const Node& at, const std::string& path);
  /// Every load's set-up once the whole model is read (Load::set_up).
  void set_up_loads();

  // read_gas.cpp
  void parse_gas_load(const Node& l, const std::string& path);
  /// The membrane element sets of `elements` (one name or a list); nullopt when invalid.
  /// `walls`: the sets bound the chamber (each set may bound one); false: a subset of them
  /// (leakage).
  std::optional<std::vector<GasLoad::Part>> gas_parts(const Node& l, const std::string& path,
                                                      bool walls = true);
  /// The gas-flow keys (temperature, gas_constant, inflator, vents, leakage, orifices).
  bool parse_gas_flow(const Node& l, const std::string& path, GasLoad& gas);
  /// A time function by name (-1: step; -2: invalid, reported); inflator curves are kept for
  /// check_gas_flow.
  int gas_function(const Node& map, const char* key, const std::string& path, bool required);
  /// Once the analysis is read: orifices between known chambers, tables covering the run.
  void check_gas_flow();
  struct GasOrifice {
    Node at;
    std::string path;
    int self, other;
  };
  struct GasCurve {
    Node at;
    std::string path;
    int function;
  };
  std::vector<GasOrifice> gas_orifices_;
  std::vector<GasCurve> gas_curves_;
  /// The `load:` of a gas_volume or gas_pressure history entry; false when invalid.
  bool parse_gas_history(const Node& e, const std::string& path, HistoryEntry& he);

  // read_contact.cpp
  void parse_rigid_bodies(const Node& bs);
  // shape: mesh: its Gmsh file's triangles and quads into body.mesh, its point the centroid.
  bool read_rigid_mesh(const Node& b, const std::string& p, RigidBody& body);
  /// A free body's `inertia` (a number, principal values or a tensor); reported when bad.
  std::optional<Mat3> read_inertia(const Node& n, const std::string& p);
  void parse_contact(const Node& cs);
  /// The body (or contact index) and component of a contact_force, rigid_position or
  /// rigid_velocity history entry, into he.flow; false when invalid.
  bool parse_contact_history(const Node& e, const std::string& path, HistoryEntry& he);
  std::map<std::string, RigidBody> rigid_bodies_;
  std::set<std::string> contact_bodies_;
  int contact_count_ = 0;
  std::set<int> contact_augmented_;  ///< contacts that give `augmented`
  struct FreeBody {
    int node = -1;  ///< the node that carries it
    Node at;
    std::string path;
  };
  std::map<std::string, FreeBody> free_bodies_;
  /// Free bodies need inertia: refused in static, relaxation and form finding.
  void check_free_bodies();

  // read_analysis.cpp
  void parse_analysis(const Node& a);
  void parse_explicit_step(const Node& integrator, const std::string& path);
  void parse_path(const Node& pa);
  void parse_output(const Node& o, const Node& root);
  bool locate(HistoryEntry& he, size_t index) const;
  /// (`index`: the entry's place in the history, for a part read.)
  bool locate_cable(const Node& e, const std::string& p, HistoryEntry& he,
                    const char* quantity = "force", size_t index = SIZE_MAX);
  // read_sliding.cpp: `slip` (element: a sliding_cable's id, node: one of its interior nodes).
  bool parse_slip_history(const Node& e, const std::string& p, HistoryEntry& he);

  bool mesh_ok_ = false;
  bool wrinkles_ = false;  ///< some section wrinkles (a tension field): Newton's own default
  std::map<std::string, int> functions_;
  std::map<std::string, MaterialDef> materials_;
  std::map<std::string, ElementSet> element_sets_;
  std::map<std::string, std::vector<long>> file_node_sets_;
  std::map<std::string, std::vector<int>> node_sets_;
  std::map<std::string, std::vector<int>> set_blocks_;
  /// mesh.panel_references: per element set, node index -> its stress-free position there.
  std::map<std::string, std::map<int, Vec3>> panel_refs_;
  /// Each section's prestress as given (its node and path) with its least and greatest
  /// principal value (a cable's force twice): form finding needs tension.
  struct PrestressSite {
    Node at;
    std::string path;
    double least = 0, greatest = 0;
    bool membrane = true;
  };
  std::vector<PrestressSite> prestresses_;
  /// Element sets that bound a gas chamber: the gas load's path and line (one chamber each).
  std::map<std::string, std::string> gas_sets_;
  struct LoadAt {
    const Load* load;
    Node at;
    std::string path;
  };
  std::vector<LoadAt> load_sites_;
  std::set<long> element_ids_;
};

}  // namespace velum::io::model_file
