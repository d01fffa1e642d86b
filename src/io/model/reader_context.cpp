#include "reader_context.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace velum::io::model_file {

namespace {

// The edit distance costs the product of the lengths: only the first kMaxSuggestionChars
// characters are compared, so a megabyte-long name costs no more than a short one.
std::string nearest(std::string_view word, const std::vector<std::string>& candidates) {
  std::string best;
  int best_d = 1 << 30;
  word = word.substr(0, kMaxSuggestionChars);
  for (const auto& c : candidates) {
    const int d = edit_distance(word, std::string_view(c).substr(0, kMaxSuggestionChars));
    if (d < best_d) best_d = d, best = c;
  }
  return best;
}

}  // namespace

std::string suggestion(std::string_view word, const std::vector<std::string>& candidates) {
  if (candidates.empty()) return {};
  return fmt::format(" (did you mean '{}'?)", nearest(word, candidates));
}

int ReaderContext::line_of(const Node& n) const {
  return n.Mark().is_null() ? 0 : n.Mark().line + 1;
}

void ReaderContext::error_at(int line0, const std::string& key, const std::string& text) {
  const std::string loc = line0 >= 0 ? fmt::format("{}:{}", name_, line0 + 1) : name_;
  errors_.push_back(key.empty() ? fmt::format("{}: {}", loc, text)
                                : fmt::format("{}: {}: {}", loc, key, text));
}

void ReaderContext::error_in_file(const std::string& file, int line, const std::string& key,
                                  const std::string& text) {
  errors_.push_back(fmt::format("{}:{}: {}: {}", file, line, key, text));
}

void ReaderContext::error(const Node& at, const std::string& key, const std::string& text) {
  error_at(at.Mark().is_null() ? -1 : at.Mark().line, key, text);
}

void ReaderContext::warn(const Node& at, const std::string& key, const std::string& text) {
  const std::string loc =
      at.Mark().is_null() ? name_ : fmt::format("{}:{}", name_, std::max(line_of(at), 1));
  in_.warnings.push_back(fmt::format("{}: {}: {}", loc, key, text));
}

std::string ReaderContext::sub(const std::string& path, std::string_view key) {
  return path.empty() ? std::string(key) : path + "." + std::string(key);
}

std::string ReaderContext::item(const std::string& path, size_t i) {
  return fmt::format("{}[{}]", path, i);
}

/// Reports keys of `map` not in `allowed`; false when `map` is not a mapping.
bool ReaderContext::check_map(const Node& map, const std::string& path, Keys allowed) {
  if (!map.IsMap()) {
    error(map, path, "expected a mapping of keys (key: value)");
    return false;
  }
  std::vector<std::string> valid(allowed.begin(), allowed.end());
  for (const auto& kv : map) {
    if (!kv.first.IsScalar()) {
      error(kv.first, path, "keys must be plain names");
      continue;
    }
    const std::string k = kv.first.Scalar();
    if (std::find(valid.begin(), valid.end(), k) == valid.end())
      error(kv.first, sub(path, k), "unknown key" + suggestion(k, valid));
  }
  return true;
}

bool ReaderContext::has(const Node& map, const char* key) const {
  return map.IsMap() && map[key];
}

bool ReaderContext::require(const Node& map, const char* key, const std::string& path) {
  if (has(map, key)) return true;
  error(map, sub(path, key), "required key is missing");
  return false;
}

std::optional<double> ReaderContext::number(const Node& n, const std::string& path) {
  double v = 0;
  if (!n.IsScalar() || !YAML::convert<double>::decode(n, v)) {
    error(n, path, "expected a number");
    return std::nullopt;
  }
  if (!std::isfinite(v)) {
    error(n, path, "expected a finite number");
    return std::nullopt;
  }
  return v;
}

/// Optional key: nullopt when absent or invalid (invalid values are reported).
std::optional<double> ReaderContext::number(const Node& map, const char* key,
                                            const std::string& path, bool required) {
  if (!has(map, key)) {
    if (required) require(map, key, path);
    return std::nullopt;
  }
  return number(map[key], sub(path, key));
}

std::optional<double> ReaderContext::positive(const Node& map, const char* key,
                                              const std::string& path, bool required,
                                              const char* what) {
  auto v = number(map, key, path, required);
  if (v && *v <= 0) {
    error(map[key], sub(path, key), fmt::format("{} must be positive (got {})", what, *v));
    return std::nullopt;
  }
  return v;
}

std::optional<double> ReaderContext::non_negative(const Node& map, const char* key,
                                                  const std::string& path, const char* what) {
  auto v = number(map, key, path, false);
  if (v && *v < 0) {
    error(map[key], sub(path, key), fmt::format("{} must not be negative (got {})", what, *v));
    return std::nullopt;
  }
  return v;
}

std::optional<long> ReaderContext::integer(const Node& n, const std::string& path,
                                           const char* what) {
  long v = 0;
  if (!n.IsScalar() || !YAML::convert<long>::decode(n, v)) {
    error(n, path, fmt::format("expected an integer {}", what));
    return std::nullopt;
  }
  return v;
}

std::optional<std::string> ReaderContext::text(const Node& map, const char* key,
                                               const std::string& path, bool required) {
  if (!has(map, key)) {
    if (required) require(map, key, path);
    return std::nullopt;
  }
  const Node n = map[key];
  if (!n.IsScalar()) {
    error(n, sub(path, key), "expected a name (a plain string)");
    return std::nullopt;
  }
  return n.Scalar();
}

std::optional<bool> ReaderContext::boolean(const Node& map, const char* key,
                                           const std::string& path) {
  if (!has(map, key)) return std::nullopt;
  bool v = false;
  if (!map[key].IsScalar() || !YAML::convert<bool>::decode(map[key], v)) {
    error(map[key], sub(path, key), "expected true or false");
    return std::nullopt;
  }
  return v;
}

std::optional<Vec3> ReaderContext::vec3(const Node& n, const std::string& path) {
  if (!n.IsSequence() || n.size() != 3) {
    error(n, path, "expected a list of three numbers [x, y, z]");
    return std::nullopt;
  }
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    auto c = number(n[i], item(path, i));
    if (!c) return std::nullopt;
    v[i] = *c;
  }
  return v;
}

std::optional<Vec3> ReaderContext::vec3(const Node& map, const char* key, const std::string& path,
                                        bool required) {
  if (!has(map, key)) {
    if (required) require(map, key, path);
    return std::nullopt;
  }
  return vec3(map[key], sub(path, key));
}

std::optional<int> ReaderContext::component(const Node& map, const char* key,
                                            const std::string& path) {
  auto c = text(map, key, path, true);
  if (!c) return std::nullopt;
  if (*c == "x") return 0;
  if (*c == "y") return 1;
  if (*c == "z") return 2;
  error(map[key], sub(path, key),
        fmt::format("unknown component '{}'{}", *c, suggestion(*c, {"x", "y", "z"})));
  return std::nullopt;
}

}  // namespace velum::io::model_file
