// MSH 4.1 (ASCII and binary): $Entities gives each geometric entity's physical groups; $Nodes
// and $Elements come in blocks, one per entity (and type). Binary sizes: int 4, size_t 8,
// double 8 bytes (checked at $MeshFormat).
#include <fmt/format.h>

#include <limits>

#include "msh_input.hpp"

namespace velum::io::msh {

namespace {

using Size = std::uint64_t;

int small_int(const Input& in, long v, std::string_view what) {
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max())
    in.fail(fmt::format("{} {} is out of range", what, v));
  return static_cast<int>(v);
}

// A physical group's tag in $Entities: its sign is an orientation, dropped.
int physical_tag(const Input& in, long v) {
  if (v == 0 || v < -std::numeric_limits<int>::max() || v > std::numeric_limits<int>::max())
    in.fail(fmt::format("physical group tag {} is out of range", v));
  return static_cast<int>(v < 0 ? -v : v);
}

int dimension(const Input& in, long v) {
  if (v < 0 || v > 3) in.fail(fmt::format("an entity dimension of {} (0 to 3 expected)", v));
  return static_cast<int>(v);
}

// The four counts that open $Entities, $Nodes and $Elements.
struct Header {
  Size a = 0, b = 0, c = 0, d = 0;
};

Header header(Input& in, bool binary, std::string_view what) {
  Header h;
  if (binary) {
    h.a = in.binary<Size>(what);
    h.b = in.binary<Size>(what);
    h.c = in.binary<Size>(what);
    h.d = in.binary<Size>(what);
    return h;
  }
  Tokens t(in.line(what), in);
  Size* v[] = {&h.a, &h.b, &h.c, &h.d};
  for (Size* x : v) {
    const long n = t.integer(what);
    if (n < 0) in.fail(fmt::format("{}: a negative count", what));
    *x = static_cast<Size>(n);
  }
  return h;
}

void expect_end(Input& in, bool binary, std::string_view end) {
  if (binary) in.end_binary_block();
  if (in.line(end) != end) in.fail(fmt::format("expected {} here", end));
}

}  // namespace

void read_msh41_entities(Input& in, bool binary, MshContents& out) {
  const Header h = header(in, binary, "the numbers of points, curves, surfaces and volumes");
  const Size counts[] = {h.a, h.b, h.c, h.d};
  for (int dim = 0; dim < 4; ++dim) {
    // The smallest record: a point (int, 3 doubles, size_t) in binary; "1 0 0 0 0" in ASCII.
    in.need(binary ? 36 : 10, counts[dim], "the entities");
    for (Size i = 0; i < counts[dim]; ++i) {
      if (binary) {
        const int tag = in.binary<std::int32_t>("an entity tag");
        for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) (void)in.binary<double>("an entity's box");
        const Size nphys = in.binary<Size>("an entity's number of physical groups");
        in.need(4, nphys, "an entity's physical groups");
        for (Size k = 0; k < nphys; ++k) {
          const long p = in.binary<std::int32_t>("a physical group tag");
          out.entity_physicals[{dim, tag}].insert(physical_tag(in, p));
        }
        if (dim > 0) {
          const Size nbound = in.binary<Size>("an entity's number of bounding entities");
          in.need(4, nbound, "an entity's bounding entities");
          for (Size k = 0; k < nbound; ++k) (void)in.binary<std::int32_t>("a bounding entity");
        }
      } else {
        Tokens t(in.line("an entity line"), in);
        const int tag = small_int(in, t.integer("the entity tag"), "entity tag");
        for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) (void)t.real("an entity's box");
        const long nphys = t.integer("the entity's number of physical groups");
        if (nphys < 0) in.fail("a negative number of physical groups");
        for (long k = 0; k < nphys; ++k) {
          out.entity_physicals[{dim, tag}].insert(
              physical_tag(in, t.integer("a physical group tag")));
        }
        // The bounding entities (curves, surfaces, volumes) are not needed.
      }
    }
  }
  expect_end(in, binary, "$EndEntities");
}

void read_msh41_nodes(Input& in, bool binary, MshContents& out) {
  const Header h = header(in, binary, "the $Nodes header (blocks, nodes, smallest, largest tag)");
  in.need(binary ? 20 : 8, h.a, "the node blocks");
  in.need(binary ? 32 : 4, h.b, "the nodes");
  if (binary) out.nodes.reserve(out.nodes.size() + h.b);
  Size total = 0;
  for (Size blk = 0; blk < h.a; ++blk) {
    int dim = 0, entity = 0;
    long parametric = 0;
    Size n = 0;
    if (binary) {
      dim = dimension(in, in.binary<std::int32_t>("a node block's dimension"));
      entity = in.binary<std::int32_t>("a node block's entity");
      parametric = in.binary<std::int32_t>("a node block's parametric flag");
      n = in.binary<Size>("a node block's size");
    } else {
      Tokens t(in.line("a node block header"), in);
      dim = dimension(in, t.integer("the node block's dimension"));
      entity = small_int(in, t.integer("the node block's entity"), "entity tag");
      parametric = t.integer("the node block's parametric flag");
      const long count = t.integer("the node block's size");
      if (count < 0) in.fail("a negative node block size");
      n = static_cast<Size>(count);
    }
    if (parametric != 0 && parametric != 1)
      in.fail(fmt::format("a node block's parametric flag of {} (0 or 1)", parametric));
    if (n > h.b - total)
      in.fail(fmt::format("node block {} holds {} nodes, beyond the {} the header declares",
                          blk + 1, n, h.b));
    const int values = 3 + (parametric ? dim : 0);
    const std::size_t first = out.nodes.size();
    if (binary) {
      in.need(8 + 8 * values, n, "the nodes of a block");
      for (Size i = 0; i < n; ++i)
        out.nodes.push_back({checked_tag(in, in.binary<Size>("a node tag"), "node tag"), {}});
      for (Size i = 0; i < n; ++i) {
        Vec3& x = out.nodes[first + i].x;
        for (int k = 0; k < values; ++k) {
          const double v = in.binary<double>("a node coordinate");
          if (k < 3) x[k] = v;
        }
      }
    } else {
      for (Size i = 0; i < n; ++i) {
        Tokens t(in.line("a node tag"), in);
        const long tag = t.integer("the node tag");
        out.nodes.push_back({checked_tag(in, tag < 0 ? 0 : tag, "node tag"), {}});
      }
      for (Size i = 0; i < n; ++i) {
        Tokens t(in.line("a node's coordinates"), in);
        Vec3& x = out.nodes[first + i].x;
        for (int k = 0; k < values; ++k) {
          const double v = t.real("a node coordinate");
          if (k < 3) x[k] = v;
        }
      }
    }
    out.node_blocks.push_back({dim, entity, first, static_cast<std::size_t>(n)});
    total += n;
  }
  if (total != h.b)
    in.fail(fmt::format("$Nodes declares {} nodes but its blocks hold {}", h.b, total));
  expect_end(in, binary, "$EndNodes");
}

void read_msh41_elements(Input& in, bool binary, MshContents& out) {
  const Header h = header(in, binary, "the $Elements header (blocks, elements, tags)");
  in.need(binary ? 20 : 8, h.a, "the element blocks");
  in.need(binary ? 16 : 4, h.b, "the elements");
  Size total = 0;
  for (Size blk = 0; blk < h.a; ++blk) {
    int dim = 0, entity = 0, number = 0;
    Size n = 0;
    if (binary) {
      dim = dimension(in, in.binary<std::int32_t>("an element block's dimension"));
      entity = in.binary<std::int32_t>("an element block's entity");
      number = in.binary<std::int32_t>("an element block's type");
      n = in.binary<Size>("an element block's size");
    } else {
      Tokens t(in.line("an element block header"), in);
      dim = dimension(in, t.integer("the element block's dimension"));
      entity = small_int(in, t.integer("the element block's entity"), "entity tag");
      number = small_int(in, t.integer("the element block's type"), "element type");
      const long count = t.integer("the element block's size");
      if (count < 0) in.fail("a negative element block size");
      n = static_cast<Size>(count);
    }
    const ElementType* type = element_type(number);
    if (!type)
      in.fail(fmt::format("element block {}: unknown Gmsh element type {}", blk + 1, number));
    if (type->dim != dim)
      in.fail(fmt::format("element block {}: type {} ({}) on an entity of dimension {}", blk + 1,
                          number, type->name, dim));
    if (n > h.b - total)
      in.fail(fmt::format("element block {} holds {} elements, beyond the {} the header declares",
                          blk + 1, n, h.b));
    ElementBlock b{dim, entity, number, {}, {}};
    if (binary) {
      in.need(8 * static_cast<std::size_t>(1 + type->nodes), n, "the elements of a block");
      b.tags.reserve(n);
      b.nodes.reserve(n * static_cast<std::size_t>(type->nodes));
      for (Size e = 0; e < n; ++e) {
        b.tags.push_back(checked_tag(in, in.binary<Size>("an element tag"), "element tag"));
        for (int k = 0; k < type->nodes; ++k)
          b.nodes.push_back(checked_tag(in, in.binary<Size>("an element's node"), "node tag"));
      }
    } else {
      for (Size e = 0; e < n; ++e) {
        Tokens t(in.line("an element line"), in);
        const long tag = t.integer("the element tag");
        b.tags.push_back(checked_tag(in, tag < 0 ? 0 : tag, "element tag"));
        for (int k = 0; k < type->nodes; ++k) {
          const long v = t.integer("a node of the element");
          b.nodes.push_back(checked_tag(in, v < 0 ? 0 : v, "node tag"));
        }
        if (!t.empty())
          in.fail(fmt::format("element {} ({}) has more than its {} nodes", tag, type->name,
                              type->nodes));
      }
    }
    out.elements.push_back(std::move(b));
    total += n;
  }
  if (total != h.b)
    in.fail(fmt::format("$Elements declares {} elements but its blocks hold {}", h.b, total));
  expect_end(in, binary, "$EndElements");
}

}  // namespace velum::io::msh
