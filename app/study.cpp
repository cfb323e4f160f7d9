#include "app/study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "app/io/mesh_import.h"
#include "app/process_memory.h"
#include "app/run_session.h"
#include "app/timed_run.h"
#include "core/scene/reference_csv.h"
#include "core/scene/scene.h"
#include "core/scene/schema.h"
#include "render/graphics_context.h"
#include "render/plot.h"

namespace fs = std::filesystem;

namespace ff::app {

namespace {

struct Row {
  StudyVariant variant;
  std::string status, reason;
  std::vector<double> walls;  ///< one per repetition
  double wall_s = NAN, setup_s = NAN, run_s = NAN;
  double peak_mb = NAN;       ///< peak resident growth during the first repetition
  double metric = NAN, error = NAN, error_percent = NAN;
  long long steps = 0, iterations = 0, updates = 0;
  bool pareto = false;
  bool is_reference = false;
};

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

std::string fmt(const char* f, double v) {
  if (!std::isfinite(v)) return "-";
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

/// Linear interpolation of y at x in a reference table (x scaled); throws outside the table.
double interpolate_reference(const StudyReference& r) {
  scene::ReferenceTable t;
  std::vector<double> xs, ys;
  try {
    t = scene::read_reference_csv(r.file);
    xs = t.column(r.x_column);
    ys = t.column(r.y_column);
  } catch (const std::runtime_error& e) {
    throw InputError(std::string("study reference: ") + e.what());
  }
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    const double x0 = xs[i] * r.x_scale, x1 = xs[i + 1] * r.x_scale;
    if ((r.at - x0) * (r.at - x1) <= 0.0 && x0 != x1) return ys[i] + (ys[i + 1] - ys[i]) * (r.at - x0) / (x1 - x0);
  }
  throw InputError(r.file + ": x = " + std::to_string(r.at) + " lies outside column '" + r.x_column +
                   "' (times " + std::to_string(r.x_scale) + ")");
}

std::string reference_text(const StudyReference& r, double value) {
  char b[64];
  std::snprintf(b, sizeof b, "%.6g", value);
  switch (r.kind) {
    case StudyReference::Kind::finest: return std::string(b) + " from the finest variant (every axis at its last value)";
    case StudyReference::Kind::value: return std::string(b) + " (" + r.source + ")";
    case StudyReference::Kind::table:
      return std::string(b) + " (" + r.source + "; " + fs::path(r.file).filename().string() + ", " + r.y_column +
             " at " + r.x_column + " x " + fmt("%g", r.x_scale) + " = " + fmt("%g", r.at) + ")";
    case StudyReference::Kind::scene: {
      std::string o;
      for (const std::string& s : r.overrides) o += " --set " + s;
      return std::string(b) + " from a run of " + fs::path(r.scene).stem().string() + o;
    }
  }
  return b;
}

}  // namespace

StudySpec make_study_spec(const StudyOptions& o) {
  StudySpec s;
  std::string file;
  for (const auto& [name, path] : bundled_studies())
    if (name == o.target) file = path;
  if (file.empty() && is_study_file(o.target)) file = o.target;
  if (!file.empty()) {
    s = read_study_file(file);
  } else {
    s.scene = resolve_scene(o.target);
    s.name = fs::path(s.scene).stem().string();
    if (o.vary.empty()) throw InputError("study of a scene needs at least one --vary KEY=V1,V2,...");
  }
  for (const std::string& v : o.vary) s.axes.push_back(parse_vary(v));
  for (const std::string& v : o.overrides) s.base_overrides.push_back(v);
  if (!o.overrides.empty()) {
    for (StudyVariant& v : s.extra) v.overrides.insert(v.overrides.end(), o.overrides.begin(), o.overrides.end());
    if (s.reference.kind == StudyReference::Kind::scene)
      s.reference.overrides.insert(s.reference.overrides.end(), o.overrides.begin(), o.overrides.end());
  }
  if (!o.metric.empty()) s.metric = o.metric;
  if (s.metric.empty()) throw InputError("study needs --metric NAME (a summary.json metric of the scene)");
  if (!o.baseline.empty()) s.reference = parse_reference("scene:" + o.baseline);
  if (!o.reference.empty()) s.reference = parse_reference(o.reference);
  if (s.reference.kind == StudyReference::Kind::scene && s.reference.overrides.empty())
    s.reference.overrides = s.base_overrides;
  if (o.each) s.grid = false;
  if (o.repeat) s.repeat = *o.repeat;
  if (s.axes.empty() && s.extra.empty()) throw InputError("study '" + s.name + "' has nothing to vary");
  return s;
}

int check_study(const StudySpec& spec) {
  std::vector<StudyVariant> runs = spec.variants();
  if (const std::optional<StudyVariant> r = spec.reference_run())
    if (std::none_of(runs.begin(), runs.end(), [&](const StudyVariant& v) { return v.same_run(*r); }))
      runs.push_back(*r);
  for (const StudyVariant& v : runs) {
    try {
      std::printf("%-50s %s\n", v.label.c_str(), scene::check_scene(v.scene, v.overrides, io::scene_context()).c_str());
    } catch (const scene::SceneError& e) {
      std::vector<scene::Issue> issues = e.issues;
      for (scene::Issue& i : issues) i.message += " (study '" + spec.name + "', variant " + v.label + ")";
      throw scene::SceneError(issues);
    }
  }
  if (spec.reference.kind == StudyReference::Kind::table)
    std::printf("reference %.6g from %s\n", interpolate_reference(spec.reference), spec.reference.file.c_str());
  std::printf("study %s: %zu runs valid\n", spec.name.c_str(), runs.size());
  return 0;
}

int run_study(const StudySpec& spec, const std::string& out_dir_option, const std::atomic<bool>& stop) {
  const fs::path dir = out_dir_option.empty() ? fs::path("out") / "study" / spec.name : fs::path(out_dir_option);
  fs::create_directories(dir);
  std::vector<Row> rows;
  for (const StudyVariant& v : spec.variants()) {
    rows.emplace_back();
    rows.back().variant = v;
    rows.back().status = "not run";
  }

  // the reference: a number, a run outside the variants, or the finest variant
  double ref = NAN;
  std::size_t ref_row = rows.size();
  switch (spec.reference.kind) {
    case StudyReference::Kind::value: ref = spec.reference.value; break;
    case StudyReference::Kind::table: ref = interpolate_reference(spec.reference); break;
    case StudyReference::Kind::scene:
    case StudyReference::Kind::finest: {
      const StudyVariant target = *spec.reference_run();
      for (std::size_t i = 0; i < rows.size(); ++i)
        if (rows[i].variant.same_run(target)) ref_row = i;
      if (ref_row == rows.size()) {
        std::fprintf(stderr, "reference run %s ...\n", target.label.c_str());
        const TimedRun r = timed_run(target.scene, target.overrides, stop);
        ref = metric(r.metrics, spec.metric);
        if (!std::isfinite(ref))
          throw InputError("the reference run (" + target.label + ") has no finite metric '" + spec.metric +
                           "' (status " + to_string(r.outcome.status) + ")");
      }
    }
  }

  // repetitions interleaved over the variants, so drift of the machine spreads over all of them
  const int repeat = std::max(1, spec.repeat);
  const std::size_t total = rows.size() * repeat;
  std::size_t done = 0;
  for (int k = 0; k < repeat && !stop; ++k) {
    for (std::size_t i = 0; i < rows.size() && !stop; ++i) {
      Row& row = rows[i];
      ++done;
      if (k > 0 && row.status != "completed") continue;
      std::fprintf(stderr, "[%zu/%zu] %s ...", done, total, row.variant.label.c_str());
      std::fflush(stderr);
      const double rss0 = resident_mb();
      const bool reset = k == 0 && reset_peak_resident();
      TimedRun r;
      try {
        r = timed_run(row.variant.scene, row.variant.overrides, stop);
      } catch (const scene::SceneError&) {
        throw;
      } catch (const std::exception& e) {
        row.status = "failed";
        row.reason = e.what();
        std::fprintf(stderr, " failed: %s\n", e.what());
        continue;
      }
      row.walls.push_back(r.total_s());
      if (k == 0) {
        row.status = to_string(r.outcome.status);
        row.reason = r.outcome.reason;
        row.metric = metric(r.metrics, spec.metric);
        row.steps = r.totals.steps;
        row.iterations = r.totals.newton_iterations;
        row.updates = r.totals.jacobian_updates;
        row.peak_mb = reset ? std::max(0.0, peak_resident_mb() - rss0) : NAN;
        row.setup_s = r.setup_s;
        row.run_s = r.run_s;
        if (!std::isfinite(row.metric) && r.outcome.status == RunStatus::completed) {
          std::fprintf(stderr, "\n");
          std::string names;
          for (const auto& [name, value] : r.metrics) names += " " + name;
          throw InputError("scene " + fs::path(row.variant.scene).stem().string() + " has no metric '" + spec.metric +
                           "'; its metrics are:" + names);
        }
      }
      std::fprintf(stderr, " %s, %s = %.6g, %.3f s\n", row.status.c_str(), spec.metric.c_str(), row.metric,
                   row.walls.back());
    }
  }
  if (ref_row < rows.size()) {
    ref = rows[ref_row].metric;
    rows[ref_row].is_reference = true;
  }

  // errors, relative time, Pareto front (no cheaper variant is as accurate)
  const double scale = std::isfinite(ref) && ref != 0.0 ? std::abs(ref) : NAN;
  double first_wall = NAN;
  for (Row& r : rows) {
    r.wall_s = median(r.walls);
    if (!std::isfinite(first_wall) && std::isfinite(r.wall_s)) first_wall = r.wall_s;
    r.error = std::abs(r.metric - ref);
    r.error_percent = 100.0 * r.error / scale;
  }
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (std::isfinite(rows[i].wall_s) && std::isfinite(rows[i].error) && !rows[i].is_reference) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return rows[a].wall_s < rows[b].wall_s; });
  double best = INFINITY;
  // a variant must beat the cheaper ones by more than round-off to count
  for (std::size_t i : order)
    if (rows[i].error < best * (1.0 - 1e-6)) {
      best = rows[i].error;
      rows[i].pareto = true;
    }

  // study.csv
  std::ofstream csv(dir / "study.csv");
  csv << "variant";
  for (const StudyAxis& a : spec.axes) csv << ',' << a.name();
  csv << ",status,wall_s,relative_time,setup_s,run_s,steps,newton_iterations,jacobian_updates,peak_memory_mb,"
      << spec.metric << ",reference,error,error_percent,pareto,is_reference\n";
  // non-finite values (a variant that diverged has no metric) are left empty, never "nan"
  const auto num = [](double v) {
    if (!std::isfinite(v)) return std::string();
    char b[32];
    std::snprintf(b, sizeof b, "%.10g", v);
    return std::string(b);
  };
  const auto quoted = [](const std::string& text) {
    std::string q = "\"";
    for (char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + '"';
  };
  for (const Row& r : rows) {
    csv << quoted(r.variant.label);
    for (const std::string& l : r.variant.axis_labels) csv << ',' << quoted(l);
    csv << ',' << r.status << ',' << num(r.wall_s) << ',' << num(r.wall_s / first_wall) << ',' << num(r.setup_s)
        << ',' << num(r.run_s) << ',' << r.steps << ',' << r.iterations << ',' << r.updates << ',' << num(r.peak_mb)
        << ',' << num(r.metric) << ',' << num(ref) << ',' << num(r.error) << ',' << num(r.error_percent) << ','
        << (r.pareto ? 1 : 0) << ',' << (r.is_reference ? 1 : 0) << '\n';
  }
  csv.close();

  // study.md
  std::ofstream md(dir / "study.md");
  md << "# Study " << spec.name << "\n\n";
  if (!spec.description.empty()) md << spec.description << "\n\n";
  md << "- base scene: " << fs::path(spec.scene).stem().string();
  for (const std::string& s : spec.base_overrides) md << " `--set " << s << "`";
  md << "\n- metric: `" << spec.metric << "`; reference " << reference_text(spec.reference, ref) << "\n";
  md << "- wall time: median of " << repeat << " run(s) per variant (set-up + solve, no output), repetitions"
     << " interleaved over the variants; relative time is to the first variant, measured in the same study\n";
  md << "- peak memory: growth of the resident set during the variant's first run"
     << (std::isfinite(rows.empty() ? NAN : rows.front().peak_mb) ? "" : " (not measurable here: shown as -)")
     << "\n- Pareto: no faster variant has a smaller error\n\n";
  md << "| variant | wall [s] | relative time | Newton it. | matrix updates | peak memory [MB] | " << spec.metric
     << " | error [%] | Pareto | status |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    md << "| " << r.variant.label << " | " << fmt("%.3g", r.wall_s) << " | " << fmt("%.3f", r.wall_s / first_wall)
       << " | " << r.iterations << " | " << r.updates << " | " << fmt("%.2f", r.peak_mb) << " | "
       << fmt("%.6g", r.metric) << " | " << (r.is_reference ? std::string("reference") : fmt("%.3g", r.error_percent))
       << " | " << (r.pareto ? "yes" : "") << " | " << r.status << (r.reason.empty() ? "" : ": " + r.reason)
       << " |\n";
  }
  md.close();

  // pareto.png: error against wall time, log-log; a line per value of the later axes
  std::string err;
  auto gc = render::GraphicsContext::create(&err);
  if (gc) {
    render::PlotSpec plot;
    plot.title = spec.name + ": error of " + spec.metric + " against wall time";
    plot.x_label = "wall time [s]";
    plot.y_label = "error in " + spec.metric + " [%]";
    plot.log_x = plot.log_y = true;
    std::map<std::string, std::size_t> series_of;
    for (const Row& r : rows) {
      std::string group;
      bool axis_row = false;
      for (std::size_t a = 0; a < r.variant.axis_labels.size(); ++a) {
        if (!r.variant.axis_labels[a].empty()) axis_row = true;
        if (a == 0 && spec.grid) continue;  // points along the first axis share a line
        if (!r.variant.axis_labels[a].empty())
          group += (group.empty() ? "" : ", ") + spec.axes[a].name() + "=" + r.variant.axis_labels[a];
      }
      if (!axis_row) group = r.variant.label;
      if (group.empty()) group = spec.axes.empty() ? "variants" : spec.axes.front().name();
      auto [it, fresh] = series_of.emplace(group, plot.series.size());
      if (fresh) plot.series.push_back({group, {}, {}, true});  // markers: neighbours are not a continuum in time
      plot.series[it->second].x.push_back(r.wall_s);
      plot.series[it->second].y.push_back(r.error_percent);
    }
    render::PlotSeries front{"Pareto front", {}, {}, false};
    for (std::size_t i : order)
      if (rows[i].pareto) {
        front.x.push_back(rows[i].wall_s);
        front.y.push_back(rows[i].error_percent);
      }
    if (front.x.size() > 1) plot.series.push_back(front);
    if (!render::write_plot_png(*gc, plot, (dir / "pareto.png").string(), &err))
      std::fprintf(stderr, "warning: pareto plot: %s\n", err.c_str());
  } else {
    std::fprintf(stderr, "warning: no graphics context for pareto.png: %s\n", err.c_str());
  }
  std::ifstream in(dir / "study.md");
  std::cout << in.rdbuf();
  std::printf("\nwrote %s/{study.csv, study.md, pareto.png}\n", dir.string().c_str());
  return stop ? 130 : 0;
}

}  // namespace ff::app
