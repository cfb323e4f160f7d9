#pragma once
/// \file scene.h
/// Scene file -> validated Document -> Simulation + output settings. Bad input throws
/// ff::scene::SceneError naming file, line, key and what was expected.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/model/simulation.h"
#include "core/scene/mesh_quality_report.h"
#include "core/scene/output_settings.h"
#include "core/scene/scene_context.h"
#include "core/scene/schema.h"

namespace ff::scene {

struct LoadedScene {
  std::string name;
  std::string path;
  const Schema* schema = nullptr;  ///< what the scene was validated against (its live keys)
  std::unique_ptr<Simulation> simulation;
  OutputSettings output;
  /// The shell structure's mesh quality report (core/scene/mesh_quality_report.h); none for a
  /// model without a shell mesh (hub_beam).
  std::optional<MeshQualityReport> mesh_quality;
  /// What the scene's builder accepted but warns about (SceneContext::warnings), each a located
  /// "file:line:column: key '...': ..." line: `check` prints them, `run` writes them to stderr.
  std::vector<std::string> warnings;
};

/// One kind of model a scene can name in `scene.model`: the registry that load_scene, the
/// reference and the editors read (core/scene/scene.cpp, model_kinds()). A new model is one line
/// there plus its schema and builder (core/scene/<model>_scene.{h,cpp}).
struct ModelKind {
  std::string name;         ///< the value of scene.model
  /// the value of scene.analysis for the analyses of one model (the shell structure: "static",
  /// "dynamic"); "" for a model with one analysis of its own (hub_beam)
  std::string analysis;
  std::string description;  ///< one line
  const Schema& (*schema)();
  std::string end_key;      ///< the key that ends a run (its timeline's range)
  bool camera_keys;         ///< its [output] has view, view_center, view_radius
  std::unique_ptr<Simulation> (*build)(const Document& d, const std::string& path, const SceneContext& ctx);
  /// The estimated peak memory [bytes] of a run of a validated document, from its keys without
  /// building the model (estimated_run_bytes); 0 when unknown (a mesh file that cannot be read).
  double (*estimated_bytes)(const Document& d, const std::string& path, const SceneContext& ctx);
};
const std::vector<ModelKind>& model_kinds();
/// The kind named `name` (with scene.analysis = `analysis` for a model of several analyses), or
/// nullptr.
const ModelKind* find_model(const std::string& name, const std::string& analysis = "");
/// The schema a scene file is validated against, picked by its `scene.model` (the hub-beam
/// schema when the file cannot be read or parsed; validating with it then reports why).
/// Editors (the GUI's parameter list) read the keys, kinds, ranges and docs from it.
const Schema& scene_schema(const std::string& path);

/// The schema of a scene text, picked by its `scene.model` as scene_schema() does for a file.
const Schema& schema_for_text(const std::string& text);

/// The camera path of a scene text (e.g. /run/scene_text of a results file), validated against
/// its model's schema; empty when the text has no timeline. Throws SceneError when invalid.
std::vector<CameraKey> camera_path_from_text(const std::string& text, const std::string& file_name);
/// Every `file` a [[part]] of the scene text names, as written (relative to the scene's folder
/// unless absolute); none when the text is not TOML. What a study's resume fingerprints besides
/// the scene itself.
std::vector<std::string> part_files_in_text(const std::string& text, const std::string& file_name);

/// Markdown reference of every scene key of every model (docs/reference/scene-keys.md).
std::string scene_reference_markdown();

/// Reads, validates and builds a scene. `overrides` are "key=value" from --set; `ctx` brings what
/// the program around provides (a mesh file reader).
LoadedScene load_scene(const std::string& path, const std::vector<std::string>& overrides = {},
                       const SceneContext& ctx = {});
/// load_scene on a scene text held in memory (the window's scene being set up). `path` names it in
/// messages, and relative mesh files are read from its folder, as for a file at `path`.
LoadedScene load_scene_text(const std::string& text, const std::string& path,
                            const std::vector<std::string>& overrides = {}, const SceneContext& ctx = {});

/// A live edit of the scene's running model (the GUI's `set` of a live key): `value` validated
/// against the scene's schema (validate_live), then handed typed to Simulation::change_live.
/// Returns "" when the model took it (from its next step), otherwise why not: the SceneError
/// text for a key that is not live or a value that does not validate, or the model's reason.
std::string change_live(LoadedScene& scene, const std::string& key, const std::string& value);

/// The estimated peak memory [bytes] of a run of the scene, from its keys (no model is built; a
/// mesh file is read for its node count): the figure `check` and `run` compare with the memory
/// limit, for callers that run several scenes side by side (`study --jobs`). 0 when the scene does
/// not validate (its run reports why).
double estimated_run_bytes(const std::string& path, const std::vector<std::string>& overrides = {},
                           const SceneContext& ctx = {});

/// Validation only (for `flexframe check`): also builds the model as far as a run would refuse it
/// at start-up, so numerical set-up errors (e.g. an EFG support too small for its basis at any
/// point where the matrices evaluate it) are found too, but not what a valid scene only needs to
/// run (the hub-beam's dense matrices: built at the run's start). Returns a one-line description.
std::string check_scene(const std::string& path, const std::vector<std::string>& overrides = {},
                        const SceneContext& ctx = {});
/// What `flexframe check` prints: check_scene's line, then, for a shell structure, its mesh
/// quality report (counts, worst and typical per metric, "warning: " lines for poor quads), then
/// the scene's own warnings ("warning: " lines, LoadedScene::warnings).
std::string check_scene_report(const std::string& path, const std::vector<std::string>& overrides = {},
                               const SceneContext& ctx = {});

}  // namespace ff::scene
