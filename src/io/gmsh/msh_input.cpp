#include "msh_input.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>

namespace velum::io::msh {

namespace {

// Gmsh's element types (gmsh.info/doc/texinfo, "MSH file format"), the ones a file may carry
// beside ours: a binary file's elements can only be stepped over when their node count is known.
constexpr ElementType kTypes[] = {
    {1, 2, 1, "line2"},       {2, 3, 2, "tri3"},        {3, 4, 2, "quad4"},
    {4, 4, 3, "tet4"},        {5, 8, 3, "hex8"},        {6, 6, 3, "prism6"},
    {7, 5, 3, "pyramid5"},    {8, 3, 1, "line3"},       {9, 6, 2, "tri6"},
    {10, 9, 2, "quad9"},      {11, 10, 3, "tet10"},     {12, 27, 3, "hex27"},
    {13, 18, 3, "prism18"},   {14, 14, 3, "pyramid14"}, {15, 1, 0, "point"},
    {16, 8, 2, "quad8"},      {17, 20, 3, "hex20"},     {18, 15, 3, "prism15"},
    {19, 13, 3, "pyramid13"}, {20, 9, 2, "tri9"},       {21, 10, 2, "tri10"},
    {22, 12, 2, "tri12"},     {23, 15, 2, "tri15"},     {24, 15, 2, "tri15i"},
    {25, 21, 2, "tri21"},     {26, 4, 1, "line4"},      {27, 5, 1, "line5"},
    {28, 6, 1, "line6"},      {29, 20, 3, "tet20"},     {30, 35, 3, "tet35"},
    {31, 56, 3, "tet56"},     {36, 16, 2, "quad16"},    {37, 25, 2, "quad25"},
    {38, 36, 2, "quad36"},    {92, 64, 3, "hex64"},     {93, 125, 3, "hex125"},
};

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

}  // namespace

const ElementType* element_type(int number) {
  for (const auto& t : kTypes)
    if (t.number == number) return &t;
  return nullptr;
}

std::string_view Tokens::token(std::string_view what) {
  std::size_t i = 0;
  while (i < rest_.size() && is_space(rest_[i])) ++i;
  std::size_t j = i;
  while (j < rest_.size() && !is_space(rest_[j])) ++j;
  if (i == j) in_.fail("the line ends where " + std::string(what) + " was expected");
  const std::string_view t = rest_.substr(i, j - i);
  rest_.remove_prefix(j);
  return t;
}

bool Tokens::empty() {
  while (!rest_.empty() && is_space(rest_.front())) rest_.remove_prefix(1);
  return rest_.empty();
}

long Tokens::integer(std::string_view what) {
  const std::string_view t = token(what);
  long v = 0;
  const char* first = t.data() + (t.size() > 1 && t.front() == '+' ? 1 : 0);
  const auto [end, ec] = std::from_chars(first, t.data() + t.size(), v);
  if (ec != std::errc() || end != t.data() + t.size())
    in_.fail(std::string(what) + ": '" + printable(t) + "' is not an integer" +
             (ec == std::errc::result_out_of_range ? " in range" : ""));
  return v;
}

double Tokens::real(std::string_view what) {
  const std::string_view t = token(what);
  double v = 0;
  const char* first = t.data() + (t.size() > 1 && t.front() == '+' ? 1 : 0);
  const auto [end, ec] = std::from_chars(first, t.data() + t.size(), v);
  if (ec == std::errc::result_out_of_range)
    in_.fail(std::string(what) + ": '" + printable(t) + "' is beyond the range of a double");
  if (ec != std::errc() || end != t.data() + t.size())
    in_.fail(std::string(what) + ": '" + printable(t) + "' is not a number");
  return v;
}

std::string Tokens::quoted(std::string_view what) {
  while (!rest_.empty() && is_space(rest_.front())) rest_.remove_prefix(1);
  if (rest_.empty()) in_.fail("the line ends where " + std::string(what) + " was expected");
  if (rest_.front() != '"') {
    std::string s(rest_);
    rest_ = {};
    return s;
  }
  const std::size_t close = rest_.find('"', 1);
  if (close == std::string_view::npos) in_.fail(std::string(what) + " has no closing quote");
  std::string s(rest_.substr(1, close - 1));
  rest_.remove_prefix(close + 1);
  return s;
}

long checked_tag(const Input& in, std::uint64_t tag, std::string_view what) {
  if (tag == 0 || tag > static_cast<std::uint64_t>(std::numeric_limits<long>::max()))
    in.fail(std::string(what) + " " + std::to_string(tag) +
            " is out of range (Gmsh tags are 1 and above)");
  return static_cast<long>(tag);
}

// $PhysicalNames (ASCII in binary files too): the count, then "dim tag "name"" per line.
void read_physical_names(Input& in, MshContents& out) {
  Tokens head(in.line("the number of physical names"), in);
  const long n = head.integer("the number of physical names");
  if (n < 0) in.fail("a negative number of physical names");
  for (long i = 0; i < n; ++i) {
    Tokens t(in.line("a physical name"), in);
    const long dim = t.integer("the physical group's dimension");
    const long tag = t.integer("the physical group's tag");
    if (dim < 0 || dim > 3) in.fail("a physical group's dimension must be 0 to 3");
    if (tag < std::numeric_limits<int>::min() || tag > std::numeric_limits<int>::max())
      in.fail("a physical group's tag is out of range");
    out.physical_names[{static_cast<int>(dim), static_cast<int>(tag)}] =
        t.quoted("the physical group's name");
  }
  std::string_view end = in.line("$EndPhysicalNames");
  if (end != "$EndPhysicalNames")
    in.fail("$PhysicalNames holds more names than its count (" + std::to_string(n) + ")");
}

}  // namespace velum::io::msh
