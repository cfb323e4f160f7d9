#include "core/scene/scene_common.h"

#include <sstream>

#include "core/shell/shell_model.h"

namespace ff::scene {

const std::vector<std::string>& model_names() {
  static const std::vector<std::string> names = {"hub_beam", "shell"};
  return names;
}

void declare_scene_table(Schema& s, const std::string& effects_doc, std::vector<std::string> effects) {
  s.table("scene", "what this scene is and which effects it simulates", true)
      .string("scene.name", "scene name; also the default output folder out/<name>", std::nullopt)
      .string("scene.description", "one line shown in summaries", std::string{})
      .choice("scene.model", "model family", model_names(), std::nullopt)
      .string_list("scene.effects", effects_doc, std::nullopt, std::move(effects));
}

void declare_output_keys(Schema& s, std::vector<std::string> color_fields, bool camera_keys,
                         const std::vector<std::string>& stress_fields) {
  const std::string first = color_fields.front();
  color_fields.push_back("none");
  s.table("output", "what a run writes besides results.h5")
      .boolean("output.frames", "write PNG frames", true)
      .integer("output.frame_every", "render every n-th step", 1, IntRange::closed(1, 1000000))
      .integer("output.width", "frame width", 960, IntRange::closed(64, 8192))
      .integer("output.height", "frame height", 720, IntRange::closed(64, 8192))
      .number("output.deformation_scale", "drawn deformation = scale x true deformation", 1.0,
              Range::left_open(0.0, 1e6));
  if (stress_fields.empty()) {
    s.choice("output.color_field", "field that colours the body", color_fields, first);
  } else {
    // the ply fields depend on the layup: any name here, checked against the run's fields
    std::string names;
    for (const std::string& f : color_fields) names += (names.empty() ? "" : ", ") + f;
    std::string stresses;
    for (const std::string& f : stress_fields) stresses += (stresses.empty() ? "" : ", ") + f;
    s.string("output.color_field",
             "field that colours the body: " + names + ", or a stress field (which turns output.stresses on): " +
                 stresses + "; with a layup of K plies also plyK_sigma1, plyK_sigma2, plyK_tau12 (and tsai_wu, "
                 "plyK_tsai_wu when the plies have strengths); checked once the structure is read",
             first)
        .boolean("output.stresses",
                 "write every stress field of the structure (docs/guide/running.md, stress fields: stresses at the bottom, middle and "
                 "top surfaces, von Mises, principal, the resultants N, M, Q, each ply's) in every frame: results.h5, "
                 "exports, replay --field; also on when output.color_field or a [[probe]] names a stress field",
                 false);
  }
  s.boolean("output.plots", "write plots/*.png at the end", true);
  s.boolean("output.error_bar",
            "estimate every answer metric's discretization error from coarser twins of the run (a coarser mesh, "
            "twice the time step) and print it as a bar (docs/guide/how-accurate.md); --error-bar on|off overrides it",
            true);
  s.choice("output.error_bar_levels",
           "levels per source of error: two (the run and one twin, the element's formal order, safety factor 3), "
           "three (two twins: the observed order, safety factor 1.25, and a flag instead of a number where the "
           "levels are not in the asymptotic range), or auto: three for static, modal and buckling runs with a "
           "part meshed by Gmsh (whose meshes at two sizes are not nested), two for generated meshes and in time, "
           "where a third twin at 4 dt would cost more than the run (docs/guide/how-accurate.md); --error-bar "
           "two|three overrides it for one run",
           {"auto", "two", "three"}, "auto");
  if (!camera_keys) return;
  s.choice("output.view", "camera: iso, front (looking along +y, z up), top (looking down z)", {"iso", "front", "top"},
           "iso")
      .number_list("output.view_center", "point the camera looks at; [] = centre of the mesh", std::vector<double>{}, {},
                   0, 3)
      .number("output.view_radius", "half height of the view in length units; 0 = fit the mesh", 0.0,
              Range::non_negative());
}

void refuse_unknown_color_field(const Document& d, const RunInfo& info) {
  const std::string& name = d.string("output.color_field");
  if (name == "none") return;
  std::string names;
  for (const Quantity& f : info.fields) {
    if (f.name == name) return;
    names += (names.empty() ? "" : ", ") + f.name;
  }
  const bool ply = name.rfind("ply", 0) == 0 || name.find("tsai_wu") != std::string::npos;
  throw SceneError({d.issue("output.color_field", "'" + name + "' is not a field of this run (its fields: " + names +
                                                      ", none)" +
                                                      (ply ? "; the ply fields and tsai_wu follow the structure's "
                                                             "layup: plyK for K up to its most plies, tsai_wu only when "
                                                             "the plies have strengths"
                                                           : ""))});
}

void declare_linear_solver(Schema& s, const std::string& default_doc) {
  s.choice("solver.linear_solver",
           "sparse direct solver of each Newton correction: default (" + default_doc +
               "), umfpack, mumps (nested dissection), sparse_lu (Eigen, no external library), cholmod_llt (statics "
               "only: symmetric positive definite tangents, no follower loads or moments (refused), nothing past a "
               "limit point)",
           {"default", "umfpack", "mumps", "sparse_lu", "cholmod_llt"}, "default");
}

LinearBackend read_linear_solver(const Document& d, LinearBackend preferred) {
  const std::string& name = d.string("solver.linear_solver");
  if (name == "default") return linear_backend_available(preferred) ? preferred : default_linear_backend();
  const std::optional<LinearBackend> b = parse_linear_backend(name);
  if (!b || !linear_backend_available(*b))
    throw SceneError({d.issue("solver.linear_solver", "'" + name + "' is not compiled into this build (umfpack and "
                                                      "cholmod_llt need SuiteSparse, mumps needs libmumps-seq-dev "
                                                      "at configure time)")});
  return *b;
}

OutputSettings read_output(const Document& d, bool camera_keys) {
  OutputSettings o;
  o.frames = d.boolean("output.frames");
  o.frame_every = static_cast<int>(d.integer("output.frame_every"));
  o.width = static_cast<int>(d.integer("output.width"));
  o.height = static_cast<int>(d.integer("output.height"));
  o.deformation_scale = d.number("output.deformation_scale");
  o.color_field = d.string("output.color_field");
  o.plots = d.boolean("output.plots");
  o.error_bar = d.boolean("output.error_bar");
  const std::string& levels = d.string("output.error_bar_levels");
  o.error_bar_levels = levels == "two" ? 2 : levels == "three" ? 3 : 0;
  if (camera_keys) {
    o.view = d.string("output.view");
    o.view_center = d.numbers("output.view_center");
    o.view_radius = d.number("output.view_radius");
    if (!o.view_center.empty() && o.view_center.size() != 3)
      throw SceneError({d.issue("output.view_center", "expected [] or three coordinates")});
  }
  return o;
}

void refuse_impossible_step_count(const Document& d, const std::string& dt_key, const std::string& end_key) {
  const double dt = d.number(dt_key), end = d.number(end_key);
  if (dt > end) throw SceneError({d.issue(dt_key, "the time step must not exceed " + end_key)});
  const double steps = end / dt;  // a double: the quotient may exceed every integer type
  if (!(steps <= kMaxTimeSteps)) {
    std::ostringstream m;
    m << end_key << " / " << dt_key << " = " << end << " / " << dt << " = " << steps << " steps, more than the "
      << kMaxTimeSteps << " a run may take; raise " << dt_key << " or lower " << end_key;
    // at the key the user just changed, when only one of the two came from --set
    const bool end_set = d.where(end_key).rfind("--set", 0) == 0, dt_set = d.where(dt_key).rfind("--set", 0) == 0;
    throw SceneError({d.issue(end_set && !dt_set ? end_key : dt_key, m.str())});
  }
}

void refuse_unworkable_load_steps(const Document& d, int max_steps) {
  const auto from_set = [&](const std::string& k) { return d.where(k).rfind("--set", 0) == 0; };
  // of two keys out of order, the one the user just changed (a --set), else the one given, else the later
  const auto blamed = [&](const std::string& first, const std::string& second) {
    if (from_set(first) != from_set(second)) return from_set(first) ? first : second;
    if (d.present(first) != d.present(second)) return d.present(first) ? first : second;
    return second;
  };
  const double min_step = d.number("solver.min_step"), initial = d.number("solver.initial_step"),
               max_step = d.number("solver.max_step"), end = d.number("solver.end");
  if (initial < min_step)
    throw SceneError({d.issue(blamed("solver.min_step", "solver.initial_step"),
                              "solver.initial_step (" + d.value_text("solver.initial_step") +
                                  ") is smaller than solver.min_step (" + d.value_text("solver.min_step") +
                                  "): load control gives up below min_step, so the first step is never tried; "
                                  "lower solver.min_step or raise solver.initial_step")});
  if (max_step < initial)
    throw SceneError({d.issue(blamed("solver.initial_step", "solver.max_step"),
                              "solver.max_step (" + d.value_text("solver.max_step") +
                                  ") is smaller than solver.initial_step (" + d.value_text("solver.initial_step") +
                                  "): load control never steps beyond max_step, so the first step cannot be taken; "
                                  "raise solver.max_step or lower solver.initial_step")});
  const double steps = end / max_step;  // a double: the quotient may exceed every integer type
  if (!(steps <= max_steps)) {
    std::ostringstream m;
    m << "solver.end / solver.max_step = " << end << " / " << max_step << " = " << steps
      << " steps at the least, more than the " << max_steps << " a load-control path may take; lower solver.end or "
      << "raise solver.max_step";
    const bool at_max = from_set("solver.max_step") && !from_set("solver.end");
    throw SceneError({d.issue(at_max ? "solver.max_step" : "solver.end", m.str())});
  }
}

void refuse_oversized(const Document& d, const SceneContext& ctx, int nodes, double six_dof_fraction,
                      const std::string& key, int index) {
  if (!(ctx.memory_limit_bytes > 0)) return;
  const double need = shell::estimated_peak_bytes(nodes, six_dof_fraction);
  if (need <= ctx.memory_limit_bytes) return;
  std::ostringstream m;
  m.precision(3);
  m << "a run on this mesh (" << nodes << " nodes) would need about " << need / 1e9 << " GB, more than the "
    << ctx.memory_limit_bytes / 1e9 << " GB this machine allows; use a coarser mesh";
  throw SceneError({index < 0 ? d.issue(key, m.str()) : d.issue(key, static_cast<std::size_t>(index), m.str())});
}

void describe_run(const Document& d, const std::string& path, RunInfo& info) {
  info.scene_name = d.string("scene.name");
  info.scene_path = path;
  info.scene_text = d.text();
  for (const std::string& k : d.key_paths()) {
    const std::string v = d.value_text(k);
    if (!v.empty()) info.settings.emplace_back(k, v);
  }
  // the structure's parts and materials (arrays of tables: their keys carry the entry's index)
  for (const char* array : {"material", "part", "junction"})
    if (d.declares_array(array))
      for (std::size_t i = 0; i < d.count(array); ++i)
        for (const std::string& k : d.element_key_paths(array))
          if (d.present(k, i))
            info.settings.emplace_back(std::string(array) + "[" + std::to_string(i) + "]" + k.substr(k.find('.')),
                                       d.value_text(k, i));
  // the scripted events, so a reader of the results sees what happened when
  if (d.count("timeline") > 0)
    for (std::size_t i = 0; i < d.count("timeline"); ++i)
      for (const std::string& k : d.element_key_paths("timeline"))
        if (d.present(k, i))
          info.settings.emplace_back("timeline[" + std::to_string(i) + "]" + k.substr(k.find('.')), d.value_text(k, i));
}

}  // namespace ff::scene
