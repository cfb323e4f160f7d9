// flexframe: command-line entry point. Verbs: run, check, scenes, compare, bench, study, policies, gui.
#include <CLI/CLI.hpp>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "app/bench.h"
#include "app/compare.h"
#include "app/gui/gui_app.h"
#include "app/policy_table.h"
#include "app/run_session.h"
#include "app/study.h"
#include "app/io/mesh_import.h"
#include "core/scene/scene.h"

namespace {
std::atomic<bool> g_stop{false};

extern "C" void on_sigint(int) {
  if (g_stop.exchange(true)) {  // second Ctrl-C: leave at once
    std::signal(SIGINT, SIG_DFL);
    std::raise(SIGINT);
  }
}

void print_result(const ff::app::RunResult& r) {
  std::printf("%s: %s at t = %g after %lld steps (%lld Newton iterations) in %.2f s wall\n", r.scene_name.c_str(),
              ff::to_string(r.outcome.status), r.outcome.stop_time, static_cast<long long>(r.totals.steps),
              static_cast<long long>(r.totals.newton_iterations), r.outcome.wall_time_s);
  if (!r.outcome.reason.empty()) std::printf("  reason: %s\n", r.outcome.reason.c_str());
  for (const auto& [k, v] : r.metrics) std::printf("  %-30s %.6g\n", k.c_str(), v);
  std::printf("  outputs: %s/{results.h5, summary.json, frames/ (%d PNG), plots/}\n", r.out_dir.c_str(),
              r.frames_rendered);
}
}  // namespace

int main(int argc, char** argv) {
  ff::io::install_mesh_file_reader();  // scenes with mesh.generator = "file"
  CLI::App app{"FlexFrame: flexible multibody dynamics with a headless renderer"};
  app.require_subcommand(1);

  // run
  ff::app::RunOptions run_opt;
  std::string run_scene;
  bool no_frames = false, no_plots = false, quiet = false;
  CLI::App* run = app.add_subcommand("run", "run a scene headlessly: results.h5, frames/, plots/, summary.json");
  run->add_option("scene", run_scene, "scene file or bundled scene name (default: " + ff::app::default_scene() + ")");
  run->add_option("--out", run_opt.out_dir, "output folder (default: out/<scene name>)");
  run->add_option("--set", run_opt.overrides, "override a scene key, e.g. --set solver.dt=0.01")->take_all();
  run->add_option("--frame-every", run_opt.frame_every, "render every n-th step")->check(CLI::Range(1, 1000000));
  run->add_option("--width", run_opt.width, "frame width in pixels")->check(CLI::Range(64, 8192));
  run->add_option("--height", run_opt.height, "frame height in pixels")->check(CLI::Range(64, 8192));
  run->add_flag("--no-frames", no_frames, "skip PNG frames");
  run->add_flag("--no-plots", no_plots, "skip plots");
  run->add_flag("--quiet", quiet, "no progress line");

  // check
  std::string check_scene;
  std::vector<std::string> check_overrides;
  CLI::App* check = app.add_subcommand("check", "validate a scene without running it");
  check->add_option("scene", check_scene, "scene file or bundled scene name")->required();
  check->add_option("--set", check_overrides, "override a scene key")->take_all();

  // scenes
  bool reference = false;
  CLI::App* scenes = app.add_subcommand("scenes", "list bundled scenes, or print the scene key reference");
  scenes->add_flag("--reference", reference, "print every scene key as a markdown table");

  // compare
  std::vector<std::string> compare_inputs;
  std::string compare_out = "out/compare";
  CLI::App* compare = app.add_subcommand("compare", "overlay the probes of several runs (results.h5 or run folders)");
  compare->add_option("runs", compare_inputs, "results.h5 files or run folders")->required()->expected(1, -1);
  compare->add_option("--out", compare_out, "output folder for the overlay plots");

  // bench
  ff::app::BenchOptions bench_opt;
  CLI::App* bench = app.add_subcommand("bench", "measure steps/s of the bundled hub-beam scenes, EFG/FEM cost, frames/s");
  bench->add_option("--repeat", bench_opt.repeat, "repetitions per measurement (median is reported)")
      ->check(CLI::Range(1, 1000));
  bench->add_option("--out", bench_opt.out_file, "also write the results as JSON to this file");

  // study
  ff::app::StudyOptions study_opt;
  CLI::App* study = app.add_subcommand("study", "run variants of a scene: error vs wall time table and plot");
  study->add_option("scene", study_opt.scene, "scene file or bundled scene name")->required();
  study->add_option("--vary", study_opt.vary, "KEY=V1,V2,... (each --vary is one table, varied alone)")
      ->required()->take_all();
  study->add_option("--baseline", study_opt.baseline, "scene whose run defines relative time and the reference value");
  study->add_option("--metric", study_opt.metric, "summary metric compared to the reference")->required();
  study->add_option("--repeat", study_opt.repeat, "timing repetitions (median)")->check(CLI::Range(1, 1000));
  study->add_option("--out", study_opt.out_dir, "output folder (study.csv, study.md, study.png)");

  // policies
  ff::app::PolicyTableOptions pol_opt;
  std::string pol_dts = "5e-4", pol_policies = "full,nni:2,nni:3,nni:4,frozen";
  CLI::App* policies = app.add_subcommand(
      "policies", "NOI/NOU and wall time per iteration-matrix policy and step (the shell paper's Tables 3-4)");
  policies->add_option("scene", pol_opt.scene, "shell_dynamic scene file or bundled name");
  policies->add_option("--dt", pol_dts, "time steps, comma separated");
  policies->add_option("--policies", pol_policies, "comma separated: full, frozen, nni:<i>");
  policies->add_option("--until", pol_opt.until, "simulated time per run [s]")->check(CLI::PositiveNumber);
  policies->add_option("--set", pol_opt.overrides, "override a scene key in every run")->take_all();
  policies->add_option("--out", pol_opt.out_dir, "output folder (policies.csv, policies.md, policies.png)");

  // gui
  ff::app::gui::GuiOptions gui_opt;
  std::string gui_scene;
  CLI::App* gui = app.add_subcommand("gui", "interactive window: edit a scene, run/pause/step it, watch it and its probes");
  gui->add_option("scene", gui_scene, "scene file or bundled scene name (default: " + ff::app::default_scene() + ")");
  gui->add_option("--set", gui_opt.overrides, "override a scene key, e.g. --set solver.dt=0.01")->take_all();
  gui->add_option("--actions", gui_opt.actions_file,
                  "run a script of GUI actions, one per line: run, pause, step [N], reset, set KEY VALUE, "
                  "wait SECONDS, screenshot FILE, probe NODE, save FILE, export FILE, quit");
  gui->add_option("--screenshot", gui_opt.screenshot, "write the window as PNG just before quitting");
  gui->add_option("--quit-after", gui_opt.quit_after, "quit after this many seconds")->check(CLI::NonNegativeNumber);
  gui->add_flag("--run", gui_opt.run, "start the solver at once (default: paused at t = 0)");
  gui->add_option("--width", gui_opt.width, "window width in pixels")->check(CLI::Range(640, 8192));
  gui->add_option("--height", gui_opt.height, "window height in pixels")->check(CLI::Range(480, 8192));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are not errors; every other usage error is bad input (exit 2)
    const int code = app.exit(e);
    return e.get_exit_code() == 0 ? code : 2;
  }
  std::signal(SIGINT, on_sigint);
  std::signal(SIGTERM, on_sigint);

  try {
    if (*run) {
      run_opt.scene_path = ff::app::resolve_scene(run_scene.empty() ? ff::app::default_scene() : run_scene);
      run_opt.frames = !no_frames;
      run_opt.plots = !no_plots;
      run_opt.progress = !quiet;
      const ff::app::RunResult r = ff::app::run_scene(run_opt, g_stop);
      print_result(r);
      return ff::app::exit_code(r.outcome);
    }
    if (*check) {
      std::printf("%s\n", ff::scene::check_scene(ff::app::resolve_scene(check_scene), check_overrides).c_str());
      return 0;
    }
    if (*scenes) {
      if (reference) {
        std::printf("%s", ff::scene::scene_reference_markdown().c_str());
      } else {
        std::printf("bundled scenes in %s:\n", ff::app::scene_dir().c_str());
        for (const std::string& s : ff::app::bundled_scenes()) std::printf("  %s\n", s.c_str());
      }
      return 0;
    }
    if (*gui) {
      gui_opt.scene_path = ff::app::resolve_scene(gui_scene.empty() ? ff::app::default_scene() : gui_scene);
      return ff::app::gui::run_gui(gui_opt, g_stop);
    }
    if (*compare) return ff::app::compare_runs(compare_inputs, compare_out);
    if (*bench) return ff::app::run_bench(bench_opt, g_stop);
    if (*policies) {
      auto split = [](const std::string& s) {
        std::vector<std::string> out;
        std::stringstream ss(s);
        for (std::string item; std::getline(ss, item, ',');)
          if (!item.empty()) out.push_back(item);
        return out;
      };
      pol_opt.dts = split(pol_dts);
      pol_opt.policies = split(pol_policies);
      return ff::app::run_policy_table(pol_opt, g_stop);
    }
    if (*study) {
      study_opt.scene = ff::app::resolve_scene(study_opt.scene);
      if (!study_opt.baseline.empty()) study_opt.baseline = ff::app::resolve_scene(study_opt.baseline);
      return ff::app::run_study(study_opt, g_stop);
    }
  } catch (const ff::scene::SceneError& e) {
    std::fprintf(stderr, "error: invalid scene\n%s\n", e.what());
    return 2;
  } catch (const ff::app::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {  // output folder, HDF5 file, ...: the run failed
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
