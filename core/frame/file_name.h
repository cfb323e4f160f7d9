#pragma once
/// \file file_name.h
/// The one check that a name read from a scene or a results file must pass before it becomes a
/// file or folder name (a scene's output folder out/<name>, a probe's plot plots/<name>.png, a
/// stored scene name's export/<name>.pvd). A name that passes is one plain component: it cannot
/// leave the folder it is placed in, hide as "." or "..", or carry a byte a file name or a
/// manifest line cannot hold.

#include <string>

namespace ff {

/// Longest name accepted: with ".png" or "_modes.pvd" added it stays far below NAME_MAX (255).
inline constexpr std::size_t kMaxFileNameBytes = 200;

/// Why `name` cannot be one plain file name ("is empty", "contains '..'", ...), or "" when it can.
inline std::string file_name_problem(const std::string& name) {
  if (name.empty()) return "is empty";
  if (name.size() > kMaxFileNameBytes) return "is longer than " + std::to_string(kMaxFileNameBytes) + " bytes";
  if (name == "." || name == "..") return "is '" + name + "', which names a folder, not a file";
  if (name.find("..") != std::string::npos) return "contains '..'";
  for (const char c : name) {
    if (c == '/' || c == '\\') return std::string("contains the path separator '") + c + "'";
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return "contains a control character";
  }
  return "";
}

}  // namespace ff
