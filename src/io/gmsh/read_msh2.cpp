// MSH 2.2 (ASCII and binary): nodes as "tag x y z"; elements carry their physical group and
// geometric entity as their first two tags. Here the elements are sorted into blocks by
// (dimension, entity, type) and the entities into physical groups, as MSH 4.1 has them.
#include <fmt/format.h>

#include <map>
#include <tuple>

#include "msh_input.hpp"

namespace velum::io::msh {

namespace {

long tag_of(const Input& in, long v, std::string_view what) {
  return checked_tag(in, v < 0 ? 0 : static_cast<std::uint64_t>(v), what);
}

class Msh2Elements {
 public:
  explicit Msh2Elements(MshContents& out) : out_(out) {}
  /// One element: its physical group and entity (0: none), type and nodes.
  void add(const ElementType& type, long tag, long physical, long entity, const long* nodes) {
    const auto key = std::make_tuple(type.dim, static_cast<int>(entity), type.number);
    auto [it, fresh] = block_.try_emplace(key, out_.elements.size());
    if (fresh) out_.elements.push_back({type.dim, static_cast<int>(entity), type.number, {}, {}});
    ElementBlock& b = out_.elements[it->second];
    b.tags.push_back(tag);
    b.nodes.insert(b.nodes.end(), nodes, nodes + type.nodes);
    if (physical != 0)
      out_.entity_physicals[{type.dim, static_cast<int>(entity)}].insert(
          static_cast<int>(physical));
  }

 private:
  MshContents& out_;
  std::map<std::tuple<int, int, int>, std::size_t> block_;
};

long section_count(Input& in, std::string_view what) {
  Tokens t(in.line(what), in);
  const long n = t.integer(what);
  if (n < 0) in.fail(fmt::format("{} is negative", what));
  return n;
}

void expect_end(Input& in, std::string_view end) {
  if (in.line(end) != end) in.fail(fmt::format("expected {} here", end));
}

}  // namespace

void read_msh2_nodes(Input& in, bool binary, MshContents& out) {
  const long n = section_count(in, "the number of nodes");
  if (binary) {
    in.need(4 + 3 * 8, static_cast<std::size_t>(n), "the nodes");
    out.nodes.reserve(out.nodes.size() + static_cast<std::size_t>(n));
    for (long i = 0; i < n; ++i) {
      const long tag = tag_of(in, in.binary<std::int32_t>("a node tag"), "node tag");
      Vec3 x;
      for (int k = 0; k < 3; ++k) x[k] = in.binary<double>("a node coordinate");
      out.nodes.push_back({tag, x});
    }
    in.end_binary_block();
  } else {
    for (long i = 0; i < n; ++i) {
      Tokens t(in.line("a node line"), in);
      const long tag = tag_of(in, t.integer("the node tag"), "node tag");
      Vec3 x;
      for (int k = 0; k < 3; ++k) x[k] = t.real("a node coordinate");
      out.nodes.push_back({tag, x});
    }
  }
  expect_end(in, "$EndNodes");
}

void read_msh2_elements(Input& in, bool binary, MshContents& out) {
  const long n = section_count(in, "the number of elements");
  Msh2Elements elements(out);
  long nodes[125];
  if (binary) {
    for (long done = 0; done < n;) {
      const int number = in.binary<std::int32_t>("an element block's type");
      const long count = in.binary<std::int32_t>("an element block's size");
      const long ntags = in.binary<std::int32_t>("an element block's number of tags");
      const ElementType* type = element_type(number);
      if (!type) in.fail(fmt::format("unknown Gmsh element type {}", number));
      if (count <= 0 || count > n - done || ntags < 0 || ntags > 1000)
        in.fail(fmt::format("an element block of {} elements with {} tags: corrupt", count, ntags));
      in.need(4 * static_cast<std::size_t>(1 + ntags + type->nodes),
              static_cast<std::size_t>(count), "the elements");
      for (long e = 0; e < count; ++e) {
        const long tag = tag_of(in, in.binary<std::int32_t>("an element tag"), "element tag");
        long physical = 0, entity = 0;
        for (long k = 0; k < ntags; ++k) {
          const long v = in.binary<std::int32_t>("an element's tags");
          if (k == 0) physical = v;
          if (k == 1) entity = v;
        }
        for (int k = 0; k < type->nodes; ++k)
          nodes[k] = tag_of(in, in.binary<std::int32_t>("an element's node"), "node tag");
        elements.add(*type, tag, physical, entity, nodes);
      }
      done += count;
    }
    in.end_binary_block();
  } else {
    for (long i = 0; i < n; ++i) {
      Tokens t(in.line("an element line"), in);
      const long tag = tag_of(in, t.integer("the element tag"), "element tag");
      const long number = t.integer("the element type");
      const ElementType* type =
          number > 0 && number < 1000 ? element_type(static_cast<int>(number)) : nullptr;
      if (!type) in.fail(fmt::format("element {}: unknown Gmsh element type {}", tag, number));
      const long ntags = t.integer("the number of tags");
      if (ntags < 0 || ntags > 1000) in.fail(fmt::format("element {}: {} tags", tag, ntags));
      long physical = 0, entity = 0;
      for (long k = 0; k < ntags; ++k) {
        const long v = t.integer("an element tag");
        if (k == 0) physical = v;
        if (k == 1) entity = v;
      }
      if (physical < -2147483647 || physical > 2147483647 || entity < -2147483647 ||
          entity > 2147483647)
        in.fail(fmt::format("element {}: a physical or entity tag out of range", tag));
      for (int k = 0; k < type->nodes; ++k) nodes[k] = tag_of(in, t.integer("a node"), "node tag");
      if (!t.empty())
        in.fail(fmt::format("element {} ({}) has more than its {} nodes", tag, type->name,
                            type->nodes));
      elements.add(*type, tag, physical, entity, nodes);
    }
  }
  expect_end(in, "$EndElements");
}

}  // namespace velum::io::msh
