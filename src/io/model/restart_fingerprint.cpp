#include "restart_fingerprint.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <cstring>

#include "velum/model/element_block.hpp"

namespace velum::io::model_file {
namespace {

/// FNV-1a over raw values: the same model gives the same number on every machine that runs it.
class Sum {
 public:
  template <class T>
  void add(const T& x) {
    unsigned char b[sizeof x];
    std::memcpy(b, &x, sizeof x);
    for (unsigned char c : b) h_ = (h_ ^ c) * 1099511628211ull;
  }
  template <class V>
  void all(const V& v) {
    add(v.size());
    for (const auto& x : v) add(x);
  }
  std::string hex() const { return fmt::format("{:016x}", h_); }

 private:
  std::uint64_t h_ = 14695981039346656037ull;
};

/// Every mapping and list below `n` written on one line (a node keeps the style it was read in).
void flow(YAML::Node n) {
  if (!n.IsMap() && !n.IsSequence()) return;
  n.SetStyle(YAML::EmitterStyle::Flow);
  if (n.IsSequence())
    for (YAML::Node c : n) flow(c);
  else
    for (auto kv : n) flow(kv.second);
}

/// A section as read, without comments or layout; time.end left out of analyses (a longer run
/// continues a finished one).
std::string section(const YAML::Node& root, const char* key) {
  if (!root.IsMap() || !root[key]) return fmt::format("[{}]\n(none)\n", key);
  YAML::Node s = YAML::Clone(root[key]);
  const auto drop_end = [](YAML::Node a) {
    if (a.IsMap() && a["time"] && a["time"].IsMap()) a["time"].remove("end");
  };
  if (std::strcmp(key, "analysis") == 0) drop_end(s);
  if (std::strcmp(key, "steps") == 0 && s.IsSequence())
    for (YAML::Node st : s)
      if (st.IsMap() && st["analysis"]) drop_end(st["analysis"]);
  std::string f = fmt::format("[{}]\n", key);
  const auto line = [&f](const YAML::Node& n) {
    flow(n);
    YAML::Emitter e;
    e << n;
    f += e.c_str() + std::string("\n");
  };
  if (s.IsSequence())
    for (const YAML::Node& item : s) line(item);
  else if (s.IsMap())
    for (const auto& kv : s) {
      YAML::Node one(YAML::NodeType::Map);
      one[kv.first] = kv.second;
      line(one);
    }
  else
    line(s);
  return f;
}

}  // namespace

std::string restart_fingerprint(const YAML::Node& root, const Model& m) {
  std::string f;
  for (const char* key :
       {"analysis", "steps", "boundary", "loads", "functions", "masses", "contact", "rigid_bodies"})
    f += section(root, key);
  Sum nodes;
  nodes.all(m.node_ids);
  for (Eigen::Index i = 0; i < m.X.size(); ++i) nodes.add(m.X.data()[i]);
  for (Eigen::Index i = 0; i < m.U0.size(); ++i) nodes.add(m.U0.data()[i]);
  f += fmt::format("[mesh]\nnode coordinates: {} nodes, checksum {}\n", m.num_nodes(), nodes.hex());
  for (const auto& b : m.blocks) {
    Sum e;
    e.all(b->connectivity());
    f += fmt::format("elements of {}: {}, checksum {}\n", b->set_name(), b->size(), e.hex());
  }
  Sum supports;
  for (const FixedDofs& d : m.fixed) supports.all(d.nodes), supports.add(d.fix);
  for (const SymmetryPlane& s : m.symmetry) supports.all(s.nodes), supports.add(s.normal);
  for (const PrescribedMotion& p : m.prescribed)
    supports.all(p.nodes), supports.add(p.displacement), supports.add(p.function);
  f += fmt::format("fixed, symmetric and prescribed nodes: checksum {}\n", supports.hex());
  return f;
}

}  // namespace velum::io::model_file
