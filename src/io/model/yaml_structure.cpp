#include "yaml_structure.hpp"

#include <fmt/format.h>

#include <map>
#include <set>

namespace velum::io::model_file {
namespace {

class Walker {
 public:
  explicit Walker(const std::string& file) : file_(file) {}

  void walk(const YAML::Node& n, const std::string& path, int depth) {
    if (!n.IsMap() && !n.IsSequence()) return;
    if (!n.Mark().is_null() && !seen_.insert(n.Mark().pos).second) return;  // an alias
    if (depth > kMaxYamlDepth) {
      if (!too_deep_)
        problems_.push_back(fmt::format("{}:{}: {}: nested more than {} levels deep", file_,
                                        n.Mark().line + 1, path.empty() ? "model" : path,
                                        kMaxYamlDepth));
      too_deep_ = true;
      return;
    }
    if (n.IsSequence()) {
      size_t i = 0;
      for (const auto& item : n) walk(item, fmt::format("{}[{}]", path, i++), depth + 1);
      return;
    }
    std::map<std::string, int> lines;
    for (const auto& kv : n) {
      const std::string key = kv.first.IsScalar() ? kv.first.Scalar() : std::string();
      const std::string sub = path.empty() ? key : path + "." + key;
      const int line = kv.first.Mark().is_null() ? 0 : kv.first.Mark().line + 1;
      if (kv.first.IsScalar()) {
        auto [it, fresh] = lines.emplace(key, line);
        if (!fresh)
          problems_.push_back(
              fmt::format("{}:{}: {}: the key '{}' is given twice (lines {} and {}); give it once",
                          file_, line, sub, key, it->second, line));
      }
      walk(kv.second, sub, depth + 1);
    }
  }

  std::vector<std::string> problems_;

 private:
  const std::string& file_;
  std::set<std::size_t> seen_;
  bool too_deep_ = false;
};

}  // namespace

std::vector<std::string> yaml_structure_problems(const YAML::Node& root, const std::string& file) {
  Walker w(file);
  w.walk(root, "", 0);
  return std::move(w.problems_);
}

}  // namespace velum::io::model_file
