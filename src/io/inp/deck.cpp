// Splits a deck into keyword blocks (deck.hpp) and reads typed data fields.

#include "deck.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>

#include "velum/io/inp_reader.hpp"
#include "velum/io/model_reader.hpp"

namespace velum::io {

InpError::InpError(std::vector<std::string> messages)
    : std::runtime_error([&] {
        std::string s;
        for (const auto& m : messages) {
          if (!s.empty()) s += '\n';
          s += m;
        }
        return s;
      }()),
      messages_(std::move(messages)) {}

namespace inp {
namespace {

constexpr int kMaxIncludeDepth = 16;

std::string trim(std::string_view s) {
  size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return std::string(s.substr(a, b - a));
}

std::vector<std::string> split_fields(std::string_view s) {
  std::vector<std::string> out;
  size_t start = 0;
  while (true) {
    const size_t comma = s.find(',', start);
    out.push_back(trim(s.substr(start, comma == std::string_view::npos ? s.npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return out;
}

// The options of a keyword line: split at the commas outside quotes (a quoted file name may
// hold commas and blanks).
std::vector<std::string> split_options(std::string_view s) {
  std::vector<std::string> out;
  size_t start = 0;
  char quote = 0;
  for (size_t i = 0; i <= s.size(); ++i) {
    if (i < s.size() && quote) {
      if (s[i] == quote) quote = 0;
      continue;
    }
    if (i < s.size() && (s[i] == '"' || s[i] == '\'')) {
      quote = s[i];
      continue;
    }
    if (i == s.size() || s[i] == ',') {
      out.push_back(trim(s.substr(start, i - start)));
      start = i + 1;
    }
  }
  return out;
}

struct Reader {
  Diagnostics& diag;
  std::vector<Keyword> keywords;
  std::vector<std::filesystem::path> open;  // the include chain, for loops
  // The block data lines go to: the last keyword but an *INCLUDE (an included file is read in
  // place, so a file of data lines only continues the block its *INCLUDE stands in); -1 none.
  long block = -1;

  void read(const std::filesystem::path& file, int depth, const Keyword* from) {
    const int fi = static_cast<int>(diag.files.size());
    diag.files.push_back(file.string());
    auto fail = [&](const std::string& text) {
      if (from)
        diag.error(*from, text);
      else
        diag.errors.push_back(fmt::format("{}: {}", file.string(), text));
    };
    namespace fs = std::filesystem;
    std::error_code ec;
    const auto st = fs::status(file, ec);
    if (!fs::exists(st)) return fail(fmt::format("cannot open '{}': no such file", file.string()));
    if (fs::is_directory(st))
      return fail(fmt::format("'{}' is a directory, not an input deck", file.string()));
    if (!fs::is_regular_file(st))
      return fail(fmt::format("'{}' is not a regular file (a device or a pipe?)", file.string()));
    if (fs::file_size(file, ec) > kMaxModelFileBytes)
      return fail(
          fmt::format("'{}' is larger than {} MiB", file.string(), kMaxModelFileBytes >> 20));
    std::ifstream in(file, std::ios::binary);
    if (!in) return fail(fmt::format("cannot open '{}'", file.string()));
    const auto canon = fs::weakly_canonical(file, ec);
    if (std::find(open.begin(), open.end(), canon) != open.end())
      return fail(fmt::format("'{}' includes itself (an *INCLUDE loop)", file.string()));
    open.push_back(canon);
    std::string text;
    int number = 0;
    bool continued = false;  // the last keyword line ended with a comma
    while (std::getline(in, text)) {
      ++number;
      if (!text.empty() && text.back() == '\r') text.pop_back();
      if (text.find('\0') != std::string::npos) {
        diag.errors.push_back(
            fmt::format("{}: a NUL byte: not a text input deck", diag.where(fi, number)));
        break;
      }
      const std::string line = trim(text);
      if (line.rfind("**", 0) == 0) continue;
      if (line.empty()) continue;  // CalculiX skips blank lines; Abaqus refuses them
      if (continued) {
        add_options(keywords.back(), line);
        continued = line.back() == ',';
        continue;
      }
      if (line[0] == '*') {
        Keyword k;
        k.file = fi;
        k.line = number;
        const size_t comma = line.find(',');
        k.name = canonical(std::string_view(line).substr(
            1, comma == std::string::npos ? std::string::npos : comma - 1));
        if (comma != std::string::npos) add_options(k, line.substr(comma + 1));
        continued = line.back() == ',';
        if (k.name == "INCLUDE") {
          keywords.push_back(k);  // kept so that messages can name it
          auto it = k.options.find("INPUT");
          if (it == k.options.end() || it->second.empty()) {
            diag.error(k, "INPUT=file is required");
          } else if (depth >= kMaxIncludeDepth) {
            diag.error(k, fmt::format("more than {} nested includes", kMaxIncludeDepth));
          } else {
            std::string name = it->second;
            if (name.size() >= 2 && (name.front() == '"' || name.front() == '\'') &&
                name.back() == name.front())
              name = name.substr(1, name.size() - 2);
            std::filesystem::path p = name;
            if (p.is_relative()) p = file.parent_path() / p;
            const Keyword include = keywords.back();  // the vector grows while it is read
            read(p, depth + 1, &include);
            continued = false;
          }
          continue;
        }
        keywords.push_back(std::move(k));
        block = static_cast<long>(keywords.size()) - 1;
        continue;
      }
      if (block < 0) {
        diag.errors.push_back(
            fmt::format("{}: a data line outside any keyword block", diag.where(fi, number)));
        continue;
      }
      DataLine d{fi, number, split_fields(line)};
      if (d.fields.size() > 1 && d.fields.back().empty()) d.fields.pop_back();  // "1, 2,"
      keywords[static_cast<size_t>(block)].data.push_back(std::move(d));
    }
    open.pop_back();
  }

  void add_options(Keyword& k, const std::string& text) {
    for (const auto& f : split_options(text)) {
      if (f.empty()) continue;
      const size_t eq = f.find('=');
      const std::string name = canonical(f.substr(0, eq));
      const std::string value = eq == std::string::npos ? "" : trim(f.substr(eq + 1));
      if (k.options.count(name)) diag.error(k, fmt::format("option {} is given twice", name));
      k.options[name] = value;
    }
  }
};

}  // namespace

std::string canonical(std::string_view s) {
  std::string out;
  bool blank = false;
  for (char c : s) {
    if (std::isspace(static_cast<unsigned char>(c))) {
      blank = !out.empty();
      continue;
    }
    if (blank) out += ' ';
    blank = false;
    out += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  }
  return out;
}

std::string Diagnostics::where(int file, int line) const {
  return fmt::format("{}:{}", files.at(static_cast<size_t>(file)), line);
}
void Diagnostics::error(const Keyword& k, const std::string& text) {
  errors.push_back(fmt::format("{}: *{}: {}", where(k.file, k.line), k.name, text));
}
void Diagnostics::error(const Keyword& k, const DataLine& d, const std::string& text) {
  errors.push_back(fmt::format("{}: *{}: {}", where(d.file, d.line), k.name, text));
}
void Diagnostics::warn(const Keyword& k, const std::string& text) {
  warnings.push_back(fmt::format("{}: *{}: {}", where(k.file, k.line), k.name, text));
}
void Diagnostics::warn(const Keyword& k, const DataLine& d, const std::string& text) {
  warnings.push_back(fmt::format("{}: *{}: {}", where(d.file, d.line), k.name, text));
}

std::optional<double> Diagnostics::number(const Keyword& k, const DataLine& d, size_t i,
                                          std::optional<double> fallback) {
  if (i >= d.fields.size() || d.fields[i].empty()) {
    if (!fallback) error(k, d, fmt::format("field {} (a number) is missing", i + 1));
    return fallback;
  }
  std::string s = d.fields[i];
  std::replace_if(
      s.begin(), s.end(), [](char c) { return c == 'd' || c == 'D'; }, 'e');
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0' || !std::isfinite(v) || errno == ERANGE) {
    error(k, d, fmt::format("field {}: '{}' is not a finite number", i + 1, d.fields[i]));
    return std::nullopt;
  }
  return v;
}

std::optional<long> Diagnostics::integer(const Keyword& k, const DataLine& d, size_t i,
                                         std::optional<long> fallback) {
  if (i >= d.fields.size() || d.fields[i].empty()) {
    if (!fallback) error(k, d, fmt::format("field {} (a whole number) is missing", i + 1));
    return fallback;
  }
  const std::string& s = d.fields[i];
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (end == s.c_str() || *end != '\0' || errno == ERANGE) {
    error(k, d, fmt::format("field {}: '{}' is not a whole number", i + 1, s));
    return std::nullopt;
  }
  return v;
}

bool Diagnostics::check_options(const Keyword& k, const std::vector<std::string>& allowed) {
  bool ok = true;
  for (const auto& [name, value] : k.options)
    if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
      error(k,
            fmt::format("option {} is not supported here{}", name,
                        allowed.empty() ? std::string()
                                        : fmt::format(" (known: {})", fmt::join(allowed, ", "))));
      ok = false;
    }
  return ok;
}

std::optional<std::string> Diagnostics::required(const Keyword& k, const std::string& option) {
  auto it = k.options.find(option);
  if (it == k.options.end() || it->second.empty()) {
    error(k, fmt::format("{}= is required", option));
    return std::nullopt;
  }
  return it->second;
}

std::vector<Keyword> read_deck(const std::filesystem::path& file, Diagnostics& diag) {
  Reader r{diag, {}, {}};
  r.read(file, 0, nullptr);
  return std::move(r.keywords);
}

}  // namespace inp
}  // namespace velum::io
