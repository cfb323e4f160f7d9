#pragma once
/// \file scene_selections.h
/// What the names of a shell scene select, in the joined structure's node numbers: the nodes of
/// every [[bc]], [[load]], [[probe]], [[joint]] and [[arc]] entry, the parts and the mesh's named
/// groups. For `flexframe check --picture`, which draws them so that a user sees what a scene
/// selects before running it. The selections are the ones the model builders make
/// (select_nodes on Structure::joined), so the picture shows what a run acts on.

#include <optional>
#include <string>
#include <vector>

#include "core/mesh/shell_mesh.h"
#include "core/scene/scene_context.h"

namespace ff::scene {

/// The nodes one scene entry acts on.
struct EntrySelection {
  std::string table;      ///< "bc", "load", "probe", "joint" or "arc"
  std::size_t index = 0;  ///< the entry's place in its table (bc[index])
  /// "bc[0] clamped", "load[1] pressure", "probe[0] tip_w", "joint[0] revolute to ground"
  std::string label;
  /// what it covers, in words: "33 nodes", "64 quads of 81 nodes", "node 120 (the first of 3
  /// selected)" for a displacement probe, which reads one node
  std::string extent;
  std::vector<int> nodes;  ///< the nodes it acts on, ascending (a displacement probe: its one node)
  std::vector<int> quads;  ///< pressure and surface loads: the quads loaded; empty otherwise
};

struct SceneSelections {
  std::string scene_name;
  mesh::ShellMesh mesh;                 ///< the whole structure (parts joined), reference geometry
  std::vector<std::string> part_names;  ///< [[part]] names in order
  std::vector<int> quad_part;           ///< part index per quad of `mesh`
  std::vector<EntrySelection> entries;  ///< bc, load, probe, joint, arc entries, in that order
};

/// The selections of the shell scene at `path` (with --set `overrides`); nothing for a model
/// without a shell structure (hub_beam). Throws SceneError as load_scene does for what a
/// selection refuses (an empty node set ...); call it on a scene load_scene accepted.
std::optional<SceneSelections> scene_selections(const std::string& path, const std::vector<std::string>& overrides,
                                                const SceneContext& ctx);
/// The same for a scene text held in memory (the window's); `path` names it as for load_scene_text.
std::optional<SceneSelections> scene_selections_of_text(const std::string& text, const std::string& path,
                                                        const std::vector<std::string>& overrides, const SceneContext& ctx);

}  // namespace ff::scene
