#pragma once
/// Keys and reading shared by every model's scene schema. Below the models and the registry
/// (scene.h): nothing here knows which models there are beyond their names.
#include <string>
#include <vector>

#include "core/frame/frame.h"
#include "core/scene/output_settings.h"
#include "core/scene/scene_context.h"
#include "core/scene/schema.h"
#include "core/solve/sparse_solver.h"

namespace ff::scene {

/// The values of scene.model, one per model in the registry (scene.cpp, model_kinds(), which
/// checks that its entries are these names in this order).
const std::vector<std::string>& model_names();

/// [scene]: name, description, model, and the model's effects list.
void declare_scene_table(Schema& s, const std::string& effects_doc, std::vector<std::string> effects);
/// [output]: frames, cadence, size, deformation scale, colour field, plots (and camera keys if asked).
/// With `stress_fields` (the shell analyses): output.stresses, and output.color_field takes any
/// name, the fixed `color_fields` or a stress field, which depend on the structure's layup:
/// refuse_unknown_color_field checks it once the run's fields are known.
void declare_output_keys(Schema& s, std::vector<std::string> color_fields, bool camera_keys,
                         const std::vector<std::string>& stress_fields = {});
/// Refuses, at output.color_field, a name that is neither "none" nor one of the run's fields,
/// naming the fields it has.
void refuse_unknown_color_field(const Document& d, const RunInfo& info);
/// OutputSettings from a document declared with declare_output_keys.
OutputSettings read_output(const Document& d, bool camera_keys);
/// The most time steps a scene may ask for: beyond it no run could finish (10^9 steps at 10^5
/// steps/s is about 3 hours of the fastest model) and step counters near 2^53 lose exactness.
inline constexpr double kMaxTimeSteps = 1e9;
/// Refuses, at `dt_key`, a time step larger than the end time or one that needs more than
/// kMaxTimeSteps steps to reach it (the count is in the message); `check` sees it as `run` would.
void refuse_impossible_step_count(const Document& d, const std::string& dt_key, const std::string& end_key);
/// Refuses load-control steps (solver.initial_step, max_step, min_step, end) a path cannot take,
/// before it starts: unless min_step <= initial_step <= max_step (at whichever key of a pair the
/// --set changed, else the later one in that order), and a solver.end that max_step cannot reach
/// within `max_steps` steps (the path's budget; at solver.end, or max_step when only it was set).
void refuse_unworkable_load_steps(const Document& d, int max_steps);
/// Refuses, at `key` (element `index` of an array of tables, or a plain key when index < 0), a
/// shell run whose estimated peak memory (shell::estimated_peak_bytes) exceeds the context's
/// limit; the message gives both figures.
void refuse_oversized(const Document& d, const SceneContext& ctx, int nodes, double six_dof_fraction,
                      const std::string& key, int index = -1);
/// solver.linear_solver: the sparse direct solver of every Newton correction (both shell models);
/// `default_doc` says what "default" means for the model.
void declare_linear_solver(Schema& s, const std::string& default_doc);
/// The backend asked for ("default": `preferred` when compiled in, else default_linear_backend());
/// refuses, at the key, one that is not compiled into this build.
LinearBackend read_linear_solver(const Document& d, LinearBackend preferred = default_linear_backend());
/// Scene name, path, text and every effective setting into a RunInfo.
void describe_run(const Document& d, const std::string& path, RunInfo& info);

}  // namespace ff::scene
