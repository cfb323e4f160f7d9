// `flexframe bench --error-bars [--scene S ...]`: what the error bars cost, as ratios measured in
// this one command. Each round runs `flexframe run S --error-bar off` and `--error-bar on` as child
// processes, one after the other, their order swapped every other round (so neither always runs
// on a machine the other has just warmed), into a folder this command creates and removes. Two
// figures per scene: the whole command's wall time with bars against without (what a user waits
// for: reading, meshing, solving, frames, plots, files), and the share the run itself prints (the
// twins' solves against the run's own, docs/validation/error-bars.md#cost). The targets of the
// error-bar issue are printed beside them: 35 % for static and eigen scenes, 60 % for dynamic ones.
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/bench/bench.h"
#include "app/child_process.h"
#include "app/io/mesh_import.h"
#include "app/run_session.h"
#include "core/frame/input_file.h"
#include "core/scene/discretization_twins.h"
#include "core/scene/scene.h"

namespace fs = std::filesystem;

namespace ff::app {
namespace {

// the error-bar issue's acceptance: bars add at most this share to a run's wall time
constexpr double kStaticTarget = 0.35, kDynamicTarget = 0.60;

// the default scenes: the default job, and one static, one eigen and one arc-length scene the
// validation page measures bars on, each a few seconds
std::vector<std::string> default_bar_scenes() {
  return {default_scene(), "clamped_plate_pressure", "modal_clamped_plate", "hemisphere_18deg_h004", "cantilever_step_load"};
}

struct TimedChild {
  double wall_s = 0;
  std::string failure;  ///< "" when it exited 0 (completed); else what happened
};

// Runs `argv` with stdout and stderr to `log`, waits for it and times it
TimedChild run_child(const std::vector<std::string>& argv, const fs::path& log) {
  ChildSpec spec;
  spec.program = argv.front();
  spec.args = argv;
  spec.log = log.string();
  spec.stderr_to_log = true;
  TimedChild t;
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = spawn_child(spec);
  if (pid < 0) {
    t.failure = std::string("cannot start it: ") + std::strerror(errno);
    return t;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) {
      t.failure = std::string("cannot wait for it: ") + std::strerror(errno);
      return t;
    }
  t.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (WIFSIGNALED(status)) t.failure = "it was killed by signal " + std::to_string(WTERMSIG(status));
  else if (WEXITSTATUS(status) != 0) t.failure = "it exited with code " + std::to_string(WEXITSTATUS(status));
  if (!t.failure.empty()) t.failure += " (its output: " + log.string() + ")";
  return t;
}

struct SceneRow {
  std::string scene;
  bool dynamic = false;
  std::vector<double> off_s, on_s, ratios, run_shares;
  std::string status, failure;
};

}  // namespace

int run_error_bar_bench(const BenchOptions& opt, const std::atomic<bool>& stop) {
  const std::vector<std::string> names = opt.scenes.empty() ? default_bar_scenes() : opt.scenes;
  // every scene is found and read before the first one is timed: a typo ends the command at once
  std::vector<SceneRow> rows;
  std::vector<std::string> paths;
  for (const std::string& name : names) {
    paths.push_back(resolve_scene(name));
    scene::load_scene(paths.back(), opt.overrides, io::scene_context());
    SceneRow row;
    row.scene = name;
    row.dynamic = scene::discretization_twins(paths.back(), opt.overrides, 0).dynamic;
    rows.push_back(row);
  }
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);  // the children are this very build
  if (ec) {
    std::fprintf(stderr, "error: bench --error-bars: cannot find this executable (/proc/self/exe): %s\n",
                 ec.message().c_str());
    return 1;
  }
  const fs::path dir = make_bench_folder("error_bars");
  if (dir.empty()) {
    std::fprintf(stderr, "error: bench --error-bars: cannot create a folder in %s: %s\n",
                 fs::temp_directory_path().string().c_str(), std::strerror(errno));
    return 1;
  }
  const int rounds = std::max(1, opt.repeat);
  bool any_failed = false;
  for (std::size_t i = 0; i < rows.size() && !stop; ++i) {
    SceneRow& row = rows[i];
    for (int round = 0; round < rounds && !stop && row.failure.empty(); ++round) {
      double wall[2] = {0, 0};
      for (int k = 0; k < 2 && row.failure.empty() && !stop; ++k) {
        const bool on = (k == 0) == (round % 2 == 1);  // off first in even rounds, on first in odd ones
        const std::string tag = std::to_string(i + 1) + (on ? "_on_" : "_off_") + std::to_string(round + 1);
        const fs::path out = dir / ("run_" + tag);
        std::vector<std::string> argv = {self.string(), "run", paths[i], "--out", out.string(), "--error-bar",
                                         on ? "on" : "off"};
        for (const std::string& s : opt.overrides) argv.insert(argv.end(), {"--set", s});
        std::fprintf(stderr, "bench --error-bars: %s, round %d of %d, bars %s\n", row.scene.c_str(), round + 1,
                     rounds, on ? "on" : "off");
        const TimedChild t = run_child(argv, dir / ("run_" + tag + ".log"));
        if (!t.failure.empty()) {
          row.failure = t.failure;
          break;
        }
        wall[on] = t.wall_s;
        nlohmann::json summary;
        try {
          std::string text;
          read_input_file((out / "summary.json").string(), &text, kMaxTextInputBytes, kTextInputBound, nullptr);
          summary = nlohmann::json::parse(text);
        } catch (const std::exception& e) {
          row.failure = std::string("its summary.json cannot be read: ") + e.what();
          break;
        }
        row.status = summary.value("status", "");
        if (on) {
          const nlohmann::json& cost = summary["error_bars"]["cost"];
          if (cost.is_object() && cost["share_of_run"].is_number())
            row.run_shares.push_back(cost["share_of_run"].get<double>());
        }
        fs::remove_all(out, ec);  // the frames of a long scene add up over the rounds
      }
      if (!row.failure.empty() || stop) break;
      row.off_s.push_back(wall[0]);
      row.on_s.push_back(wall[1]);
      row.ratios.push_back(wall[1] / wall[0]);
    }
    if (!row.failure.empty()) {
      any_failed = true;
      std::fprintf(stderr, "bench --error-bars: %s failed: %s\n", row.scene.c_str(), row.failure.c_str());
    }
  }

  std::printf("What the error bars cost: `flexframe run` with --error-bar on against off, alternated pairs, %d "
              "round(s) per scene; medians\n\n",
              rounds);
  std::printf("| scene | kind | status | off [s] | on [s] | whole command on/off | bars' share as the run prints it "
              "| target |\n|---|---|---|---|---|---|---|---|\n");
  nlohmann::ordered_json json_rows = nlohmann::ordered_json::array();
  for (const SceneRow& row : rows) {
    const double target = row.dynamic ? kDynamicTarget : kStaticTarget;
    const double ratio = median_of(row.ratios), share = median_of(row.run_shares);
    if (!row.failure.empty() || row.ratios.empty()) {
      std::printf("| %s | %s | %s | | | | | %.0f %% |\n", row.scene.c_str(), row.dynamic ? "dynamic" : "static/eigen",
                  row.failure.empty() ? "not timed" : "failed", 100 * target);
    } else {
      std::printf("| %s | %s | %s | %.2f | %.2f | %.2f (%+.0f %%) | %.0f %% | %.0f %% |\n", row.scene.c_str(),
                  row.dynamic ? "dynamic" : "static/eigen", row.status.c_str(), median_of(row.off_s),
                  median_of(row.on_s), ratio, 100 * (ratio - 1), 100 * share, 100 * target);
    }
    json_rows.push_back({{"scene", row.scene},
                         {"dynamic", row.dynamic},
                         {"status", row.status},
                         {"failure", row.failure},
                         {"off_s", row.off_s},
                         {"on_s", row.on_s},
                         {"ratio_median", std::isfinite(ratio) ? nlohmann::ordered_json(ratio) : nlohmann::ordered_json()},
                         {"run_share_median", std::isfinite(share) ? nlohmann::ordered_json(share) : nlohmann::ordered_json()},
                         {"target_share", target}});
  }
  std::printf("\nwhole command: reading, meshing, solving, frames and files, as a user waits for them; the run's share: "
              "the twins' set-up and solves against the run's own (the figure its console and summary.json print)\n");
  std::fflush(stdout);
  if (!any_failed) fs::remove_all(dir, ec);  // a failed run keeps its log for the reader
  else std::fprintf(stderr, "bench --error-bars: the runs' logs are kept in %s\n", dir.string().c_str());
  if (!opt.out_file.empty()) {
    const nlohmann::ordered_json root = {{"rounds", rounds}, {"overrides", opt.overrides}, {"scenes", json_rows}};
    if (!write_bench_json(opt.out_file, root.dump(2) + "\n")) return 1;
  }
  return stop ? 130 : any_failed ? 1 : 0;
}

}  // namespace ff::app
