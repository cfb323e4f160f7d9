#include "app/study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "app/run_session.h"
#include "app/timed_run.h"
#include "render/graphics_context.h"
#include "render/plot.h"

namespace fs = std::filesystem;

namespace ff::app {

namespace {
struct Row {
  std::string key, value, status;
  double wall_s, relative_time, metric, error_percent;
  long long iterations;
};

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, sep)) out.push_back(item);
  return out;
}
}  // namespace

int run_study(const StudyOptions& opt, const std::atomic<bool>& stop) {
  fs::create_directories(opt.out_dir);
  const std::string ref_scene = opt.baseline.empty() ? opt.scene : opt.baseline;
  const TimedRun base = timed_run_median(ref_scene, {}, opt.repeat, stop);
  const double ref = metric(base.metrics, opt.metric);
  if (!std::isfinite(ref))
    throw std::runtime_error("the baseline run has no metric '" + opt.metric + "' (status " +
                             to_string(base.outcome.status) + ")");
  std::fprintf(stderr, "baseline %s: %s = %.6g, %.3f ms\n", fs::path(ref_scene).stem().c_str(), opt.metric.c_str(), ref,
               1e3 * base.total_s());
  std::vector<Row> rows;
  for (const std::string& spec : opt.vary) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos) throw InputError("--vary needs KEY=V1,V2,..., got '" + spec + "'");
    const std::string key = spec.substr(0, eq);
    for (const std::string& value : split(spec.substr(eq + 1), ',')) {
      if (stop) break;
      // baseline and variant timed alternately, so machine drift cancels in the ratio
      std::vector<double> ratios;
      TimedRun r;
      for (int k = 0; k < std::max(1, opt.repeat) && !stop; ++k) {
        const TimedRun b = timed_run(ref_scene, {}, stop);
        const TimedRun v = timed_run(opt.scene, {key + "=" + value}, stop);
        if (k == 0) r = v;
        ratios.push_back(v.total_s() / b.total_s());
      }
      std::sort(ratios.begin(), ratios.end());
      const double m = metric(r.metrics, opt.metric);
      rows.push_back({key, value, to_string(r.outcome.status), r.total_s(), ratios[ratios.size() / 2], m,
                      100.0 * std::abs(m - ref) / std::abs(ref), r.totals.newton_iterations});
      std::fprintf(stderr, "  %s = %s: %s = %.6g (error %.3g %%), relative time %.3f\n", key.c_str(), value.c_str(),
                   opt.metric.c_str(), m, rows.back().error_percent, rows.back().relative_time);
    }
  }
  const fs::path dir(opt.out_dir);
  std::ofstream csv(dir / "study.csv");
  csv << "key,value,status,wall_s,relative_time," << opt.metric << ",error_percent,newton_iterations\n";
  for (const Row& r : rows)
    csv << r.key << ',' << r.value << ',' << r.status << ',' << r.wall_s << ',' << r.relative_time << ','
        << r.metric << ',' << r.error_percent << ',' << r.iterations << '\n';
  std::ofstream md(dir / "study.md");
  md << "Study of " << fs::path(opt.scene).stem().string() << " against "
     << fs::path(ref_scene).stem().string() << " (" << opt.metric << " = " << ref
     << ", wall " << 1e3 * base.total_s()
     << " ms = relative time 1; relative time = median over " << opt.repeat
     << " ratios of variant and baseline timed back to back)\n\n";
  std::string last_key;
  for (const Row& r : rows) {
    if (r.key != last_key) {
      md << "\n| " << r.key << " | relative time | " << opt.metric << " | error [%] | status |\n|---|---|---|---|---|\n";
      last_key = r.key;
    }
    char line[256];
    std::snprintf(line, sizeof line, "| %s | %.3f | %.5g | %.3f | %s |\n", r.value.c_str(), r.relative_time, r.metric,
                  r.error_percent, r.status.c_str());
    md << line;
  }
  csv.close();
  md.close();
  // error against cost, one series per varied key
  std::string err;
  auto gc = render::GraphicsContext::create(&err);
  if (gc) {
    render::PlotSpec spec;
    spec.title = "what accuracy costs: " + opt.metric;
    spec.x_label = "wall time relative to the baseline";
    spec.y_label = "error in " + opt.metric + " [%]";
    for (const Row& r : rows) {
      if (spec.series.empty() || spec.series.back().label != r.key) spec.series.push_back({r.key, {}, {}, true});
      spec.series.back().x.push_back(r.relative_time);
      spec.series.back().y.push_back(r.error_percent);
    }
    if (!render::write_plot_png(*gc, spec, (dir / "study.png").string(), &err))
      std::fprintf(stderr, "warning: study plot: %s\n", err.c_str());
  }
  std::ifstream in(dir / "study.md");
  std::cout << in.rdbuf();
  std::printf("\nwrote %s/{study.csv, study.md, study.png}\n", opt.out_dir.c_str());
  return stop ? 130 : 0;
}

}  // namespace ff::app
