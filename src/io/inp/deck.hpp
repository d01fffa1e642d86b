// The lines of an Abaqus/CalculiX deck, split into keyword blocks (Abaqus's input syntax
// rules): `**` starts a comment line; a line starting with `*` is a keyword line, its name
// before the first comma, its options `NAME` or `NAME=value` after it, continued on the next
// line when it ends with a comma; every other line is a data line of comma-separated fields.
// Keyword and option names are upper-cased with runs of blanks made one space; values keep
// their spelling. *INCLUDE, INPUT=file is read in place (relative to the including file).
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "velum/math/types.hpp"

namespace velum::io::inp {

struct DataLine {
  int file = 0;  ///< index into Deck::files
  int line = 0;  ///< 1-based
  std::vector<std::string> fields;
};

struct Keyword {
  std::string name;                            ///< "MEMBRANE SECTION"
  std::map<std::string, std::string> options;  ///< upper-cased names; "" for a bare flag
  int file = 0, line = 0;
  std::vector<DataLine> data;
  bool has(const std::string& option) const { return options.count(option) > 0; }
};

/// Upper case, runs of blanks made one space, trimmed.
std::string canonical(std::string_view s);

/// Collects the problems of a deck and formats them "file:line: *KEYWORD: text".
class Diagnostics {
 public:
  std::vector<std::string> files;  ///< the deck and its includes, as named in messages
  std::vector<std::string> errors, warnings;

  std::string where(int file, int line) const;
  void error(const Keyword& k, const std::string& text);
  void error(const Keyword& k, const DataLine& d, const std::string& text);
  void warn(const Keyword& k, const std::string& text);
  void warn(const Keyword& k, const DataLine& d, const std::string& text);

  // Typed fields of a data line; nullopt after reporting a bad value.
  std::optional<double> number(const Keyword& k, const DataLine& d, size_t i,
                               std::optional<double> fallback = std::nullopt);
  std::optional<long> integer(const Keyword& k, const DataLine& d, size_t i,
                              std::optional<long> fallback = std::nullopt);
  /// Reports options of `k` not in `allowed`; true when there are none.
  bool check_options(const Keyword& k, const std::vector<std::string>& allowed);
  /// The value of a required option (reported when missing or empty).
  std::optional<std::string> required(const Keyword& k, const std::string& option);
};

/// Reads the keyword blocks of `file` and its includes. Unreadable files and syntax errors
/// (data before the first keyword, an include loop) go to `diag.errors`.
std::vector<Keyword> read_deck(const std::filesystem::path& file, Diagnostics& diag);

}  // namespace velum::io::inp
