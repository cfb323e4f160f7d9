#include "app/error_bar_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>

#include "app/io/mesh_import.h"
#include "core/model/run_loop.h"
#include "core/scene/discretization_twins.h"
#include "core/scene/scene.h"

namespace ff::app {
namespace {

// the formal orders of error_bars.md §1: displacements and eigenvalues of the CB shell, and the
// generalized-alpha step, are second order
constexpr double kFormalOrder = 2.0;

std::map<std::string, int> event_counts(const std::vector<PathEvent>& events) {
  std::map<std::string, int> n;
  for (const PathEvent& e : events) ++n[e.kind];
  return n;
}

std::string events_text(const std::map<std::string, int>& n) {
  if (n.empty()) return "none";
  std::string s;
  for (const auto& [kind, count] : n) s += (s.empty() ? "" : ", ") + std::to_string(count) + " " + kind;
  return s;
}

TwinRun run_twin(const scene::TwinPlan& plan, const std::string& path, const std::vector<std::string>& overrides,
                 const std::atomic<bool>& stop) {
  TwinRun t;
  t.name = plan.name;
  t.description = plan.description;
  t.planned_ratio = plan.mesh_ratio;
  const auto wall0 = std::chrono::steady_clock::now();
  try {
    std::vector<std::string> all = overrides;
    all.insert(all.end(), plan.overrides.begin(), plan.overrides.end());
    all.push_back("output.error_bar=false");  // a twin's own error indicator field is never read
    scene::LoadedScene twin = scene::load_scene(path, all, io::scene_context(&stop));
    if (twin.mesh_quality) t.elements = twin.mesh_quality->quality.quad_count;
    t.info = twin.simulation->info();
    RunLoop loop(*twin.simulation);
    const RunOutcome o = loop.run([&t](Frame&& f) { t.history.add(f); }, stop);
    t.status = o.status;
    t.reason = o.reason;
    t.events = event_counts(o.events);
    t.metrics = twin.simulation->metrics();
    t.points = twin.simulation->metric_points();
    if (const ModeSet* modes = twin.simulation->modes()) t.modes = *modes;
  } catch (const std::exception& e) {  // a twin the scene's keys refuse (e.g. a cylinder of too few elements)
    t.status = RunStatus::failed;
    t.reason = std::string("the twin could not be built: ") + e.what();
  }
  t.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return t;
}

const std::array<double, 3>* point_of(const std::vector<std::pair<std::string, std::array<double, 3>>>& points,
                                      const std::string& metric) {
  for (const auto& [name, x] : points)
    if (name == metric) return &x;
  return nullptr;
}

// the diagonal of the reference mesh's bounding box (0 without a mesh)
double model_diagonal(const FrameMesh& mesh) {
  const std::vector<double>& p = mesh.reference_points;
  if (p.size() < 3) return 0.0;
  std::array<double, 3> lo{p[0], p[1], p[2]}, hi = lo;
  for (std::size_t i = 0; i + 2 < p.size(); i += 3)
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], p[i + c]), hi[c] = std::max(hi[c], p[i + c]);
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

// For every point of `coarse` the index of the point of `fine` at the same place (within `tolerance`),
// or -1: a twin's nodes at half the counts are every other node of the run's
std::vector<int> common_points(const std::vector<double>& fine, const std::vector<double>& coarse, double tolerance) {
  // the fine points sorted by x: each coarse point looks only at those within the tolerance in x
  std::vector<int> by_x(fine.size() / 3);
  for (std::size_t i = 0; i < by_x.size(); ++i) by_x[i] = static_cast<int>(i);
  std::sort(by_x.begin(), by_x.end(), [&](int a, int b) { return fine[3 * a] < fine[3 * b]; });
  std::vector<int> at(coarse.size() / 3, -1);
  for (std::size_t j = 0; j < at.size(); ++j) {
    const double* p = &coarse[3 * j];
    auto it = std::lower_bound(by_x.begin(), by_x.end(), p[0] - tolerance,
                               [&](int i, double x) { return fine[3 * i] < x; });
    for (; it != by_x.end() && fine[3 * *it] <= p[0] + tolerance; ++it) {
      const double* q = &fine[3 * *it];
      if (std::abs(q[1] - p[1]) <= tolerance && std::abs(q[2] - p[2]) <= tolerance) {
        at[j] = *it;
        break;
      }
    }
  }
  return at;
}

// The modal assurance criterion of two mode shapes over the points they share (error_bars.md §5):
// 1 for the same shape, 0 for orthogonal ones
double mac(const Mode& run_mode, const Mode& twin_mode, const std::vector<int>& shared) {
  double ab = 0, aa = 0, bb = 0;
  for (std::size_t j = 0; j < shared.size(); ++j) {
    if (shared[j] < 0) continue;
    for (int c = 0; c < 3; ++c) {
      const double a = run_mode.displacement[3 * static_cast<std::size_t>(shared[j]) + c];
      const double b = twin_mode.displacement[3 * j + c];
      ab += a * b, aa += a * a, bb += b * b;
    }
  }
  return aa > 0 && bb > 0 ? ab * ab / (aa * bb) : 0.0;
}

// The twin's value for one of the run's modes: its mode of the largest MAC with the run's (so that
// modes that change order between the meshes are compared with themselves), unless the run's mode
// shares its value with a neighbour (a double eigenvalue, whose shapes are any mix of the pair:
// then by number). *note says when the pairing differs from the numbers; nullopt with *flag set
// when no twin mode is like the run's.
std::optional<double> paired_mode_value(const ModeSet& run_modes, const TwinRun& twin, int number,
                                        const std::vector<int>& shared, std::string* flag, std::string* note) {
  const Mode* run_mode = nullptr;
  for (const Mode& m : run_modes.modes)
    if (m.number == number) run_mode = &m;
  if (!run_mode || !twin.modes) return std::nullopt;
  // the shape as the shared points see it: a mode whose nodal lines run through them (the (1,3)
  // modes of a plate on a 4 x 4 twin's grid) is nearly zero there, and its MAC with anything says
  // nothing; then by number
  double shared_sq = 0, all_sq = 0;
  std::size_t shared_count = 0;
  for (double d : run_mode->displacement) all_sq += d * d;
  for (int i : shared)
    if (i >= 0) {
      ++shared_count;
      for (int c = 0; c < 3; ++c) shared_sq += std::pow(run_mode->displacement[3 * static_cast<std::size_t>(i) + c], 2);
    }
  const double points = static_cast<double>(run_mode->displacement.size() / 3);
  if (shared_count == 0 || shared_sq / shared_count < 0.05 * all_sq / points) return std::nullopt;
  for (const Mode& m : run_modes.modes)  // a double eigenvalue: its shapes are not unique
    if (&m != run_mode && !m.rigid_body && std::abs(m.value - run_mode->value) <= 1e-3 * std::abs(run_mode->value))
      return std::nullopt;
  const Mode* best = nullptr;
  double best_mac = -1;
  for (const Mode& m : twin.modes->modes) {
    if (m.rigid_body) continue;
    const double v = mac(*run_mode, m, shared);
    if (v > best_mac) best_mac = v, best = &m;
  }
  if (!best) return std::nullopt;
  char text[200];
  if (best_mac < 0.5) {
    std::snprintf(text, sizeof text, "the %s twin has no mode like the run's mode %d (largest MAC %.2f)",
                  twin.name.c_str(), number, best_mac);
    *flag = text;
    return std::nullopt;
  }
  if (best->number != number) {
    std::snprintf(text, sizeof text, "paired with the %s twin's mode %d by its shape (MAC %.2f): the modes change order",
                  twin.name.c_str(), best->number, best_mac);
    *note = text;
  }
  return best->value;
}

const TwinRun* twin_named(const std::vector<TwinRun>& twins, const std::string& name) {
  for (const TwinRun& t : twins)
    if (t.name == name) return &t;
  return nullptr;
}

// r of (R5) for a surface mesh (d = 2), or 0 when the twin is not coarser
double mesh_ratio(int fine_elements, int coarse_elements) {
  if (fine_elements <= 0 || coarse_elements <= 0 || coarse_elements >= fine_elements) return 0.0;
  return std::sqrt(static_cast<double>(fine_elements) / coarse_elements);
}

// why `twin` cannot stand beside the run for a metric read off its path, or "" (error_bars.md §6)
std::string twin_problem(const TwinRun& twin, const RunOutcome& run) {
  if (twin.status != RunStatus::completed)
    return "the " + twin.name + " twin ended " + std::string(to_string(twin.status)) + " where the run completed (" +
           twin.reason + ")";
  const std::map<std::string, int> run_events = event_counts(run.events);
  if (twin.events != run_events)
    return "the " + twin.name + " twin's path differs in kind: the run had " + events_text(run_events) +
           ", the twin " + events_text(twin.events);
  return "";
}

std::string pct(double x) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2g %%", 100 * x);
  return b;
}

}  // namespace

const MetricError* ErrorBarReport::find(const std::string& metric) const {
  for (const MetricError& m : metrics)
    if (m.metric == metric) return &m;
  return nullptr;
}

ErrorBarReport estimate_error_bars(const std::string& scene_path, const std::vector<std::string>& overrides,
                                   const Simulation& run, const RunOutcome& outcome, double setup_wall_s,
                                   int run_elements, int levels, const std::optional<FieldErrorEstimate>& field_error,
                                   const std::atomic<bool>& stop) {
  ErrorBarReport r;
  r.on = true;
  r.run_wall_s = outcome.wall_time_s + setup_wall_s;
  const scene::TwinPlans plans = scene::discretization_twins(scene_path, overrides, levels);
  r.levels = plans.levels;
  r.local_time = plans.local_time;
  r.missing = plans.missing;
  // a mesh no twin can coarsen (a fixed mesh file) still has the field indicator: said as such, the
  // energy-norm error of the whole solution, not a bar of the metric (how-accurate.md)
  if (field_error)
    for (std::string& why : r.missing)
      if (why.rfind("no mesh estimate", 0) == 0) {
        char text[160];
        std::snprintf(text, sizeof text,
                      "; the field indicator alone puts the solution's energy-norm error at %.2g %% "
                      "(summary.json \"field_error\"), not a bar of this metric",
                      100 * field_error->relative_energy_error);
        why += text;
      }
  for (const scene::TwinPlan& plan : plans.twins) {
    if (stop) break;
    r.twins.push_back(run_twin(plan, scene_path, overrides, stop));
    r.twins_wall_s += r.twins.back().wall_s;
    if (r.twins.back().status == RunStatus::interrupted) r.interrupted = true;
  }
  if (stop) r.interrupted = true;
  for (TwinRun& t : r.twins) {
    t.problem = twin_problem(t, outcome);
    if (t.problem.empty())
      t.ratio = t.name == "time"   ? 2.0
                : t.name == "mesh" ? (t.planned_ratio > 0 ? t.planned_ratio : mesh_ratio(run_elements, t.elements))
                                   : 0.0;
  }

  // one ladder of levels per source, finest first: the time step on the run's mesh; the mesh at the
  // run's step (statics, eigen) or at 2 dt from the time twin down (dynamics, (R8))
  struct Rung {
    const TwinRun* twin;  // null: the run itself
    int elements;
    double h = 0.0;       // its mesh's h over the run's where the plan knows it (1 for the run's own mesh); 0: not known
  };
  struct Ladder {
    std::string source;
    std::vector<Rung> rungs;
    bool known_ratio;  // time: 2 per rung; mesh: from the element counts (R5)
  };
  std::vector<Ladder> ladders;
  if (const TwinRun* t = twin_named(r.twins, "time")) {
    Ladder time{"time", {{nullptr, run_elements, 1.0}, {t, run_elements, 1.0}}, true};
    if (const TwinRun* t4 = twin_named(r.twins, "time_coarser")) time.rungs.push_back({t4, run_elements, 1.0});
    ladders.push_back(time);
  }
  const bool at_2dt = plans.dynamic && !plans.local_time;  // (R8); with (R9) the mesh twin runs at the run's dt
  const std::string suffix = at_2dt ? "_at_2dt" : "";
  const TwinRun* mesh_top = at_2dt ? twin_named(r.twins, "time") : nullptr;
  if (const TwinRun* m = twin_named(r.twins, "mesh" + suffix); m && (!at_2dt || mesh_top)) {
    Ladder mesh{"mesh", {}, false};
    if (at_2dt) mesh.rungs.push_back({mesh_top, run_elements, 1.0});
    else mesh.rungs.push_back({nullptr, run_elements, 1.0});
    mesh.rungs.push_back({m, m->elements, m->planned_ratio});
    if (const TwinRun* m4 = twin_named(r.twins, "mesh_coarser" + suffix))
      mesh.rungs.push_back({m4, m4->elements, m4->planned_ratio});
    ladders.push_back(mesh);
  }

  const Metrics values = run.metrics();
  const auto run_points = run.metric_points();
  const auto local_time = run.local_time_errors();
  const ModeSet* run_modes = run.modes();
  std::map<const TwinRun*, std::vector<int>> shared_points;  // per twin: its points' places in the run's mesh
  // a probe point the twin's mesh has too, up to round-off of the coordinates
  const double same_point = 1e-7 * model_diagonal(run.info().mesh);
  for (const std::string& name : run.answer_metrics()) {
    const std::optional<double> value = find_metric(values, name);
    if (!value || !std::isfinite(*value)) continue;
    MetricError m;
    m.metric = name;
    m.value = *value;
    m.missing = r.missing;
    for (const auto& [metric, e] : local_time)
      if (metric == name) m.local_time_error = e;
    if (plans.local_time && !r.interrupted) {  // the time source without a twin (error_bars.md (R9))
      if (std::isfinite(m.local_time_error)) m.sources.push_back(local_time_source(m.value, m.local_time_error));
      else m.missing.push_back("no time estimate: the integrator's local error (R9) follows displacement probes only "
                               "(--error-bar three estimates it from time twins)");
    }
    if (r.interrupted) {
      m.missing.push_back("not estimated: the twins were interrupted");
      r.metrics.push_back(std::move(m));
      continue;
    }
    for (const Ladder& ladder : ladders) {
      std::vector<double> levels_values, ratios;
      std::string flag;
      for (std::size_t k = 0; k < ladder.rungs.size() && flag.empty(); ++k) {
        const Rung& rung = ladder.rungs[k];
        std::optional<double> v = value;
        if (rung.twin) {
          if (const std::string& problem = rung.twin->problem; !problem.empty()) {
            // a third level that failed leaves the two finer ones, which did not: two levels, said
            // so (the cantilever roll-up's 5 x 2 twin diverges where its 10 x 2 twin rolls up)
            if (k == 2) {
              // the twin's reason is in its own record (summary.json error_bars.twins) and its warning
              const std::string why = problem.substr(0, std::min(problem.find(" where "), problem.find(" (")));
              m.notes.push_back(ladder.source + ": two levels, the formal order (" + why + ")");
              break;
            }
            flag = problem;
            break;
          }
          const std::array<double, 3>* at = point_of(run_points, name);
          const std::array<double, 3>* twin_at = point_of(rung.twin->points, name);
          if (at && twin_at) {
            const double d = std::hypot((*at)[0] - (*twin_at)[0], (*at)[1] - (*twin_at)[1], (*at)[2] - (*twin_at)[2]);
            if (d > same_point) {
              char where[160];
              std::snprintf(where, sizeof where, "(%.4g, %.4g, %.4g), %.3g away from the run's (%.4g, %.4g, %.4g)",
                            (*twin_at)[0], (*twin_at)[1], (*twin_at)[2], d, (*at)[0], (*at)[1], (*at)[2]);
              flag = "the " + rung.twin->name + " twin's mesh has no node at the probe's point: it reads " + where +
                     ", another point, not a coarser answer (put a node there in both: a mesh count divisible by 2, "
                     "or a named point of the geometry)";
              break;
            }
          }
          v = find_metric(rung.twin->metrics, name);
          // a mode: the twin's mode of the same shape, not of the same number (MAC)
          if (run_modes && rung.twin->modes && name.rfind(run_modes->value_name + "_", 0) == 0) {
            std::string mode_flag, note;
            auto [cached, fresh] = shared_points.try_emplace(rung.twin);
            if (fresh)
              cached->second = common_points(run.info().mesh.reference_points, rung.twin->info.mesh.reference_points,
                                             same_point);
            const std::vector<int>& shared = cached->second;
            const int number = std::atoi(name.c_str() + run_modes->value_name.size() + 1);
            if (const std::optional<double> paired = paired_mode_value(*run_modes, *rung.twin, number, shared, &mode_flag, &note))
              v = paired;
            if (!mode_flag.empty()) {
              flag = mode_flag;
              break;
            }
            if (!note.empty()) m.notes.push_back(note);
          }
          if (!v || !std::isfinite(*v)) {
            if (k == 2) {
              m.notes.push_back(ladder.source + ": two levels, the formal order (the " + rung.twin->name +
                                " twin has no value for it)");
              break;
            }
            flag = "the " + rung.twin->name + " twin has no value for it";
            break;
          }
        }
        levels_values.push_back(*v);
        if (k == 0) continue;
        // the plan's ratio of h where it knows it (generator counts, some kept), else (R5) from the counts
        const Rung& above = ladder.rungs[k - 1];
        const double ratio = ladder.known_ratio           ? 2.0
                             : rung.h > 0 && above.h > 0 ? rung.h / above.h
                                                         : mesh_ratio(above.elements, rung.elements);
        if (ratio <= 0) {
          flag = "the " + rung.twin->name + " twin is not coarser than the level above it (" +
                 std::to_string(rung.elements) + " elements for " + std::to_string(ladder.rungs[k - 1].elements) + ")";
          break;
        }
        ratios.push_back(ratio);
      }
      if (flag.empty()) {
        const LevelEstimate e = estimate_from_levels(ladder.source, levels_values, ratios, kFormalOrder);
        if (e.error) m.sources.push_back(*e.error);
        else flag = e.flag;
      }
      if (!flag.empty()) m.flags.push_back(flag);
    }
    if (!m.flags.empty()) m.sources.clear();  // a flagged metric gets no number (error_bars.md §3, §6)
    r.metrics.push_back(std::move(m));
  }
  for (const auto& [name, why] : run.answers_without_bar()) {  // said, not printed like a solver count
    const std::optional<double> value = find_metric(values, name);
    if (!value) continue;
    MetricError m;
    m.metric = name;
    m.value = *value;
    m.flags.push_back("not estimated: " + why);
    r.metrics.push_back(std::move(m));
  }
  return r;
}

std::string error_bar_plan_text(const std::string& scene_path, const std::vector<std::string>& overrides) {
  const scene::TwinPlans plans = scene::discretization_twins(scene_path, overrides, 0);
  if (!plans.on) return "error bars: off (output.error_bar = false; --error-bar on turns them on for one run)";
  std::string s = "error bars, " + std::to_string(plans.levels) + " levels per source (--error-bar off skips them):";
  if (plans.local_time)
    s += "\n  time: the integrator's own local error, accumulated at each probe (no twin, core/model/error_bars.md (R9))";
  if (plans.twins.empty()) s += " no twin";
  for (const scene::TwinPlan& t : plans.twins) {
    // what the twin costs beside the run, in work (measured shares: docs/validation/error-bars.md#cost)
    const bool coarser = t.name.find("coarser") != std::string::npos;
    const std::string mesh_work = coarser ? "about a sixteenth of the run's elements" : "about a quarter of the run's elements";
    const std::string work = t.name == "time"           ? "half the run's steps, often with more Newton iterations each"
                             : t.name == "time_coarser" ? "a quarter of the run's steps"
                                                        : mesh_work;
    s += "\n  " + t.name + " twin: " + t.description + " (" + work + ")";
  }
  for (const std::string& m : plans.missing) s += "\n  " + m;
  return s;
}

std::string error_bar_text(const MetricError& m) {
  if (!m.flags.empty()) return "(no bar: " + m.flags.front() + ")";
  if (m.sources.empty()) return m.missing.empty() ? "" : "(no bar: " + m.missing.front() + ")";
  char b[64];
  std::snprintf(b, sizeof b, "± %.2g", m.bar());
  std::string s = b;
  s += " (" + pct(m.relative_bar());
  // a source left out is said beside the metric; a third level not made changes no source (the
  // two levels remain) and is said once under the table
  std::string left_out;
  for (const std::string& missing : m.missing)
    if (missing.rfind(scene::kNoThirdMeshLevel, 0) != 0) left_out += "; " + missing.substr(0, missing.find(':'));
  std::string parts;
  if (m.sources.size() > 1 || !left_out.empty())
    for (const SourceError& e : m.sources)
      parts += (parts.empty() ? "" : ", ") + e.source + " " + pct(m.value != 0 ? e.bar / std::abs(m.value) : 0.0);
  if (!parts.empty()) s += ": " + parts;
  s += ")" + left_out;
  for (const std::string& note : m.notes) s += "; " + note;
  return s;
}

nlohmann::ordered_json error_bars_json(const ErrorBarReport& report) {
  using Json = nlohmann::ordered_json;
  Json metrics = Json::object();
  for (const MetricError& m : report.metrics) {
    Json sources = Json::array();
    for (const SourceError& s : m.sources)
      sources.push_back({{"source", s.source},
                         {"method", s.method == "local" ? "the integrator's accumulated local error (R9)"
                                                        : "Richardson extrapolation of twins"},
                         {"fine", s.fine},
                         {"coarse", s.coarse},
                         {"ratio", s.ratio},
                         {"order", s.order},
                         {"order_kind", s.order_observed          ? "observed"
                                        : s.observed_order > 0.0 ? "formal (the observed order is above it)"
                                                                 : "formal"},
                         {"observed_order", s.observed_order > 0.0 ? Json(s.observed_order) : Json()},
                         {"safety_factor", s.safety},
                         {"estimate", s.estimate},
                         {"bar", s.bar}});
    const bool bar = m.has_bar();
    metrics[m.metric] = {{"value", m.value},
                         {"estimate", bar ? Json(m.estimate()) : Json()},
                         {"extrapolated", bar ? Json(m.extrapolated()) : Json()},
                         {"bar", bar ? Json(m.bar()) : Json()},
                         {"bar_relative", bar ? Json(m.relative_bar()) : Json()},
                         {"method", report.local_time ? "mesh: Richardson extrapolation of a twin, GCI bar; time: the "
                                                        "integrator's accumulated local error (core/model/error_bars.md)"
                                                      : "Richardson extrapolation of twins, GCI bar (core/model/error_bars.md)"},
                         {"sources", sources},
                         {"flags", m.flags},
                         {"missing", m.missing},
                         {"notes", m.notes}};
    if (std::isfinite(m.local_time_error)) metrics[m.metric]["time_local_estimate"] = m.local_time_error;
  }
  Json twins = Json::array();
  for (const TwinRun& t : report.twins) {
    Json tm = Json::object();
    for (const auto& [k, v] : t.metrics) tm[k] = v;
    twins.push_back({{"name", t.name},
                     {"description", t.description},
                     {"status", to_string(t.status)},
                     {"reason", t.reason},
                     {"elements", t.elements},
                     {"wall_time_s", t.wall_s},
                     {"events", t.events},
                     {"metrics", tm}});
  }
  return {{"on", report.on},
          {"levels", report.levels},
          {"time_source", report.local_time ? "local error estimate" : "twins"},
          {"not_estimated", report.not_estimated},
          {"metrics", metrics},
          {"twins", twins},
          {"missing", report.missing},
          {"cost", {{"twins_wall_time_s", report.twins_wall_s},
                    {"run_wall_time_s", report.run_wall_s},
                    {"share_of_run", report.cost_share()},
                    {"twins_ran", "after the run, one after the other"}}}};
}

nlohmann::ordered_json field_error_json(const FieldErrorEstimate& e) {
  nlohmann::ordered_json j;
  j["relative_energy_error"] = e.relative_energy_error;
  j["method"] = "Zienkiewicz-Zhu: stress resultants recovered by superconvergent patch fits, error in the energy norm "
                "(core/shell/error_indicator.md)";
  j["elements"] = e.elements;
  j["largest_at"] = e.worst_at;
  j["largest_indicator"] = e.worst_indicator;
  j["half_error_element_fraction"] = e.half_error_fraction;
  j["field"] = "error_indicator";
  return j;
}

std::string field_error_text(const FieldErrorEstimate& e, bool picture) {
  char line[512];
  const bool concentrated = e.half_error_fraction < 0.25;
  std::snprintf(line, sizeof line,
                "field error (recovered stresses): %.2g %% in the energy norm; half of it in %.0f %% of the elements, "
                "the most (%.1fx the RMS element) at (%.4g, %.4g, %.4g): %s%s",
                100 * e.relative_energy_error, 100 * e.half_error_fraction,
                e.relative_energy_error > 0 ? e.worst_indicator / e.relative_energy_error : 0.0, e.worst_at[0],
                e.worst_at[1], e.worst_at[2], concentrated ? "refine there" : "spread over the mesh, refine it all",
                picture ? " (plots/error_indicator.png)" : "");
  return line;
}

}  // namespace ff::app
