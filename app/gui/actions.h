#pragma once
/// \file actions.h
/// Scripted GUI sessions (`flexframe gui --actions FILE`): one action per line,
///   run | pause | step [N] | reset | set KEY VALUE | wait SECONDS | screenshot FILE |
///   probe NODE | save FILE | export FILE | redraws | quit
/// and, to set a problem up (app/gui/scene_draft.h):
///   new static|dynamic | open FILE | add TABLE [KEY=VALUE ...] | remove TABLE[I] |
///   preset material[I] NAME | pick NODE... | pick-box X0 Y0 X1 Y1 | pick-clear | use-pick TABLE[I] |
///   use-edge TABLE[I] PATCH EDGE |
///   click X Y | show all|none|TABLE[I] | wait-end | metrics | view scene|iso|top|front|side |
///   mode N|off
/// (`wait-end` waits until the run has ended; `metrics` prints "metric NAME = VALUE" for each metric of the run, which must have ended.)
/// (click and pick-box take pixels of the 3D view, origin top left, as a mouse would.)
/// (`mode N` animates mode N of an eigen-analysis whose run has ended, as the Modes list does, and
/// prints "mode N: VALUE"; `mode off` shows the run's frames again.)
/// (`redraws` prints "redraws N", the window frames drawn so far: an idle window draws none.)
/// Blank lines and lines starting with '#' are skipped. No GL or ImGui here (unit tested).

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ff::app::gui {

struct Action {
  enum class Kind {
    run, pause, step, reset, set, wait, screenshot, probe, save, export_png, redraws, quit,
    new_problem, open, add, remove, preset, pick, pick_box, pick_clear, use_pick, use_edge, click, show, wait_end, metrics, view, mode
  };
  Kind kind = Kind::run;
  long long count = 1;   ///< step: solver steps; probe: node index; remove/preset/use-pick/show: entry index;
                         ///< mode: its number (0 = off)
  double seconds = 0.0;  ///< wait
  std::string key;       ///< set: the key; add/remove/use-pick/show: the table ("" for show all|none)
  std::vector<std::pair<std::string, std::string>> fields;  ///< add: KEY=VALUE (value as --set takes it)
  std::vector<long long> nodes;  ///< pick: node numbers
  std::string patch, edge;       ///< use-edge
  std::vector<double> pixels;    ///< click: x, y; pick-box: x0, y0, x1, y1
  std::string text;      ///< set: value (TOML text, rest of the line); screenshot/save/export/open: path;
                         ///< new: static|dynamic; preset: its name; show: all|none
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
