#include "app/compare.h"

#include "app/output_folder.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "app/io/results.h"
#include "app/plots.h"

namespace fs = std::filesystem;

namespace ff::app {

int compare_runs(const std::vector<std::string>& inputs, const std::string& out_dir) {
  std::vector<LabelledRun> runs;
  for (const std::string& in : inputs) {
    const std::string path = fs::is_directory(in) ? (fs::path(in) / "results.h5").string() : in;
    std::string err;
    auto reader = io::ResultReader::open(path, &err);
    if (!reader) throw std::runtime_error(err);
    LabelledRun r;
    r.info = reader->info();
    r.label = r.info.scene_name;
    r.history.time = reader->times();
    for (const Quantity& q : r.info.probes) r.history.probes.push_back(reader->probe_series(q.name));
    runs.push_back(std::move(r));
  }
  OutputFolder folder(out_dir, "compare");  // its lock before any file in it is touched
  folder.remove_earlier("plots/");
  std::string err;
  const auto files = write_overlay_plots(runs, folder.sub_folder("plots").string(), &err);
  for (const std::string& f : files) folder.record("plots/" + fs::path(f).filename().string());
  if (files.empty()) throw std::runtime_error("no overlay plot written: " + err);
  if (err.find("could not write PNG") != std::string::npos) throw WriteError("overlay plots: " + err);
  if (!err.empty()) std::fprintf(stderr, "warning: overlay plots: %s\n", err.c_str());
  std::printf("overlay of %zu runs: %zu plots in %s/plots\n", runs.size(), files.size(), out_dir.c_str());
  return 0;
}

}  // namespace ff::app
