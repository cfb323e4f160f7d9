#include "app/compare.h"

#include "app/output_folder.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <stdexcept>

#include "app/io/results.h"
#include "app/plots.h"
#include "app/run_session.h"

namespace fs = std::filesystem;

namespace ff::app {

int compare_runs(const std::vector<std::string>& inputs, const std::string& out_dir) {
  std::vector<LabelledRun> runs;
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
  std::printf("overlay of %zu runs: %zu plots in %s/plots\n", runs.size(), files.size(), out_dir.c_str());
  return 0;
}

}  // namespace ff::app
