#pragma once
/// \file param_editor.h
/// The GUI's scene parameter list, built from the scene's schema and its validated values, so
/// every model (and every key a future model declares) is editable with no GUI change. Edits
/// come out as `--set`-style (key, TOML value) pairs for the solver thread's command queue.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/scene/schema.h"

namespace ff::app::gui {

/// One editable key of a scene.
struct ParamItem {
  std::string key;    ///< what --set takes: "solver.dt", "part[1].thickness"
  std::string group;  ///< table it sits in: "solver", "shell[1]", "" for the top level
  std::string name;   ///< last path segment
  const scene::Schema::KeySpec* spec = nullptr;
  std::string value;  ///< TOML text of the validated value ("" = required but absent)
  std::string where;  ///< "file:line:col", "--set ...", "default" or "absent"
  bool edited = false;  ///< an edit of this session is in effect
};

/// The editable keys of a scene text: every declared key outside arrays of tables, then every key
/// of every element of the arrays the text has, leaving out keys that do not apply to the entry's
/// choices (another generator's dimensions, another selection's point) unless the text gives them.
/// scene.model is left out (it picks the schema). `edited` marks values that differ from
/// `opened_text` (the scene as opened). Throws SceneError when the text does not validate.
std::vector<ParamItem> scene_params(const std::string& text, const std::string& path, const std::string& opened_text);

/// A refusal of the solver thread in a window user's words.
struct Refusal {
  std::string key;   ///< the refused key ("" when not an edit: a load or a reset)
  std::string text;  ///< e.g. "solver.dt = -1 was not applied: expected a number > 0, got -1. ..."
};
/// Rewords a refusal message of the solver thread ("set KEY = VALUE refused:\n--set KEY=VALUE:
/// key 'KEY': why"), which names the CLI's --set syntax, for the window; nullopt for other messages.
std::optional<Refusal> readable_refusal(const std::string& message);

/// The marker of a live key (a green "live" badge), beside the key and in the list's header.
void draw_live_tag();

/// Draws the list (ImGui) and returns the edits made this frame: (key, TOML value text).
class ParamEditor {
 public:
  /// Refills the list; call when the scene, its edits or the solver's answer changed.
  void load(const std::string& text, const std::string& path, const std::string& opened_text);
  std::vector<std::pair<std::string, std::string>> draw();
  const std::string& error() const { return error_; }
  /// The listed keys the scene's schema declares live (an edit changes the running model).
  std::vector<std::string> live_keys() const;
  /// Shows a refused edit's reason under its key (until that key is edited again or cleared).
  void show_refusal(Refusal refusal) { refusal_ = std::move(refusal); }
  void clear_refusal() { refusal_.reset(); }

 private:
  struct Row {
    ParamItem item;
    std::string buffer;  ///< text being edited
    bool flag = false;   ///< booleans
    std::vector<std::string> selected;  ///< string lists with allowed values
  };
  std::vector<Row> rows_;
  std::string filter_;
  std::string error_;
  std::optional<Refusal> refusal_;
};

}  // namespace ff::app::gui
