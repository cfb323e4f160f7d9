#pragma once
/// \file scene_draft.h
/// Setting a problem up in the window: the scene is a TOML text held in memory, and every
/// set-up action (a new problem, an entry added or removed, a key set, a generator or selection
/// switched, a material preset, a live edit) turns it into a new text. The solver thread builds
/// the new text; if it refuses it, the old text stays. So the text is at every moment the scene
/// that reproduces what the window runs, and Save writes it. No GL or ImGui here (unit tested).

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/scene/schema.h"

namespace ff::app::gui {

/// A new text and, in words, what the edit did besides the obvious ("dropped part[0].polar_end:
/// it belongs to generator = spherical_cap"); "" when nothing more.
struct DraftEdit {
  std::string text;
  std::string note;
};

/// The text of a new problem: one 1 m x 1 m steel plate (8 x 8 elements, 10 mm), no supports yet;
/// a static one has a 1 N force at the far corner and a probe of its deflection (statics are built
/// only with a load, and need a probe). `analysis` is "static" (load control) or "dynamic" (time stepping with
/// gravity); `name` is scene.name. std::invalid_argument for another analysis.
std::string new_scene_text(const std::string& analysis, const std::string& name);

/// The text of a new static problem whose one part is the mesh or CAD file `mesh_path` (written as
/// given: pass an absolute path so the text works wherever it is saved), named `name`: a file
/// dropped on the window.
std::string mesh_scene_text(const std::string& mesh_path, const std::string& name);

/// The arrays of tables the window can add entries to for the scene text's model, in the order
/// a problem is set up: part, material, bc, load, joint, probe, metric (those its schema has).
std::vector<std::string> addable_tables(const scene::Schema& schema);

/// `text` with a new [[table]] entry from a template that validates on the new problem's plate:
/// a part (a plate beside the others), a material, a clamped edge x = 0, a tip force, a joint to
/// the ground, a probe of the tip deflection, a metric of a probe's final value. Names are made
/// unique. `fields` (key, value as --set takes it: a bare word is a string) replace or add
/// template keys.
/// std::invalid_argument for a table without a template.
DraftEdit with_entry_added(const std::string& text, const std::string& path, const std::string& table,
                           const std::vector<std::pair<std::string, std::string>>& fields = {});

/// `text` without entry `index` of [[table]]. std::invalid_argument when it does not exist or is
/// the only entry of a table that needs one (the last part, the last material).
DraftEdit with_entry_removed(const std::string& text, const std::string& path, const std::string& table,
                             std::size_t index);

/// `text` with `key` = `value` (as --set takes them). When `key` is a choice other keys depend on
/// (part[i].generator, bc[i].select, ...), the keys of that entry that no longer apply are dropped
/// and, for a generator, the dimensions it needs are added at their defaults; the note says which.
/// Throws SceneError when the value does not validate.
DraftEdit with_key_set(const std::string& text, const std::string& path, const std::string& key,
                       const std::string& value);

/// A named material from the window's list of presets.
struct MaterialPreset {
  std::string name;   ///< "steel", "aluminium", "CFRP ply (T300/5208)"
  std::string about;  ///< where its numbers come from
  std::vector<std::pair<std::string, std::string>> keys;  ///< [[material]] keys, TOML values
};
const std::vector<MaterialPreset>& material_presets();

/// `text` with material[index] set to preset `preset` (its thickness and name kept); the keys of
/// the other kind (isotropic against orthotropic) are dropped. std::invalid_argument for an
/// unknown preset or entry.
DraftEdit with_material_preset(const std::string& text, const std::string& path, std::size_t index,
                               const std::string& preset);

/// `text` with a live edit `key` = `value` made at time (or load factor) `at` > 0 of a run written
/// in: a [[timeline]] entry at `at` in its place among the others (or merged into one at the same
/// time), so a run of the text changes the model at the same step as the window did.
/// Throws SceneError when the key has no timeline form.
DraftEdit with_live_edit(const std::string& text, const std::string& path, const std::string& key,
                         const std::string& value, double at);

/// The text to save as `save_path`: scene.name becomes the file's stem (its runs get an output
/// folder of their own), and when it differs from `opened_text` a first comment says it was set
/// up in the window from `opened_from` and that the comments below describe that scene.
/// std::invalid_argument when the stem cannot be an output folder name.
std::string text_to_save(const std::string& text, const std::string& path, const std::string& save_path,
                         const std::string& opened_text, const std::string& opened_from);

}  // namespace ff::app::gui
