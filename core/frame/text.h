#pragma once
/// \file text.h
/// The small text helpers every layer shares, one copy each: numbers in messages and tables,
/// and trimming. (Numbers written back into a scene, where they must read back exactly, are
/// scene::text::number's: the shortest text that does.)

#include <cstdio>
#include <string>
#include <string_view>

namespace ff {

/// `v` with `digits` significant digits, as printf's %g: "0.30797", "1e-05", "2215.28".
inline std::string significant(double v, int digits = 6) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*g", digits, v);
  return text;
}

/// `s` without the spaces, tabs, carriage returns and line feeds at either end.
inline std::string trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string_view::npos) return "";
  const auto last = s.find_last_not_of(" \t\r\n");
  return std::string(s.substr(first, last - first + 1));
}

}  // namespace ff
