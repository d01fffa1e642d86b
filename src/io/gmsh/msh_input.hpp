// What the Gmsh .msh readers share: a cursor over the file's bytes that reads ASCII lines and
// tokens or binary values, and that never reads or allocates past what the file holds (a count
// in the file is checked against the bytes left before anything is sized from it); and the
// file's contents as read, before they become a MeshData (gmsh_reader.cpp).
#pragma once

#include <cstdint>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "velum/io/mesh_data.hpp"

namespace velum::io::msh {

/// At most 40 characters of a file's text for a message, non-printable bytes as '?'.
inline std::string printable(std::string_view text) {
  std::string s(text.substr(0, 40));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 32 || static_cast<unsigned char>(c) > 126) c = '?';
  return s;
}

/// A Gmsh element type: its number in the file, node count, dimension and name.
struct ElementType {
  int number = 0;
  int nodes = 0;
  int dim = 0;
  const char* name = "";
};

/// The type of a Gmsh element type number, or nullptr when Gmsh has no such type (or it is one
/// of the rare high-order ones this reader does not know the node count of).
const ElementType* element_type(int number);

/// The elements of one type on one geometric entity, in file order.
struct ElementBlock {
  int dim = 0;
  int entity = 0;
  int type = 0;
  std::vector<long> tags;
  std::vector<long> nodes;  ///< flattened, ElementType::nodes per element
};

/// The nodes classified on one entity (positions in MshContents::nodes).
struct NodeBlock {
  int dim = 0;
  int entity = 0;
  std::size_t first = 0, count = 0;
};

struct MshContents {
  std::vector<MeshNode> nodes;
  std::vector<NodeBlock> node_blocks;
  std::vector<ElementBlock> elements;
  /// (dim, entity) -> the physical groups (tags) it belongs to.
  std::map<std::pair<int, int>, std::set<int>> entity_physicals;
  /// (dim, physical tag) -> its name from $PhysicalNames.
  std::map<std::pair<int, int>, std::string> physical_names;
};

/// The cursor over the file. Its failures are MeshFileErrors naming the file and the line
/// (ASCII) or the byte (binary) where reading stopped.
class Input {
 public:
  Input(std::string_view bytes, std::string name) : bytes_(bytes), name_(std::move(name)) {}

  const std::string& name() const { return name_; }
  bool at_end() const { return pos_ >= bytes_.size(); }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  /// The 1-based number of the line last returned by next_line.
  long line_number() const { return line_; }

  /// The next line without its end of line (a trailing \r is dropped); false at the end.
  bool next_line(std::string_view& line) {
    if (at_end()) return false;
    const std::size_t end = bytes_.find('\n', pos_);
    const std::size_t stop = end == std::string_view::npos ? bytes_.size() : end;
    line = bytes_.substr(pos_, stop - pos_);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos_ = end == std::string_view::npos ? bytes_.size() : end + 1;
    ++line_;
    return true;
  }
  /// The next line, or a failure naming what was expected.
  std::string_view line(std::string_view what) {
    std::string_view l;
    if (!next_line(l))
      fail(std::string("the file ends where ") + std::string(what) + " was expected");
    return l;
  }

  /// Binary mode: one value of type T in the machine's byte order (checked at $MeshFormat).
  template <class T>
  T binary(std::string_view what) {
    need(sizeof(T), 1, what);
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  /// Checks that count records of `size` bytes each fit in what is left of the file: no array
  /// is sized from a count the file cannot hold.
  void need(std::size_t size, std::size_t count, std::string_view what) const {
    if (size != 0 && count > remaining() / size)
      fail(std::string("the file is too short for ") + std::string(what) + " (" +
           std::to_string(count) + " x " + std::to_string(size) + " bytes asked, " +
           std::to_string(remaining()) + " left): truncated or corrupt");
  }
  /// After binary data: skips the end of line Gmsh writes before the section's end tag.
  void end_binary_block() {
    while (!at_end() && (bytes_[pos_] == '\n' || bytes_[pos_] == '\r')) {
      if (bytes_[pos_] == '\n') ++line_;
      ++pos_;
    }
  }
  /// Skips to the line after "$End<section>" (an unknown or unused section).
  void skip_section(std::string_view section) {
    const std::string end = "$End" + std::string(section);
    std::string_view l;
    while (next_line(l))
      if (l == end) return;
    fail("section $" + std::string(section) + " has no " + end);
  }
  /// Binary files: failures name the byte, as the line count means nothing past binary data.
  void set_binary(bool b) { binary_ = b; }

  /// Fails at the present place: "file:line: why" (ASCII) or "file: byte N: why" (binary).
  [[noreturn]] void fail(const std::string& why) const {
    throw MeshFileError(binary_ ? name_ + ": byte " + std::to_string(pos_) + ": " + why
                                : name_ + ":" + std::to_string(line_) + ": " + why);
  }

 private:
  std::string_view bytes_;
  std::string name_;
  std::size_t pos_ = 0;
  long line_ = 0;
  bool binary_ = false;
};

/// The whitespace-separated tokens of one ASCII line, read as numbers.
class Tokens {
 public:
  Tokens(std::string_view line, const Input& in) : rest_(line), in_(in) {}
  long integer(std::string_view what);
  double real(std::string_view what);
  /// A quoted name ("..."), as $PhysicalNames writes it; the rest of the line if unquoted.
  std::string quoted(std::string_view what);
  bool empty();

 private:
  std::string_view token(std::string_view what);
  std::string_view rest_;
  const Input& in_;
};

/// Checks a tag read from the file (Gmsh tags start at 1) and returns it as a long.
long checked_tag(const Input& in, std::uint64_t tag, std::string_view what);

// The sections, each read from the line after its $Name to the line after its $EndName.
void read_physical_names(Input& in, MshContents& out);
void read_msh2_nodes(Input& in, bool binary, MshContents& out);
void read_msh2_elements(Input& in, bool binary, MshContents& out);
void read_msh41_entities(Input& in, bool binary, MshContents& out);
void read_msh41_nodes(Input& in, bool binary, MshContents& out);
void read_msh41_elements(Input& in, bool binary, MshContents& out);

}  // namespace velum::io::msh
