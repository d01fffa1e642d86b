// A part of a split model as a text file (io/mesh_part.hpp): keyword lines, then their
// numbers; names in double quotes (as std::quoted writes them).
#include "velum/io/mesh_part.hpp"

#include <fmt/format.h>

#include <charconv>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace velum::io {
namespace {

constexpr const char* kMagic = "velum-part";
constexpr int kVersion = 1;

// Words of the file, with the line each is on, for messages.
class Words {
 public:
  Words(std::string text, std::string name) : text_(std::move(text)), name_(std::move(name)) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw std::runtime_error(fmt::format("{}:{}: {}", name_, line_, what));
  }
  std::string_view word() {
    skip();
    if (at_ >= text_.size()) fail("the part ends early (a part of `velum partition`?)");
    const size_t from = at_;
    while (at_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[at_]))) ++at_;
    return std::string_view(text_).substr(from, at_ - from);
  }
  void expect(std::string_view key) {
    if (const auto w = word(); w != key)
      fail(fmt::format("expected '{}', found '{}': not a part of `velum partition`", key, w));
  }
  template <class T>
  T integer() {
    const auto w = word();
    T v{};
    const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
    if (ec != std::errc() || end != w.data() + w.size())
      fail(fmt::format("expected an integer, found '{}'", w));
    return v;
  }
  double number() {
    const auto w = word();
    double v = 0;
    const auto [end, ec] = std::from_chars(w.data(), w.data() + w.size(), v);
    if (ec != std::errc() || end != w.data() + w.size())
      fail(fmt::format("expected a number, found '{}'", w));
    return v;
  }
  size_t count(size_t most) {
    const long n = integer<long>();
    if (n < 0 || static_cast<size_t>(n) > most)
      fail(fmt::format("a count of {} is out of range", n));
    return static_cast<size_t>(n);
  }
  std::string quoted() {
    skip();
    std::istringstream in(text_.substr(at_, std::min<size_t>(text_.size() - at_, 4096)));
    std::string s;
    if (at_ >= text_.size() || text_[at_] != '"' || !(in >> std::quoted(s)))
      fail("expected a quoted name");
    at_ += static_cast<size_t>(in.tellg() < 0 ? static_cast<std::streamoff>(text_.size() - at_)
                                              : static_cast<std::streamoff>(in.tellg()));
    return s;
  }
  template <class T>
  std::vector<T> list(size_t most) {
    std::vector<T> out(count(most));
    for (T& v : out) v = integer<T>();
    return out;
  }

 private:
  void skip() {
    while (at_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[at_]))) {
      if (text_[at_] == '\n') ++line_;
      ++at_;
    }
  }
  std::string text_, name_;
  size_t at_ = 0;
  int line_ = 1;
};

template <class T>
void put_list(std::string& out, const char* key, const std::vector<T>& v) {
  out += fmt::format("{} {}", key, v.size());
  for (const T& x : v) out += fmt::format(" {}", x);
  out += '\n';
}

std::string quote(const std::string& s) {
  std::ostringstream o;
  o << std::quoted(s);
  return o.str();
}

}  // namespace

std::filesystem::path mesh_part_file(const std::filesystem::path& dir, int part) {
  return dir / fmt::format("part_{}.txt", part);
}

void write_mesh_part(const std::filesystem::path& file, const MeshPart& p) {
  std::string out;
  out += fmt::format("{} {}\npart {} {}\nglobal_nodes {}\nsize {:.17g}\nelement_cut {}\n", kMagic,
                     kVersion, p.part, p.parts, p.global_nodes, p.size, p.element_cut);
  out += fmt::format("nodes {}\n", p.node_id.size());
  for (size_t i = 0; i < p.node_id.size(); ++i) {
    const auto c = static_cast<Eigen::Index>(i);
    out += fmt::format("{} {} {:.17g} {:.17g} {:.17g} {}\n", p.node_id[i], p.global_node[i],
                       p.X(0, c), p.X(1, c), p.X(2, c), p.kept[i] ? 1 : 0);
  }
  put_list(out, "lone", p.lone);
  put_list(out, "bare", p.bare);
  put_list(out, "shared", p.shared);
  put_list(out, "neighbours", p.neighbours);
  for (const auto& w : p.shared_with) put_list(out, "shared_with", w);
  out += fmt::format("numberings {}\n", p.numberings.size());
  for (const auto& n : p.numberings) {
    out += fmt::format("numbering {} {} {}\n", n.global_equations, n.whole_nodes ? 1 : 0,
                       n.path_equation);
    for (size_t i = 0; i < n.equation.size(); i += 3)
      out += fmt::format("{} {} {}\n", n.equation[i], n.equation[i + 1], n.equation[i + 2]);
    out += fmt::format("edge_loads {}\n", n.edge_loads.size());
    for (const auto& edges : n.edge_loads) {
      out += fmt::format("edges {}", edges.size());
      for (const auto& e : edges) out += fmt::format(" {} {} {}", e.block, e.element, e.side);
      out += '\n';
    }
  }
  out += fmt::format("groups {}\n", p.groups.size());
  for (const auto& g : p.groups) {
    const size_t nn = g.own.empty() ? 0 : g.node_ids.size() / g.own.size();
    out += fmt::format("group {} {} {} {} {}\n", quote(g.set), g.type, g.whole, g.own.size(), nn);
    for (size_t k = 0; k < g.own.size(); ++k) {
      out += fmt::format("{} {}", g.own[k], g.ids[k]);
      for (size_t j = 0; j < nn; ++j) out += fmt::format(" {}", g.node_ids[k * nn + j]);
      out += '\n';
    }
  }
  for (const auto* sets : {&p.node_sets, &p.element_set_nodes}) {
    out += fmt::format("{} {}\n", sets == &p.node_sets ? "node_sets" : "element_set_nodes",
                       sets->size());
    for (const auto& [name, ids] : *sets) {
      out += fmt::format("set {} ", quote(name));
      put_list(out, "ids", ids);
    }
  }
  out += fmt::format("history {}\n", p.history.size());
  for (const auto& h : p.history)
    out += fmt::format("place {} {} {:.17g} {:.17g}\n", h.block, h.element, h.xi[0], h.xi[1]);
  out += fmt::format("points {}\n", p.points.size());
  for (const auto& [id, x] : p.points)
    out += fmt::format("point {} {:.17g} {:.17g} {:.17g}\n", id, x.x(), x.y(), x.z());
  out += "end\n";
  std::ofstream f(file, std::ios::binary | std::ios::trunc);
  f << out;
  f.close();
  if (!f) throw std::runtime_error(fmt::format("{}: cannot write the part", file.string()));
}

MeshPart read_mesh_part(const std::filesystem::path& file) {
  std::ifstream f(file, std::ios::binary);
  if (!f) throw std::runtime_error(fmt::format("{}: cannot open the part", file.string()));
  Words w(std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()),
          file.string());
  MeshPart p;
  w.expect(kMagic);
  if (const int v = w.integer<int>(); v != kVersion)
    w.fail(fmt::format("a part of version {}; this velum reads version {}", v, kVersion));
  constexpr size_t kMost = 1UL << 34;
  w.expect("part");
  p.part = w.integer<int>();
  p.parts = w.integer<int>();
  if (p.parts < 1 || p.part < 0 || p.part >= p.parts) w.fail("the part number is out of range");
  w.expect("global_nodes");
  p.global_nodes = w.integer<int>();
  w.expect("size");
  p.size = w.number();
  w.expect("element_cut");
  p.element_cut = w.integer<long>();
  w.expect("nodes");
  const size_t n = w.count(kMost);
  p.node_id.resize(n);
  p.global_node.resize(n);
  p.kept.resize(n);
  p.X.resize(3, static_cast<Eigen::Index>(n));
  for (size_t i = 0; i < n; ++i) {
    p.node_id[i] = w.integer<long>();
    p.global_node[i] = w.integer<int>();
    if (p.global_node[i] < 0 || p.global_node[i] >= p.global_nodes ||
        (i > 0 && p.global_node[i] <= p.global_node[i - 1]))
      w.fail("the nodes' global indices are not ascending within the model");
    for (int c = 0; c < 3; ++c) p.X(c, static_cast<Eigen::Index>(i)) = w.number();
    p.kept[i] = static_cast<char>(w.integer<int>() != 0);
  }
  auto local_list = [&](const char* key) {
    w.expect(key);
    auto v = w.list<int>(n);
    for (int l : v)
      if (l < 0 || static_cast<size_t>(l) >= n) w.fail(fmt::format("{}: no node {} here", key, l));
    return v;
  };
  p.lone = local_list("lone");
  p.bare = local_list("bare");
  p.shared = local_list("shared");
  w.expect("neighbours");
  p.neighbours = w.list<int>(static_cast<size_t>(p.parts));
  for (size_t q = 0; q < p.neighbours.size(); ++q) {
    w.expect("shared_with");
    p.shared_with.push_back(w.list<int>(p.shared.size()));
  }
  w.expect("numberings");
  p.numberings.resize(w.count(1UL << 20));
  for (auto& num : p.numberings) {
    w.expect("numbering");
    num.global_equations = w.integer<int>();
    num.whole_nodes = w.integer<int>() != 0;
    num.path_equation = w.integer<int>();
    num.equation.resize(3 * n);
    for (int& e : num.equation) {
      e = w.integer<int>();
      if (e < -1 || e >= num.global_equations) w.fail("an equation out of range");
    }
    w.expect("edge_loads");
    num.edge_loads.resize(w.count(1UL << 20));
    for (auto& edges : num.edge_loads) {
      w.expect("edges");
      edges.resize(w.count(kMost));
      for (auto& e : edges) e = {w.integer<int>(), w.integer<int>(), w.integer<int>()};
    }
  }
  w.expect("groups");
  p.groups.resize(w.count(1UL << 20));
  for (auto& g : p.groups) {
    w.expect("group");
    g.set = w.quoted();
    g.type = std::string(w.word());
    g.whole = w.integer<int>();
    const size_t own = w.count(static_cast<size_t>(std::max(g.whole, 0)));
    const size_t nn = w.count(64);
    g.own.resize(own);
    g.ids.resize(own);
    g.node_ids.resize(own * nn);
    for (size_t k = 0; k < own; ++k) {
      g.own[k] = w.integer<int>();
      if (g.own[k] < 0 || g.own[k] >= g.whole || (k > 0 && g.own[k] <= g.own[k - 1]))
        w.fail("the group's element indices are not ascending within it");
      g.ids[k] = w.integer<long>();
      for (size_t j = 0; j < nn; ++j) g.node_ids[k * nn + j] = w.integer<long>();
    }
  }
  for (auto* sets : {&p.node_sets, &p.element_set_nodes}) {
    w.expect(sets == &p.node_sets ? "node_sets" : "element_set_nodes");
    const size_t k = w.count(1UL << 24);
    for (size_t i = 0; i < k; ++i) {
      w.expect("set");
      std::string name = w.quoted();
      w.expect("ids");
      (*sets)[name] = w.list<long>(n);
    }
  }
  w.expect("history");
  p.history.resize(w.count(1UL << 24));
  for (auto& h : p.history) {
    w.expect("place");
    h.block = w.integer<int>();
    h.element = w.integer<int>();
    h.xi = {w.number(), w.number()};
  }
  w.expect("points");
  p.points.resize(w.count(1UL << 24));
  for (auto& [id, x] : p.points) {
    w.expect("point");
    id = w.integer<long>();
    const std::array<double, 3> c{w.number(), w.number(), w.number()};  // (in order)
    x = Vec3(c[0], c[1], c[2]);
  }
  w.expect("end");
  return p;
}

}  // namespace velum::io
