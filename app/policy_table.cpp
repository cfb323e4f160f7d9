#include "app/policy_table.h"

#include "app/output_folder.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "app/run_session.h"
#include "app/timed_run.h"
#include "render/graphics_context.h"
#include "render/plot.h"

namespace fs = std::filesystem;

namespace ff::app {

namespace {
struct Row {
  std::string dt, policy, status;
  double noi = 0, nou = 0, wall_s = 0, fallbacks = 0;
};

// "lazy:0.2" -> {"0.2"}, "lazy:0.2:0.1" -> {"0.2", "0.1"} (refresh_ratio, step_refresh_ratio)
std::vector<std::string> lazy_ratios(const std::string& p) {
  std::vector<std::string> parts;
  std::stringstream ss(p.substr(5));
  for (std::string part; std::getline(ss, part, ':');) parts.push_back(part);
  return parts;
}

// "full", "frozen", "nni:3", "lazy", "lazy:0.2", "lazy:0.2:0.1" -> scene overrides
std::vector<std::string> policy_overrides(const std::string& p) {
  if (p == "full" || p == "frozen" || p == "lazy") return {"solver.policy=" + p};
  if (p.rfind("nni:", 0) == 0) return {"solver.policy=nni", "solver.nni=" + p.substr(4)};
  if (p.rfind("lazy:", 0) == 0) {
    const std::vector<std::string> r = lazy_ratios(p);
    if (r.size() == 1 && !r[0].empty()) return {"solver.policy=lazy", "solver.refresh_ratio=" + r[0]};
    if (r.size() == 2 && !r[0].empty() && !r[1].empty())
      return {"solver.policy=lazy", "solver.refresh_ratio=" + r[0], "solver.step_refresh_ratio=" + r[1]};
  }
  throw InputError("--policies: '" + p + "' is not full, frozen, nni:<i>, lazy, lazy:<refresh ratio> or "
                   "lazy:<refresh ratio>:<step refresh ratio>");
}
std::string policy_label(const std::string& p) {
  if (p == "full") return "every iteration";
  if (p == "frozen") return "frozen";
  if (p == "lazy") return "lazy";
  if (p.rfind("lazy:", 0) == 0) {
    const std::vector<std::string> r = lazy_ratios(p);
    return "lazy, ratio " + r[0] + (r.size() > 1 ? ", next step " + r[1] : "");
  }
  return "NNI >= " + p.substr(4);
}
}  // namespace

int run_policy_table(const PolicyTableOptions& opt, const std::atomic<bool>& stop) {
  const std::string scene = resolve_scene(opt.scene);
  OutputFolder folder(opt.out_dir, "policies");  // its lock before any file in it is touched
  std::vector<Row> rows;
  for (const std::string& dt : opt.dts)
    for (const std::string& p : opt.policies) {
      if (stop) break;
      std::vector<std::string> o = opt.overrides;
      std::ostringstream until;
      until.precision(17);
      until << opt.until;
      for (const std::string& s : {"solver.dt=" + dt, "solver.end=" + until.str(), "solver.count_until=" + until.str()})
        o.push_back(s);
      for (const std::string& s : policy_overrides(p)) o.push_back(s);
      const TimedRun r = timed_run(scene, o, stop);
      Row row{dt, p, to_string(r.outcome.status), metric(r.metrics, "NOI"), metric(r.metrics, "NOU"), r.run_s,
              metric(r.metrics, "fallback_steps")};
      std::fprintf(stderr, "  dt %s, %s: NOI %.0f NOU %.0f, %.2f s (%s)\n", dt.c_str(), policy_label(p).c_str(),
                   row.noi, row.nou, row.wall_s, row.status.c_str());
      rows.push_back(row);
    }
  std::ostringstream csv;
  csv << "dt,policy,status,NOI,NOU,wall_s,fallback_steps\n";
  for (const Row& r : rows)
    csv << r.dt << ',' << r.policy << ',' << r.status << ',' << r.noi << ',' << r.nou << ',' << r.wall_s << ','
        << r.fallbacks << '\n';
  std::ostringstream md;
  md << "Iteration-matrix policies on " << fs::path(scene).stem().string() << ", first " << opt.until
     << " s (NOI: Newton iterations, NOU: matrix updates; changes and speed-up against 'every iteration' at the same "
        "step, from one run each)\n\n| dt [s] | policy | NOI | NOU | NOI change | NOU change | wall [s] | speed-up | "
        "status |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const Row& r : rows) {
    const Row* full = nullptr;
    for (const Row& f : rows)
      if (f.dt == r.dt && f.policy == "full") full = &f;
    char line[320];
    auto pct = [&](double a, double b) { return full && b > 0 ? 100.0 * (a - b) / b : std::nan(""); };
    std::snprintf(line, sizeof line, "| %s | %s | %.0f | %.0f | %+.1f %% | %+.1f %% | %.2f | %.2f | %s |\n",
                  r.dt.c_str(), policy_label(r.policy).c_str(), r.noi, r.nou, pct(r.noi, full ? full->noi : 0),
                  pct(r.nou, full ? full->nou : 0), r.wall_s, full && r.wall_s > 0 ? full->wall_s / r.wall_s : std::nan(""),
                  r.status.c_str());
    md << line;
  }
  write_text_file(folder.file("policies.csv"), csv.str());  // WriteError (a full disk): exit 1
  write_text_file(folder.file("policies.md"), md.str());
  std::string err;
  if (auto gc = render::GraphicsContext::create(&err)) {
    render::PlotSpec spec;
    spec.title = "iteration-matrix policies: updates against iterations";
    spec.x_label = "Newton iterations NOI";
    spec.y_label = "matrix updates NOU";
    spec.log_y = true;
    for (const Row& r : rows) {
      if (spec.series.empty() || spec.series.back().label != "dt = " + r.dt + " s")
        spec.series.push_back({"dt = " + r.dt + " s", {}, {}, true});  // one marker per policy
      spec.series.back().x.push_back(r.noi);
      spec.series.back().y.push_back(std::max(r.nou, 1.0));
    }
    if (!render::write_plot_png(*gc, spec, folder.file("policies.png").string(), &err)) {
      if (err.find("could not write PNG") != std::string::npos) throw WriteError("policies plot: " + err);
      std::fprintf(stderr, "warning: policies plot: %s\n", err.c_str());
    }
  }
  std::cout << md.str();
  std::printf("\nwrote %s/{policies.csv, policies.md, policies.png}\n", opt.out_dir.c_str());
  return stop ? 130 : 0;
}

}  // namespace ff::app
