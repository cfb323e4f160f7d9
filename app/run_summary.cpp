#include "app/run_summary.h"

#include "app/error_bar_run.h"

namespace ff::app {

namespace {
using Json = nlohmann::ordered_json;

// summary.json "mesh_quality": counts, per metric the worst quad (number and name), the median,
// the limit and the quads past it (worst first, at most 20 numbers), and the warnings' sentences
nlohmann::ordered_json mesh_quality_json(const scene::MeshQualityReport& r) {
  using Json = nlohmann::ordered_json;
  Json metrics = Json::object();
  for (int k = 0; k < mesh::quality_metric_count; ++k) {
    const mesh::MetricSummary& s = r.quality.metrics[k];
    const auto m = static_cast<mesh::QualityMetric>(k);
    Json past = Json::array();
    for (std::size_t i = 0; i < s.beyond.size() && i < 20; ++i) past.push_back(s.beyond[i]);
    metrics[mesh::metric_key(m)] = {{"unit", mesh::metric_unit(m)},
                                    {"worst", s.worst_quad >= 0 ? Json(s.worst) : Json()},
                                    {"worst_quad", s.worst_quad},
                                    {"worst_element", s.worst_quad >= 0 ? r.quad_name(s.worst_quad) : ""},
                                    {"typical", s.worst_quad >= 0 ? Json(s.typical) : Json()},
                                    {"limit", s.limit},
                                    {"past_limit", s.beyond.size()},
                                    {"past_limit_quads", past}};
  }
  return {{"quads", r.quality.quad_count}, {"nodes", r.quality.node_count}, {"parts", r.part_names.size()},
          {"poor_quads", r.quality.poor_count()}, {"metrics", metrics}, {"warnings", r.warnings()}};
}
}  // namespace

Json run_summary(const RunSummaryInputs& in) {
  const scene::LoadedScene& scene = *in.scene;
  const RunInfo& info = *in.info;
  const RunResult& result = *in.result;
  const RunOutcome& outcome = result.outcome;
  const OutputPipeline& drawn = *in.pipeline;
  Json metrics = Json::object();
  for (const auto& [k, v] : result.metrics) metrics[k] = v;
  Json metrics_unreached = Json::object();
  for (const auto& [name, why] : in.metrics_unreached) {
    metrics[name] = nullptr;
    metrics_unreached[name] = why;
  }
  Json effect_stats = Json::object();  // only the effects that ran
  for (const EffectStat& e : in.effect_stats) {
    Json one = {{"evaluations", e.evaluations}, {"time_s", e.seconds}};  // NaN (fused, not timed apart): null
    if (!e.included_in.empty()) one["included_in"] = e.included_in;
    effect_stats[e.effect] = one;
  }
  Json outputs = {{"results", "results.h5"},
                  {"frames_dir", "frames"},
                  {"frames", result.frames_rendered},
                  {"plots", in.plot_files},
                  {"movie", result.movie.empty() ? "" : "movie.mp4"},
                  {"export_frames", result.frames_exported}};
  const bool coloured = drawn.color_field >= 0 && result.frames_rendered > 0;
  const Json render_info = {
      {"backend", drawn.render_backend},
      {"gl_renderer", drawn.gl_renderer},
      {"frames_per_second", result.render_seconds > 0 ? result.frames_rendered / result.render_seconds : 0.0},
      {"color_field", coloured ? in.color_field : ""},
      {"color_range", coloured ? Json::array({drawn.color_range[0], drawn.color_range[1]}) : Json::array()},
      {"frame_memory_note", drawn.frame_memory_note}};
  Json events = Json::array();  // what the path did (statics: limit points, bifurcations, turn-backs)
  for (const PathEvent& e : outcome.events)
    events.push_back({{"kind", e.kind}, {"step", e.step}, {"load_factor", e.load_factor}, {"detail", e.detail}});
  // how each mesh file was read (format, what became of triangles, directors, named groups)
  Json mesh_import = Json::object();
  for (const auto& [key, value] : info.settings)
    if (key.rfind("mesh_import", 0) == 0) mesh_import[key] = value;
  if (in.modes)
    outputs["modes"] = {{"animated", in.mode_report->modes_animated},
                        {"frames", in.mode_report->frames},
                        {"frames_per_cycle", kModeFramesPerCycle},
                        {"amplitude_fraction_of_model_size", kModeAmplitudeFraction},
                        {"movies", in.mode_report->movies},
                        {"spectrum_plot", in.mode_report->plot},
                        {"vtu", in.mode_report->vtu}};
  Json summary = {
      {"scene", scene.name},
      {"scene_path", scene.path},
      {"status", to_string(outcome.status)},
      {"reason", outcome.reason},
      {"stop_time", outcome.stop_time},
      {"time_unit", info.time_unit},
      {"wall_time_s", outcome.wall_time_s},
      {"steps", result.totals.steps},
      {"newton_iterations", result.totals.newton_iterations},
      {"jacobian_updates", result.totals.jacobian_updates},
      {"cutbacks", result.totals.cutbacks >= 0 ? Json(result.totals.cutbacks) : Json()},  // null: not counted
      {"steps_per_second", outcome.wall_time_s > 0 ? result.totals.steps / outcome.wall_time_s : 0.0},
      {"effects", info.effects},
      {"metrics", metrics},
      {"metrics_unreached", metrics_unreached},
      {"events", events},
      {"effect_stats", effect_stats},
      {"mesh_import", mesh_import},
      {"outputs", outputs},
      {"render", render_info}};
  if (result.error_bars.on) summary["error_bars"] = error_bars_json(result.error_bars);
  if (result.field_error) {
    summary["field_error"] = field_error_json(*result.field_error);
    summary["field_error"]["picture"] = drawn.refine_picture_drawn ? Json("plots/error_indicator.png") : Json(nullptr);
  }
  if (in.modes) summary["modes"] = modes_json(*in.modes);
  if (scene.mesh_quality) summary["mesh_quality"] = mesh_quality_json(*scene.mesh_quality);
  if (drawn.von_mises >= 0) {  // null node and frame: no stored frame had a finite value
    const StressPeak& peak = drawn.von_mises_peak;
    summary["stresses"] = {{"von_mises_max", peak.value},
                           {"node", peak.node >= 0 ? Json(peak.node) : Json()},
                           {"frame", peak.frame >= 0 ? Json(peak.frame) : Json()},
                           {"step", peak.step >= 0 ? Json(peak.step) : Json()},
                           {"time", peak.frame >= 0 ? Json(peak.time) : Json()},
                           {"load_factor", peak.frame >= 0 ? Json(peak.load_factor) : Json()},
                           {"unit", info.fields[drawn.von_mises].unit}};
  }
  return summary;
}

Json summary_before_any_frame(const std::string& scene_name, const std::string& scene_path, const std::string& reason) {
  return {{"scene", scene_name}, {"scene_path", scene_path}, {"status", "failed"}, {"reason", reason},
          {"steps", 0},          {"metrics", Json::object()}, {"outputs", Json::object()}};
}

Json summary_without_metrics(const std::string& scene_name, const std::string& scene_path, const RunOutcome& o,
                             const std::string& time_unit) {
  return {{"scene", scene_name},      {"scene_path", scene_path},  {"status", to_string(o.status)},
          {"reason", o.reason},       {"stop_time", o.stop_time},   {"time_unit", time_unit},
          {"wall_time_s", o.wall_time_s}, {"steps", o.steps},      {"metrics", Json::object()},
          {"outputs", {{"results", "results.h5"}}}};
}

void write_summary(OutputFolder& folder, const Json& summary) {
  write_text_file(folder.file("summary.json"), summary.dump(2) + "\n");
}

}  // namespace ff::app
