#pragma once
/// \file setup_panel.h
/// The window's "Set up" section: a new problem, the entries of the scene (parts, materials,
/// supports, loads, joints, probes, metrics) with add and remove, material presets, and the nodes
/// picked with the mouse, which an entry's selection can take. It only asks for edits; the
/// solver thread applies them (SimWorker::edit) to the scene text. ImGui, no GL.

#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "app/gui/sim_worker.h"

namespace ff::app::gui {

/// Nodes picked with the mouse (click toggles a node, shift-drag adds a box) and which entries'
/// selections are shown on the body.
struct PickState {
  bool picking = false;  ///< clicks pick nodes instead of probing
  std::set<int> nodes;
  std::string shown = "all";  ///< "all", "none" or an entry "bc[0]"
};

/// An edit the panel asks for.
struct SetupRequest {
  std::string what;                        ///< "add bc", "remove load[1]", ...
  SimWorker::DraftOp op;                   ///< set when it edits the scene text
  std::optional<std::string> new_problem;  ///< "static" or "dynamic": a new problem instead
};

/// An entry of [[table]] from its template, with `fields` (key, value as --set takes it).
SetupRequest add_entry(const std::string& table, std::vector<std::pair<std::string, std::string>> fields = {});
/// Entry `index` of [[table]] removed.
SetupRequest remove_entry(const std::string& table, std::size_t index);
/// material[index] set to the preset `preset` (material_presets()).
SetupRequest material_preset(std::size_t index, const std::string& preset);

/// The edit that makes entry `entry` ("bc[0]") select exactly `nodes` (select = "nodes").
SetupRequest use_picked_nodes(const std::string& entry, const std::set<int>& nodes);

/// The edit that makes entry `entry` select the edge `edge` of patch `patch` (select = "patch_edge").
SetupRequest use_patch_edge(const std::string& entry, const std::string& patch, const std::string& edge);

/// The nodes to highlight for `shown` ("all", "none", "bc[0]") from the entries' selections;
/// "all" leaves out entries that act on every node of the structure.
std::vector<int> shown_nodes(const WorkerStatus& status, const std::string& shown);

class SetupPanel {
 public:
  /// Re-reads the entries from the scene text (call when it changed).
  void load(const WorkerStatus& status);
  std::vector<SetupRequest> draw(const WorkerStatus& status, PickState& pick);

 private:
  struct Entry {
    std::string table;
    std::size_t index = 0;
    std::string label;  ///< "bc[0] clamped, plane: 9 nodes"
    bool selects = false;  ///< has a node selection (bc, load, probe, joint)
  };
  std::vector<Entry> entries_;
  std::vector<std::string> addable_;
  int add_choice_ = 0;
  std::string error_;
};

}  // namespace ff::app::gui
