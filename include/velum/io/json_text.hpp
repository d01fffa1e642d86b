// A text as a JSON string (quoted; quotes, backslashes and control characters escaped): how
// summary.json, the results folder's first summary and patterns.json write names, paths and
// messages.
#pragma once

#include <fmt/format.h>

#include <string>

namespace velum {

inline std::string json_string(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\')
      o += '\\', o += c;
    else if (c == '\n')
      o += "\\n";
    else if (static_cast<unsigned char>(c) < 0x20)
      o += fmt::format("\\u{:04x}", static_cast<int>(c));
    else
      o += c;
  }
  return o + "\"";
}

}  // namespace velum
