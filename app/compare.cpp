#include "app/compare.h"

#include "app/output_folder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "app/io/results.h"
#include "app/plots.h"
#include "app/input_error.h"

namespace fs = std::filesystem;

namespace ff::app {
namespace {

// One metric of one stored run with its error bar (results.h5 attribute `error_bars`, the JSON of
// summary.json's): the bar, or why there is none
struct BarredValue {
  double value = std::nan("");
  double bar = std::nan("");
  std::string no_bar;  ///< the flag or the missing source; "" with a bar, or when no bars ran
};

std::map<std::string, BarredValue> barred_metrics(const io::ResultReader& reader) {
  std::map<std::string, BarredValue> out;
  for (const auto& [name, v] : reader.metrics()) out[name].value = v;
  for (const auto& [key, text] : reader.attributes()) {
    if (key != "error_bars") continue;
    const nlohmann::json bars = nlohmann::json::parse(text, nullptr, false);
    if (!bars.is_object() || !bars.contains("metrics") || !bars["metrics"].is_object()) continue;
    for (const auto& [name, m] : bars["metrics"].items()) {
      BarredValue& b = out[name];
      if (m.contains("bar") && m["bar"].is_number()) b.bar = m["bar"].get<double>();
      else if (m.contains("flags") && m["flags"].is_array() && !m["flags"].empty() && m["flags"][0].is_string())
        b.no_bar = "flagged: " + m["flags"][0].get<std::string>();
      else if (m.contains("missing") && m["missing"].is_array() && !m["missing"].empty() && m["missing"][0].is_string())
        b.no_bar = m["missing"][0].get<std::string>();
      else b.no_bar = "no estimate";
    }
  }
  return out;
}

std::string with_bar(const BarredValue& b) {
  char text[96];
  if (std::isfinite(b.bar)) std::snprintf(text, sizeof text, "%.6g ± %.2g", b.value, b.bar);
  else std::snprintf(text, sizeof text, "%.6g", b.value);
  return text;
}

// The answer metrics of every run beside the first one's: the difference, and whether it is larger
// than the two error bars together (then the runs differ by more than their discretizations can
// explain). Metrics without a bar in either run are compared plainly, and said so.
void print_metric_table(const std::vector<LabelledRun>& runs, const std::vector<std::map<std::string, BarredValue>>& m) {
  std::vector<std::string> names;
  for (const auto& [name, b] : m.front()) {
    const bool in_all = std::all_of(m.begin(), m.end(), [&](const auto& run) { return run.count(name) > 0; });
    const bool answer = std::any_of(m.begin(), m.end(), [&](const auto& run) {
      const auto it = run.find(name);
      return it != run.end() && (std::isfinite(it->second.bar) || !it->second.no_bar.empty());
    });
    if (in_all && answer) names.push_back(name);
  }
  if (names.empty()) {
    std::printf("no metric with an error bar in these runs (they ran with --error-bar off, or estimate none)\n");
    return;
  }
  std::printf("metrics with their error bars, each run against %s:\n", runs.front().label.c_str());
  for (const std::string& name : names) {
    const BarredValue& a = m.front().at(name);
    std::printf("  %s\n    %s: %s\n", name.c_str(), runs.front().label.c_str(), with_bar(a).c_str());
    for (std::size_t i = 1; i < runs.size(); ++i) {
      const BarredValue& b = m[i].at(name);
      const double d = b.value - a.value;
      std::string verdict;
      if (std::isfinite(a.bar) && std::isfinite(b.bar))
        verdict = std::abs(d) > a.bar + b.bar ? "differs by more than the two bars together: beyond what the "
                                                 "discretizations explain"
                                               : "within the two bars together";
      else
        verdict = "no verdict: " + (!std::isfinite(a.bar) ? runs.front().label + " has no bar (" +
                                                               (a.no_bar.empty() ? "no estimate" : a.no_bar) + ")"
                                                         : runs[i].label + " has no bar (" +
                                                               (b.no_bar.empty() ? "no estimate" : b.no_bar) + ")");
      std::printf("    %s: %s, difference %.3g: %s\n", runs[i].label.c_str(), with_bar(b).c_str(), d, verdict.c_str());
    }
  }
}

}  // namespace

int compare_runs(const std::vector<std::string>& inputs, const std::string& out_dir) {
  std::vector<LabelledRun> runs;
  std::vector<std::map<std::string, BarredValue>> metrics;
  for (const std::string& in : inputs) {
    const std::string path = fs::is_directory(in) ? (fs::path(in) / "results.h5").string() : in;
    std::string err;
    auto reader = io::ResultReader::open(path, &err);
    if (!reader) throw InputError(err);  // a file that is not a run's results is bad input: exit 2
    LabelledRun r;
    r.info = reader->info();
    r.label = r.info.scene_name;
    r.history.time = reader->times();
    for (const Quantity& q : r.info.probes) r.history.probes.push_back(reader->probe_series(q.name));
    runs.push_back(std::move(r));
    metrics.push_back(barred_metrics(*reader));
  }
  // runs of one scene (two settings, two builds) would share a legend entry: label them by path
  std::map<std::string, int> label_count;
  for (const LabelledRun& r : runs) ++label_count[r.label];
  for (std::size_t i = 0; i < runs.size(); ++i)
    if (label_count[runs[i].label] > 1) runs[i].label = inputs[i];
  // a probe that some run lacks is plotted for the others, and said so
  for (std::size_t i = 0; i < runs.size(); ++i)
    for (std::size_t j = 0; j < runs.size(); ++j) {
      if (i == j) continue;
      for (const Quantity& q : runs[j].info.probes) {
        const bool have = std::any_of(runs[i].info.probes.begin(), runs[i].info.probes.end(),
                                      [&](const Quantity& p) { return p.name == q.name; });
        bool reported = false;  // once per probe and run, whichever other runs have it
        for (std::size_t k = 0; k < j && !reported; ++k)
          if (k != i)
            for (const Quantity& p : runs[k].info.probes) reported = reported || p.name == q.name;
        if (!have && !reported && q.name != runs[j].info.plot_x_probe)
          std::fprintf(stderr, "warning: probe '%s' is not in run '%s' (%s): its plot shows the other runs only\n",
                       q.name.c_str(), runs[i].label.c_str(), inputs[i].c_str());
      }
    }
  OutputFolder folder(out_dir, "compare");  // its lock before any file in it is touched
  folder.remove_earlier("plots/");
  std::string err;
  const auto files = write_overlay_plots(runs, folder.sub_folder("plots").string(), &err);
  for (const std::string& f : files) folder.record("plots/" + fs::path(f).filename().string());
  if (files.empty()) throw std::runtime_error("no overlay plot written: " + err);
  if (err.find("could not write PNG") != std::string::npos) throw WriteError("overlay plots: " + err);
  if (!err.empty()) std::fprintf(stderr, "warning: overlay plots: %s\n", err.c_str());
  for (const ProbeDelta& d : overlay_deltas(runs)) {
    const std::string unit = d.unit.empty() ? "" : " " + d.unit;
    if (std::isfinite(d.max_abs))
      std::printf("%s: max |Delta| = %.6g%s (%s vs %s, x in [%.6g, %.6g])\n", d.probe.c_str(), d.max_abs, unit.c_str(),
                  d.run_a.c_str(), d.run_b.c_str(), d.x_lo, d.x_hi);
    else
      std::printf("%s: max |Delta| not computed (no common range, or an x that goes back)\n", d.probe.c_str());
  }
  print_metric_table(runs, metrics);
  std::printf("overlay of %zu runs: %zu plots in %s/plots\n", runs.size(), files.size(), out_dir.c_str());
  return 0;
}

}  // namespace ff::app
