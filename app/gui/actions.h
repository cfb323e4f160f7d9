#pragma once
/// \file actions.h
/// Scripted GUI sessions (`flexframe gui --actions FILE`): one action per line,
///   run | pause | step [N] | reset | set KEY VALUE | wait SECONDS | screenshot FILE |
///   probe NODE | save FILE | export FILE | redraws | quit
/// (`redraws` prints "redraws N", the window frames drawn so far: an idle window draws none.)
/// Blank lines and lines starting with '#' are skipped. No GL or ImGui here (unit tested).

#include <stdexcept>
#include <string>
#include <vector>

namespace ff::app::gui {

struct Action {
  enum class Kind { run, pause, step, reset, set, wait, screenshot, probe, save, export_png, redraws, quit };
  Kind kind = Kind::run;
  long long count = 1;   ///< step: solver steps; probe: node index
  double seconds = 0.0;  ///< wait
  std::string key;       ///< set
  std::string text;      ///< set: value (TOML text, rest of the line); screenshot/save/export: path
  std::string file;      ///< where it was read from, for messages
  int line = 0;
  /// "actions.txt:3"
  std::string where() const { return file + ":" + std::to_string(line); }
};

/// A bad line: what() is "FILE:LINE: message".
struct ActionError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Parses the text of an actions file; throws ActionError at the first bad line.
std::vector<Action> parse_actions(const std::string& text, const std::string& file_name);
/// Reads and parses FILE; an unreadable file is an ActionError too.
std::vector<Action> read_actions(const std::string& path);

}  // namespace ff::app::gui
