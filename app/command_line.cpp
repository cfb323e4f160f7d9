#include "app/command_line.h"

#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <sstream>

#include "app/bench/bench.h"
#include "app/check_picture.h"
#include "app/compare.h"
#include "app/gui/gui_app.h"
#include "app/io/mesh_import.h"
#include "app/policy_table.h"
#include "app/replay.h"
#include "app/run_session.h"
#include "app/study.h"
#include "app/view_options.h"
#include "core/scene/scene.h"
#include "core/solve/solver_ranks.h"

namespace ff::app {

namespace {

// what the error bars cost and what they could not cover, after the metric table
void print_error_bar_cost(const ErrorBarReport& b) {
  if (!b.on) return;
  if (!b.not_estimated.empty()) {
    std::printf("  error bars: none (%s)\n", b.not_estimated.c_str());
    return;
  }
  std::string twins;
  for (const TwinRun& t : b.twins) twins += (twins.empty() ? "" : "; ") + t.name + ": " + t.description;
  std::printf("  error bars: %sRichardson, %s; twins %s; they cost %.0f %% of the run (summary.json \"error_bars\")\n",
              b.local_time ? "time from the integrator's local error (no twin); mesh by " : "",
              b.levels == 3 ? "three levels (the observed order, at most the formal 2; safety factor 1.25)"
                            : "two levels (the formal order 2, safety factor 3)",
              twins.empty() ? "none" : twins.c_str(), 100 * b.cost_share());
  for (const std::string& m : b.missing) std::printf("  error bars: %s\n", m.c_str());
  for (const TwinRun& t : b.twins)
    if (t.status != ff::RunStatus::completed)
      std::fprintf(stderr, "warning: error bars: the %s twin ended %s: %s\n", t.name.c_str(), ff::to_string(t.status),
                   t.reason.c_str());
}

void print_result(const RunResult& r) {
  std::printf("%s: %s at t = %g after %lld steps (%lld Newton iterations) in %.2f s wall\n", r.scene_name.c_str(),
              ff::to_string(r.outcome.status), r.outcome.stop_time, static_cast<long long>(r.totals.steps),
              static_cast<long long>(r.totals.newton_iterations), r.outcome.wall_time_s);
  if (!r.outcome.reason.empty()) std::printf("  reason: %s\n", r.outcome.reason.c_str());
  // what the path did on the way (statics): each event once, counted by kind
  std::map<std::string, int> kinds;
  for (const ff::PathEvent& e : r.outcome.events) ++kinds[e.kind];
  for (const auto& [kind, n] : kinds)  // "2 limit_points", but "2 unloaded"
    std::printf("  events: %d %s%s (summary.json \"events\")\n", n, kind.c_str(), n > 1 && kind.back() != 'd' ? "s" : "");
  // answer metrics with their error bars (app/error_bar_run.h), the solver's counts plain
  for (const auto& [k, v] : r.metrics) {
    const ff::MetricError* e = r.error_bars.find(k);
    const std::string bar = e ? error_bar_text(*e) : "";
    std::printf("  %-30s %.6g%s%s\n", k.c_str(), v, bar.empty() ? "" : " ", bar.c_str());
  }
  print_error_bar_cost(r.error_bars);
  if (r.field_error)
    std::printf("  %s\n",
                field_error_text(*r.field_error, std::filesystem::exists(r.out_dir + "/plots/error_indicator.png")).c_str());
  std::printf("  outputs: %s/{results.h5, summary.json, frames/ (%d PNG), plots/", r.out_dir.c_str(),
              r.frames_rendered);
  if (!r.movie.empty()) std::printf(", movie.mp4");
  if (r.frames_exported > 0) std::printf(", export/ (%d frames)", r.frames_exported);
  std::printf("}\n");
  if (r.modes >= 0)  // an eigen-analysis: its table, animations and spectrum (docs/guide/mode_outputs.md)
    std::printf("  modes: %d (summary.json \"modes\"), %d animated in frames/mode_NN/\n", r.modes, r.modes_animated);
}
}  // namespace

// every verb's options, and the verb the command line chose
struct CommandLine::Verbs {
  CLI::App app{"FlexFrame: flexible multibody dynamics with a headless renderer"};
  RunOptions run_opt;
  std::string run_scene_arg;
  bool no_frames = false, no_plots = false, quiet = false;
  std::string error_bar;
  ReplayOptions replay_opt;
  std::string replay_field;
  bool replay_no_frames = false, replay_no_plots = false;
  std::string check_scene;
  std::vector<std::string> check_overrides;
  std::string check_picture;
  bool reference = false;
  std::vector<std::string> compare_inputs;
  std::string compare_out = "out/compare";
  BenchOptions bench_opt;
  StudyOptions study_opt;
  std::string study_timing = "shared";
  bool study_list = false, study_reference = false;
  StudyVariantOptions variant_opt;
  PolicyTableOptions pol_opt;
  std::string pol_dts = "5e-4", pol_policies = "full,nni:2,nni:3,nni:4,frozen,lazy";
  gui::GuiOptions gui_opt;
  std::string gui_scene;
  CLI::App *cmd_run = nullptr, *cmd_replay = nullptr, *cmd_check = nullptr, *cmd_scenes = nullptr, *cmd_compare = nullptr,
           *cmd_bench = nullptr, *cmd_study = nullptr, *cmd_study_variant = nullptr, *cmd_policies = nullptr, *cmd_gui = nullptr;
  CLI::Option* check_picture_opt = nullptr;

  Verbs() {
    app.require_subcommand(1);
    add_run();
    add_replay();
    add_check();
    add_scenes();
    add_compare();
    add_bench();
    add_study();
    add_study_variant();
    add_policies();
    add_gui();
  }

  void add_run() {
    cmd_run = app.add_subcommand("run", "run a scene headlessly: results.h5, frames/, plots/, summary.json");
    cmd_run->add_option("scene", run_scene_arg, "scene file or bundled scene name (default: " + default_scene() + ")");
    cmd_run->add_option("--out", run_opt.out_dir, "output folder (default: out/<scene name>)");
    cmd_run->add_option("--set", run_opt.overrides, "override a scene key, e.g. --set solver.dt=0.01")->take_all();
    cmd_run->add_option("--frame-every", run_opt.frame_every, "render every n-th step")->check(CLI::Range(1, 1000000));
    cmd_run->add_option("--width", run_opt.width, "frame width in pixels")->check(CLI::Range(64, 8192));
    cmd_run->add_option("--height", run_opt.height, "frame height in pixels")->check(CLI::Range(64, 8192));
    cmd_run->add_flag("--no-frames", no_frames, "skip PNG frames");
    cmd_run->add_flag("--no-plots", no_plots, "skip plots");
    cmd_run->add_flag("--quiet", quiet, "no progress line");
    cmd_run->add_option("--camera", run_opt.camera, std::string(kCameraHelp) + " (default: the scene's view)");
    cmd_run->add_flag("--movie", run_opt.movie, "also assemble the frames into DIR/movie.mp4");
    cmd_run->add_option("--fps", run_opt.fps, "movie frames per second")->check(CLI::Range(1, 240));
    cmd_run->add_option("--frame-memory", run_opt.frame_memory_mb,
                    "MB the frames may hold until the solve ends, to be drawn in one colour range and view; beyond "
                    "it the rest is drawn as it comes in the first frames' range (default: a quarter of the "
                    "machine's memory, at most 2048)")
        ->check(CLI::Range(0.001, 1e7));
    cmd_run->add_option("--animate-modes", run_opt.animate_modes,
                    "after a modal or buckling analysis, animate at most N modes (default: all; 0: none)")
        ->check(CLI::Range(0, 1000000));
    cmd_run->add_option("--export", run_opt.export_formats,
                    "write the rendered frames' deformed mesh to DIR/export: vtu (+ .pvd), gltf (.glb), obj");
    cmd_run->add_option("--error-bar", error_bar,
                    "on: every answer metric with its discretization error from coarser twins of the run (a coarser "
                    "mesh, a longer time step; docs/guide/how-accurate.md), as many as the scene's "
                    "output.error_bar_levels asks (auto: three levels in statics and eigen-analyses of Gmsh-meshed "
                    "parts, two otherwise); "
                    "two, three: that many levels per source; off: no twin (default: the scene's output.error_bar, on)")
        ->check(CLI::IsMember({"on", "off", "two", "three"}));
  }

  void add_replay() {
    cmd_replay = app.add_subcommand(
        "replay", "re-render frames, plots, a movie or mesh exports from a stored results.h5 (no solve)");
    cmd_replay->add_option("results", replay_opt.results, "results.h5 or a run folder")->required();
    cmd_replay->add_option("--out", replay_opt.out_dir, "output folder (default: <run folder>/replay)");
    cmd_replay->add_option("--field", replay_field, "colour field stored in the file, or none (default: the run's)");
    cmd_replay->add_option("--camera", replay_opt.camera, std::string(kCameraHelp) + " (default: the run's view)");
    cmd_replay->add_option("--size", replay_opt.size, "frame size WxH, e.g. 1280x720 (default: the run's)");
    cmd_replay->add_option("--frame-every", replay_opt.frame_every, "every n-th stored frame (the last is always shown)")
        ->check(CLI::Range(1, 1000000));
    cmd_replay->add_flag("--movie", replay_opt.movie, "also assemble the frames into DIR/movie.mp4");
    cmd_replay->add_option("--fps", replay_opt.fps, "movie frames per second")->check(CLI::Range(1, 240));
    cmd_replay->add_option("--export", replay_opt.export_formats,
                       "write the replayed frames' deformed mesh to DIR/export: vtu (+ .pvd), gltf (.glb), obj");
    cmd_replay->add_option("--mode", replay_opt.modes,
                       "of a stored modal or buckling analysis, animate only these modes, e.g. --mode 2 or --mode 1,3 "
                       "(default: every stored mode)")
        ->delimiter(',')
        ->check(CLI::PositiveNumber);
    cmd_replay->add_flag("--no-frames", replay_no_frames, "skip PNG frames");
    cmd_replay->add_flag("--no-plots", replay_no_plots, "skip plots");
  }

  void add_check() {
    cmd_check = app.add_subcommand("check", "validate a scene without running it");
    cmd_check->add_option("scene", check_scene, "scene file or bundled scene name")->required();
    cmd_check->add_option("--set", check_overrides, "override a scene key")->take_all();
    check_picture_opt = cmd_check->add_option(
        "--picture", check_picture,
        "also draw the shell structure to this PNG file (its folder must exist): parts, named groups and the nodes "
        "every bc, load, probe, joint and arc selects, coloured and labelled");
  }

  void add_scenes() {
    cmd_scenes = app.add_subcommand("scenes", "list bundled scenes, or print the scene key reference");
    cmd_scenes->add_flag("--reference", reference, "print every scene key as a markdown table");
  }

  void add_compare() {
    cmd_compare = app.add_subcommand("compare", "overlay the probes of several runs (results.h5 or run folders)");
    cmd_compare->add_option("runs", compare_inputs, "results.h5 files or run folders")->required()->expected(1, -1);
    cmd_compare->add_option("--out", compare_out, "output folder for the overlay plots");
  }

  void add_bench() {
    cmd_bench = app.add_subcommand(
        "bench", "measure steps/s of the bundled hub-beam scenes, EFG/FEM cost, frames/s; --solve, --effects, --scene: "
                 "other measurements");
    cmd_bench->add_option("--repeat", bench_opt.repeat, "repetitions per measurement (median is reported)")
        ->check(CLI::Range(1, 1000));
    cmd_bench->add_option("--out", bench_opt.out_file, "also write the results as JSON to this file");
    cmd_bench->add_flag("--effects", bench_opt.effects,
                    "only the time saved by effects left out (no mass matrix, 5 vs 6 DoF, hr/ans, coupling order)");
    cmd_bench->add_option("--plate", bench_opt.effects_plate, "--effects: elements per side of the plate")
        ->check(CLI::Range(2, 512));
    cmd_bench->add_flag("--solve", bench_opt.solve,
                    "only a static Newton iteration on n x n plates: assembly against factorization + solve per linear "
                    "backend");
    cmd_bench->add_option("--max-n", bench_opt.solve_max_n, "--solve: largest plate (16, 32, 64, 128, 256)")
        ->check(CLI::Range(16, 256));
    cmd_bench->add_option("--backend", bench_opt.solve_backend, "--solve: only this linear backend (e.g. mumps)")
        ->check(CLI::IsMember({"umfpack", "sparse_lu", "mumps"}));
    cmd_bench->add_option("--ranks", bench_opt.solve_ranks,
                      "--solve: MUMPS over each of these MPI rank counts and 1, e.g. --ranks 2,4: launches this "
                      "flexframe (MUMPS's MPI build) under mpiexec once per count and prints one table with the "
                      "speed-up against 1 rank")
        ->delimiter(',')
        ->check(CLI::Range(1, 4096))
        ->needs(cmd_bench->get_option("--solve"));
    cmd_bench->add_option("--rounds", bench_opt.solve_rounds,
                      "--ranks: alternated rounds of the launches (the rank counts' order reversed every other round); "
                      "times are medians over the rounds and each speed-up the median of the rounds' own ratios")
        ->check(CLI::Range(1, 100))
        ->needs(cmd_bench->get_option("--ranks"));
    cmd_bench->add_option("--json", bench_opt.out_file, "same as --out: write the results as JSON to this file");
    cmd_bench->add_option("--scene", bench_opt.scenes,
                      "only whole runs of this scene (bundled name or file; repeatable): wall time, steps, "
                      "corrections, matrix updates, median of --repeat");
    cmd_bench->add_option("--modes", bench_opt.modes,
                      "time N natural modes of clamped plates against one factorization (16 .. --max-n elements a side)")
        ->check(CLI::Range(1, 500));
    cmd_bench->add_option("--estimate", bench_opt.estimate_dofs,
                      "only MUMPS's analysis estimates (flops, factor entries, MB per rank) for plates of about these "
                      "many DoFs, e.g. --estimate 1e6 1e7; under mpirun -n K, for K ranks")
        ->check(CLI::Range(20.0, 5e7));
    cmd_bench->add_flag("--error-bars", bench_opt.error_bars,
                    "what the error bars cost: each scene's run with --error-bar on against off, --repeat alternated "
                    "pairs (default scenes: the default job and four short static, eigen and dynamic scenes; --scene "
                    "picks others)");
    cmd_bench->add_option("--set", bench_opt.overrides, "--scene, --error-bars: override a scene key in every run, e.g. --set solver.tolerance=1e-6")
        ->take_all();
  }

  void add_study() {
    cmd_study = app.add_subcommand(
        "study", "what accuracy costs: run variants of a scene, error vs wall time, iterations and memory");
    cmd_study->add_option("target", study_opt.target,
                      "bundled study (flexframe study --list), study file, or scene file / bundled scene name");
    cmd_study->add_option("--vary", study_opt.vary,
                      "KEY=V1,V2,... or KEY1+KEY2=V1,V2,... (keys set together); several --vary form a grid")
        ->take_all();
    cmd_study->add_option("--set", study_opt.overrides, "override a scene key in every run")->take_all();
    cmd_study->add_option("--metric", study_opt.metric, "summary metric whose error is measured");
    cmd_study->add_option("--reference", study_opt.reference,
                      "finest (default: every axis at its last value), a number, or scene:NAME");
    cmd_study->add_option("--baseline", study_opt.baseline, "same as --reference scene:BASELINE");
    cmd_study->add_flag("--each", study_opt.each, "vary one axis at a time instead of every combination");
    cmd_study->add_option("--repeat", study_opt.repeat, "timing repetitions per variant (median)")->check(CLI::Range(1, 1000));
    cmd_study->add_option("--out", study_opt.out_dir, "output folder (default out/study/<name>): study.csv, study.md, pareto.png");
    cmd_study->add_flag("--check", study_opt.check_only, "validate every variant without running");
    cmd_study->add_option("--jobs,-j", study_opt.jobs,
                      "variants at a time, each a single-threaded process (default: the machine's cores; 1 = in "
                      "sequence in this process)")
        ->check(CLI::Range(1, 4096));
    cmd_study->add_option("--timing", study_timing,
                      "shared (default): times as measured side by side, marked shared; exclusive: the timed "
                      "repetitions run one at a time after the side-by-side pass")
        ->check(CLI::IsMember({"shared", "exclusive"}));
    cmd_study->add_flag("--resume", study_opt.resume,
                    "keep the variants whose run folder (OUT/runs/NNN/summary.json) is complete; run the rest");
  }

  void add_study_variant() {
    // study-variant: one variant in a child process of `study --jobs N` (hidden)
    cmd_study_variant = app.add_subcommand("study-variant", "one variant of a study (internal)");
    cmd_study_variant->group("");
    cmd_study_variant->add_option("scene", variant_opt.scene)->required();
    cmd_study_variant->add_option("--set", variant_opt.overrides)->take_all();
    cmd_study_variant->add_option("--reps", variant_opt.reps)->check(CLI::Range(1, 1000));
    cmd_study_variant->add_option("--result", variant_opt.result)->required();
    cmd_study_variant->add_flag("--shared", variant_opt.shared);
    cmd_study->add_flag("--list", study_list, "list the bundled studies");
    cmd_study->add_flag("--reference-keys", study_reference, "print the study file keys as a markdown table");
  }

  void add_policies() {
    cmd_policies = app.add_subcommand(
        "policies", "NOI/NOU and wall time per iteration-matrix policy and step (the shell paper's Tables 3-4)");
    cmd_policies->add_option("scene", pol_opt.scene, "shell scene with analysis = \"dynamic\" (file or bundled name)");
    cmd_policies->add_option("--dt", pol_dts, "time steps, comma separated");
    cmd_policies->add_option("--policies", pol_policies, "comma separated: full, frozen, nni:<i>, lazy, lazy:<refresh ratio>, lazy:<refresh ratio>:<step refresh ratio>");
    cmd_policies->add_option("--until", pol_opt.until, "simulated time per run [s]")->check(CLI::PositiveNumber);
    cmd_policies->add_option("--set", pol_opt.overrides, "override a scene key in every run")->take_all();
    cmd_policies->add_option("--out", pol_opt.out_dir, "output folder (policies.csv, policies.md, policies.png)");
  }

  void add_gui() {
    cmd_gui = app.add_subcommand("gui", "interactive window: edit a scene, run/pause/step it, watch it and its probes");
    cmd_gui->add_option("scene", gui_scene, "scene file or bundled scene name (default: " + default_scene() + ")");
    cmd_gui->add_option("--set", gui_opt.overrides, "override a scene key, e.g. --set solver.dt=0.01")->take_all();
    cmd_gui->add_option("--actions", gui_opt.actions_file,
                    "run a script of GUI actions, one per line: run, pause, step [N], reset, set KEY VALUE, "
                    "wait SECONDS, screenshot FILE, probe NODE, save FILE, export FILE, redraws, quit");
    cmd_gui->add_option("--screenshot", gui_opt.screenshot, "write the window as PNG just before quitting");
    cmd_gui->add_option("--quit-after", gui_opt.quit_after, "quit after this many seconds")->check(CLI::NonNegativeNumber);
    cmd_gui->add_option("--new", gui_opt.new_problem,
                    "start from a new problem (a 1 m steel plate to set up) instead of a scene: static or dynamic")
        ->check(CLI::IsMember({"static", "dynamic"}))
        ->excludes(cmd_gui->get_option("scene"));
    cmd_gui->add_flag("--run", gui_opt.run, "start the solver at once (default: paused at t = 0)");
    cmd_gui->add_option("--width", gui_opt.width, "window width in pixels")->check(CLI::Range(640, 8192));
    cmd_gui->add_option("--height", gui_opt.height, "window height in pixels")->check(CLI::Range(480, 8192));
  }

  int run(std::atomic<bool>& interrupt, const std::atomic<int>& interrupt_signal);
  int run_verb(const std::atomic<bool>& stop, std::atomic<bool>& interrupt, const std::atomic<int>& interrupt_signal,
               bool follower, bool one_model_over_ranks, const std::function<int(int)>& leave);
};

int CommandLine::Verbs::run(std::atomic<bool>& interrupt, const std::atomic<int>& interrupt_signal) {
  // Under mpirun (or srun) only run and bench share one model over the ranks and study spreads its
  // variants over them; any other verb would run once per rank, each writing the same folder
  if (ff::launched_ranks() > 1 && !app.get_subcommands().empty() && !(*cmd_run || *cmd_bench || *cmd_study)) {
    if (ff::launched_rank() == 0)
      std::fprintf(stderr, "error: flexframe %s runs as one process: under mpirun only run and bench (one model over the "
                           "ranks) and study (its variants over the ranks) use them\n",
                   app.get_subcommands().front()->get_name().c_str());
    return 2;
  }

  // `bench --solve --ranks K`: this process launches the ranks itself (it refuses to run under mpirun)
  if (*cmd_bench && !bench_opt.solve_ranks.empty()) return run_solve_bench_over_ranks(bench_opt, interrupt);

  // MUMPS's MPI build starts MPI before its first instance. In a process started without mpirun
  // Open MPI then forks its helper daemon (a "singleton" start), which inherits every file open at
  // that moment, results.h5 and its lock among them, and holds them while it lives: an
  // eigen-analysis's mode pictures, reading results.h5 back, found it locked. So MPI starts
  // before anything is opened (no effect in the sequential build).
  if ((*cmd_run || *cmd_bench || *cmd_gui) && ff::distributed_linear_solver_built()) ff::ensure_solver_mpi();

  // One model over MPI ranks (core/solve/distributed.md): `mpirun -n K flexframe run|bench`
  // factorizes over all K ranks; every rank runs the same model, rank 0 alone writes and prints
  const bool one_model_over_ranks = ff::launched_ranks() > 1 && (*cmd_run || *cmd_bench);
  if (one_model_over_ranks) {
    if (!ff::share_linear_solvers_over_world()) {
      std::fprintf(stderr,
                   "error: this flexframe was built with the sequential MUMPS: run and bench take one process "
                   "(configure with -DFLEXFRAME_MUMPS=mpi to run one model over MPI ranks)\n");
      return 2;
    }
    if (ff::linear_solver_rank() != 0 && !std::freopen("/dev/null", "w", stdout)) return 1;
  }
  const bool follower = one_model_over_ranks && ff::linear_solver_rank() != 0;
  // rank 0 decides when a run or bench over ranks stops: the others ignore Ctrl-C (which mpirun
  // forwards to every rank) and are ended by rank 0 (end_all_ranks)
  if (follower) std::signal(SIGINT, SIG_IGN);
  // ... and every rank sees rank 0's stop at the same shared solver call (solver_ranks.h): the run
  // and the benches watch this flag on every rank, so the ranks stop at the same step together
  static std::atomic<bool> stop_over_ranks{false};
  if (one_model_over_ranks) ff::share_stop_over_ranks(&interrupt, &stop_over_ranks);
  const std::atomic<bool>& stop = one_model_over_ranks ? stop_over_ranks : interrupt;
  // an error on one rank (its output folder, say) ends every rank: the others would wait for it
  const std::function<int(int)> leave = [&](int code) {
    if (one_model_over_ranks) {
      std::fflush(stdout);
      std::fflush(stderr);
      ff::end_all_ranks(code);
    }
    return code;
  };

  try {
    return run_verb(stop, interrupt, interrupt_signal, follower, one_model_over_ranks, leave);
  } catch (const ff::scene::SceneError& e) {
    // over ranks every rank reads the same scene and meets the same error: rank 0 says it
    if (!follower) std::fprintf(stderr, "error: invalid scene or study file\n%s\n", e.what());
    return leave(2);
  } catch (const ff::SetupInterrupted& e) {  // a signal while the model was being built: nothing was written
    std::fprintf(stderr, "\n%s; nothing was written\n", e.what());
    return leave(130);
  } catch (const InputError& e) {
    if (!follower) std::fprintf(stderr, "error: %s\n", e.what());  // the same on every rank
    return leave(2);
  } catch (const std::exception& e) {  // output folder, HDF5 file, ...: the run failed
    std::fprintf(stderr, "error: %s\n", e.what());
    return leave(1);
  }
  return 0;
}

int CommandLine::Verbs::run_verb(const std::atomic<bool>& stop, std::atomic<bool>& interrupt,
                                 const std::atomic<int>& interrupt_signal, bool follower,
                                 bool one_model_over_ranks, const std::function<int(int)>& leave) {
  if (*cmd_run) {
    run_opt.scene_path = resolve_scene(run_scene_arg.empty() ? default_scene() : run_scene_arg);
    run_opt.frames = !no_frames;
    run_opt.plots = !no_plots;
    if (!error_bar.empty()) {
      run_opt.error_bar_levels = error_bar == "off" ? 0 : error_bar == "two" ? 2 : error_bar == "three" ? 3 : -1;
      // the scene's key too: the solver records the error indicator field only with bars on
      run_opt.overrides.push_back(std::string("output.error_bar=") + (error_bar == "off" ? "false" : "true"));
    }
    run_opt.progress = !quiet;
    run_opt.stop_signal = &interrupt_signal;
    if (follower) {
      const int code = follow_run(run_opt, stop);
      ff::finish_solver_mpi();  // reached only when rank 0 completed too (else it ended every rank)
      return code;
    }
    const RunResult r = run_scene(run_opt, stop);
    print_result(r);
    const int code = exit_code(r.outcome);
    // a run that did not complete may have left the other ranks waiting in a collective call for
    // this one: end them all, with this run's exit code (its results are written and closed)
    if (r.outcome.status != ff::RunStatus::completed) leave(code);
    ff::finish_solver_mpi();
    return code;
  }
  if (*cmd_replay) {
    if (!replay_field.empty()) replay_opt.field = replay_field;
    replay_opt.frames = !replay_no_frames;
    replay_opt.plots = !replay_no_plots;
    return replay(replay_opt, interrupt);
  }
  if (*cmd_check) {
    if (check_picture_opt->count() > 0) check_picture_path(check_picture);  // before any work
    std::printf("%s\n",
                ff::scene::check_scene_report(resolve_scene(check_scene), check_overrides,
                                              ff::io::scene_context(&interrupt)).c_str());
    std::printf("%s\n", error_bar_plan_text(resolve_scene(check_scene), check_overrides).c_str());
    if (check_picture_opt->count() > 0)
      std::printf("%s\n", write_check_picture(resolve_scene(check_scene), check_overrides,
                                                       check_picture, ff::io::scene_context(&interrupt)).c_str());
    return 0;
  }
  if (*cmd_scenes) {
    if (reference) {
      std::printf("%s", ff::scene::scene_reference_markdown().c_str());
    } else {
      std::printf("bundled scenes in %s:\n", scene_dir().c_str());
      for (const std::string& s : bundled_scenes()) std::printf("  %s\n", s.c_str());
    }
    return 0;
  }
  if (*cmd_gui) {
    gui_opt.scene_path = resolve_scene(gui_scene.empty() ? default_scene() : gui_scene);
    return gui::run_gui(gui_opt, interrupt);
  }
  if (*cmd_compare) return compare_runs(compare_inputs, compare_out);
  if (*cmd_bench) {
    // over ranks, the benches of one model only: the others time one process, and the effects
    // bench's rounds stop on timings that differ between ranks, so its ranks would part ways in a
    // shared call (MPI_ERR_TRUNCATE)
    const bool one_model_bench = !bench_opt.estimate_dofs.empty() || bench_opt.modes > 0 ||
                                 !bench_opt.scenes.empty() || bench_opt.solve;
    if (one_model_over_ranks && !one_model_bench) {
      if (!follower)
        std::fprintf(stderr, "error: under mpirun, bench takes --solve, --scene, --modes or --estimate (one model over "
                             "the ranks); the hub-beam and --effects benches time one process: run them without "
                             "mpirun\n");
      ff::finish_solver_mpi();  // every rank refuses alike
      return 2;
    }
    if (follower) bench_opt.out_file.clear();  // rank 0 writes the JSON
    const int code = !bench_opt.estimate_dofs.empty() ? run_estimate_bench(bench_opt, stop)
                     : bench_opt.modes > 0          ? run_modes_bench(bench_opt, stop)
                     : bench_opt.error_bars    ? run_error_bar_bench(bench_opt, stop)
                     : !bench_opt.scenes.empty() ? run_scene_bench(bench_opt, stop)
                     : bench_opt.solve         ? run_solve_bench(bench_opt, stop)
                     : bench_opt.effects       ? run_effects_bench(bench_opt, stop)
                                               : run_bench(bench_opt, stop);
    // a rank that stopped alone ends every rank (the others may wait for it in a shared call)
    if (code != 0) leave(code);
    ff::finish_solver_mpi();
    return code;
  }
  if (*cmd_policies) {
    auto split = [](const std::string& s) {
      std::vector<std::string> out;
      std::stringstream ss(s);
      for (std::string item; std::getline(ss, item, ',');)
        if (!item.empty()) out.push_back(item);
      return out;
    };
    pol_opt.dts = split(pol_dts);
    pol_opt.policies = split(pol_policies);
    return run_policy_table(pol_opt, interrupt);
  }
  if (*cmd_study) {
    if (study_list) {
      for (const auto& [name, path] : bundled_studies()) {
        const StudySpec spec = read_study_file(path);
        std::printf("%-32s %s\n", name.c_str(), spec.description.c_str());
      }
      return 0;
    }
    if (study_reference) {
      std::cout << study_reference_markdown();
      return 0;
    }
    if (study_opt.target.empty()) throw InputError("study needs a bundled study, study file or scene");
    const StudySpec spec = make_study_spec(study_opt);
    try {
      if (study_opt.check_only) return check_study(spec);
      study_opt.exclusive_timing = study_timing == "exclusive";
      return run_study(spec, study_opt, interrupt);
    } catch (const ff::scene::SceneError& e) {  // an override the study file wrote: its line there
      std::vector<ff::scene::Issue> issues = e.issues;
      locate_in_study_file(spec, issues);
      throw ff::scene::SceneError(issues);
    }
  }
  if (*cmd_study_variant) return run_study_variant(variant_opt, interrupt);
  return 0;
}

CommandLine::CommandLine() : verbs_(std::make_unique<Verbs>()) {}
CommandLine::~CommandLine() = default;

std::optional<int> CommandLine::parse(int argc, char** argv) {
  try {
    verbs_->app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are not errors; every other usage error is bad input (exit 2)
    const int code = verbs_->app.exit(e);
    return e.get_exit_code() == 0 ? code : 2;
  }
  return std::nullopt;
}

int CommandLine::run(std::atomic<bool>& interrupt, const std::atomic<int>& interrupt_signal) {
  return verbs_->run(interrupt, interrupt_signal);
}

}  // namespace ff::app
