// What every part of the model-file reader shares: its name and base directory, the list of
// problems found so far ("file:line: key: text"), the ModelInput being filled, and typed readers of
// YAML values that report a bad value instead of throwing. Each part of the file (mesh, materials
// and sections, boundary and loads, analysis and output) is read by a Reader member defined in its
// own read_*.cpp.
#pragma once

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "velum/io/model_reader.hpp"

namespace velum::io::model_file {

using YAML::Node;
using Keys = std::initializer_list<std::string_view>;

/// " (did you mean 'x'?)" with the candidate nearest to `word`; empty without candidates.
std::string suggestion(std::string_view word, const std::vector<std::string>& candidates);

template <class Map>
std::vector<std::string> keys_of(const Map& m) {
  std::vector<std::string> out;
  for (const auto& kv : m) out.push_back(kv.first);
  return out;
}

class ReaderContext {
 public:
  /// `name` starts every message; relative mesh and output paths start from `base_dir`.
  ReaderContext(std::string name, std::filesystem::path base_dir)
      : base_dir_(std::move(base_dir)), name_(std::move(name)) {
    in_.file = name_;
  }

  // What the readers of each part of the file (and the sheet-law parsers of
  // sheet_law_table.cpp) use.
  // ---- diagnostics --------------------------------------------------------------------
  int line_of(const Node& n) const;
  void error_at(int line0, const std::string& key, const std::string& text);
  void error(const Node& at, const std::string& key, const std::string& text);
  void warn(const Node& at, const std::string& key, const std::string& text);
  /// A problem in a data file the model names (a stress map's CSV): "file:line: key: text".
  void error_in_file(const std::string& file, int line, const std::string& key,
                     const std::string& text);
  /// The problems found so far.
  const std::vector<std::string>& errors() const { return errors_; }
  /// Where relative paths of the model file start.
  const std::filesystem::path& base_dir() const { return base_dir_; }

  static std::string sub(const std::string& path, std::string_view key);
  static std::string item(const std::string& path, size_t i);

  /// Reports keys of `map` not in `allowed`; false when `map` is not a mapping.
  bool check_map(const Node& map, const std::string& path, Keys allowed);
  bool has(const Node& map, const char* key) const;
  bool require(const Node& map, const char* key, const std::string& path);

  // ---- typed values: nullopt when absent or invalid (invalid values are reported) -------
  std::optional<double> number(const Node& n, const std::string& path);
  std::optional<double> number(const Node& map, const char* key, const std::string& path,
                               bool required);
  std::optional<double> positive(const Node& map, const char* key, const std::string& path,
                                 bool required, const char* what);
  std::optional<double> non_negative(const Node& map, const char* key, const std::string& path,
                                     const char* what);
  std::optional<long> integer(const Node& n, const std::string& path, const char* what);
  std::optional<std::string> text(const Node& map, const char* key, const std::string& path,
                                  bool required);
  std::optional<bool> boolean(const Node& map, const char* key, const std::string& path);
  std::optional<Vec3> vec3(const Node& n, const std::string& path);
  std::optional<Vec3> vec3(const Node& map, const char* key, const std::string& path,
                           bool required);
  std::optional<int> component(const Node& map, const char* key, const std::string& path);

 protected:
  std::filesystem::path base_dir_;  ///< relative mesh and output paths start here
  std::string name_;
  std::vector<std::string> errors_;
  ModelInput in_;
};

}  // namespace velum::io::model_file
