#include "app/run_session.h"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <csignal>

#include <algorithm>
#include <atomic>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <stdexcept>
#include <thread>

#include "app/io/mesh_import.h"
#include "app/frame_outputs.h"
#include "app/launcher_watchdog.h"
#include "app/io/results.h"
#include "app/mode_outputs.h"
#include "app/output_folder.h"
#include "app/output_pipeline.h"
#include "app/run_summary.h"
#include "app/view_options.h"
#include "core/assembly/element_threads.h"
#include "core/frame/input_file.h"
#include "core/solve/solver_ranks.h"
#include "core/scene/scene.h"
#include "render/frame_layout.h"

namespace fs = std::filesystem;

namespace ff::app {

namespace {

// a quarter of the machine's memory, at most 2 GB: what the frames kept for drawing after the
// solve may hold by default
double default_frame_memory_mb() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  const double machine_mb = pages > 0 && page > 0 ? 1e-6 * static_cast<double>(pages) * static_cast<double>(page) : 8000.0;
  return std::min(2048.0, 0.25 * machine_mb);
}

// "[lo, hi]" exactly (results.h5 attribute color_range)
std::string format_range(const std::array<double, 2>& r) {
  char text[64];
  std::snprintf(text, sizeof text, "[%.17g, %.17g]", r[0], r[1]);
  return text;
}
std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "--:--";
  const long t = std::lround(s);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld", t / 60, t % 60);
  return buf;
}

}  // namespace

std::string scene_dir() {
  // next to the build tree first (build/flexframe -> ../assets/scenes), then the source tree
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path candidate = exe.parent_path().parent_path() / "assets" / "scenes";
    if (fs::is_directory(candidate)) return candidate.string();
  }
  return std::string(FF_ASSET_DIR) + "/scenes";
}

std::vector<std::string> bundled_scenes() {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(scene_dir()))
    if (e.path().extension() == ".toml") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::string default_scene() { return "double_pendulum_shells"; }

std::string resolve_scene(const std::string& name) {
  if (fs::is_regular_file(name)) return name;
  // there, but a FIFO, a device or a link to one: said so, not looked up among the bundled scenes
  std::error_code ec;
  if (const fs::file_status st = fs::symlink_status(name, ec); !ec && fs::exists(st) && !fs::is_directory(name, ec))
    throw InputError("scene file '" + name + "' " + input_file_problem(name, kMaxTextInputBytes, kTextInputBound));
  const fs::path bundled = fs::path(scene_dir()) / (name + ".toml");
  if (fs::is_regular_file(bundled)) return bundled.string();
  std::string msg = "no scene file '" + name + "' and no bundled scene of that name in " + scene_dir() +
                    " (bundled:";
  for (const std::string& s : bundled_scenes()) msg += " " + s;
  throw InputError(msg + ")");
}

int follow_run(const RunOptions& opt, const std::atomic<bool>& stop) {
  scene::LoadedScene scene = scene::load_scene(opt.scene_path, opt.overrides, io::scene_context(&stop));
  const RunOutcome outcome = scene.simulation->run([](Frame&&) {}, stop);
  return exit_code(outcome);
}

RunResult run_scene(const RunOptions& opt, const std::atomic<bool>& stop) {
  const auto wall0 = std::chrono::steady_clock::now();
  scene::LoadedScene scene = scene::load_scene(opt.scene_path, opt.overrides, io::scene_context(&stop));
  RunOptions timed = opt;
  timed.setup_wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return run_loaded_scene(timed, std::move(scene), stop);
}

namespace {

// every answer metric with its discretization error, from coarser twins solved while the render
// thread draws the frames (core/model/error_bars.md); only a completed run has answers to bar.
// A twin whose path differs in kind is no coarser answer: its metrics are flagged, and the run
// says so where the user looks and records it with its path's events (error_bars.md §6).
void bar_the_metrics(const RunOptions& opt, const scene::LoadedScene& scene, Simulation& sim, RunOutcome& outcome,
                     RunResult& result, const std::atomic<bool>& stop) {
  const int bar_levels = opt.error_bar_levels.value_or(scene.output.error_bar ? -1 : 0);
  if (bar_levels == 0) return;
  ErrorBarReport& bars = result.error_bars;
  bars.on = true;
  if (outcome.status != RunStatus::completed) {
    bars.not_estimated = "the run did not complete";
    return;
  }
  if (linear_solver_ranks() > 1) {
    bars.not_estimated = "a run over MPI ranks runs no twins yet (--error-bar off skips this note)";
    return;
  }
  if (opt.progress) std::fprintf(stderr, "error bars: solving the coarser twins (--error-bar off skips them)\n");
  const int elements = scene.mesh_quality ? scene.mesh_quality->quality.quad_count : 0;
  try {
    bars = estimate_error_bars(opt.scene_path, opt.overrides, sim, outcome, opt.setup_wall_s, elements,
                               bar_levels < 0 ? 0 : bar_levels, result.field_error, stop);
  } catch (const std::exception& e) {  // the scene file changed under the run, or no file (a test's model)
    bars.not_estimated = std::string("the twins could not be planned: ") + e.what();
  }
  for (const TwinRun& t : bars.twins) {
    if (!t.path_differs()) continue;
    // a third level's twin only drops that level: the two finer ones still estimate
    const char* consequence = t.third_level() ? "the estimate falls back to the two finer levels"
                                              : "the metrics it would bar are flagged";
    std::fprintf(stderr, "warning: error bars: %s; %s (summary.json \"events\")\n", t.problem.c_str(), consequence);
    outcome.events.push_back({"twin_path_differs", outcome.steps, outcome.stop_time,
                              t.problem + ": a mesh-dependent path; " + consequence});
  }
  if (bars.interrupted && outcome.status == RunStatus::completed) {
    outcome.status = RunStatus::interrupted;
    outcome.reason = "interrupted by the user while the error-bar twins were solved; the solve had completed and "
                     "results.h5 holds every frame (--error-bar off skips the twins)";
  }
}

// Mesh exports of the frames, read back from results.h5 (closed by now); "" or what failed.
std::string export_stored_frames(const std::string& h5_path, const RunInfo& info, const scene::OutputSettings& out,
                                 const ExportFormats& formats, OutputFolder& folder, RunResult& result,
                                 const std::atomic<bool>& stop) {
  std::string e;
  const auto reader = io::ResultReader::open(h5_path, &e);
  if (!reader) return e;
  const int field = field_index(info, out.color_field);
  const auto frames = frame_selection(reader->frame_count(), out.frame_every, false);
  ExportReport x;
  try {
    const fs::path export_dir = folder.sub_folder("export");
    const auto [lo, hi] = field_range(*reader, frames, field);  // the frames' policy (SequenceView)
    x = export_frames(*reader, frames, formats, export_dir.string(), field, render::color_range_for(lo, hi), stop);
    for (const std::string& f : x.written) folder.record("export/" + f);
  } catch (const WriteError& w) {
    if (x.error.empty()) x.error = w.what();
  }
  result.frames_exported = x.frames;
  return x.error;
}

struct ModeOutputOrder {
  bool frames = true, plots = true;
  std::optional<render::Camera> camera;
  const scene::OutputSettings* out = nullptr;
  const ExportFormats* formats = nullptr;
};

// The modes' pictures, plot and export, about the last stored frame (as `replay` makes them);
// *error is what failed. A Ctrl-C that cut the pictures short makes the outcome `interrupted`.
ModeOutputReport write_run_mode_outputs(const std::string& h5_path, const RunOptions& opt, const ModeOutputOrder& order,
                                        const RunInfo& info, const ModeSet& modes, OutputFolder& folder,
                                        RunOutcome& outcome, std::string* error, const std::atomic<bool>& stop) {
  ModeOutputReport report;
  const auto reader = io::ResultReader::open(h5_path, error);
  if (!reader) return report;
  if (reader->frame_count() == 0) {
    *error = "no stored frame holds the state the modes are about";
    return report;
  }
  ModeOutputOptions mo;
  mo.modes = opt.animate_modes == 0 ? std::vector<int>{} : select_modes(modes, {}, opt.animate_modes);
  mo.frames = order.frames;
  mo.plot = order.plots;
  mo.movie = opt.movie;
  mo.vtu = order.formats->vtu;
  mo.fps = opt.fps;
  mo.width = order.out->width;
  mo.height = order.out->height;
  if (order.camera) mo.camera = *order.camera, mo.camera_given = true;
  report = write_mode_outputs(folder, info, reader->frame(reader->frame_count() - 1), modes, mo, nullptr, stop);
  *error = report.error;
  // pictures a Ctrl-C cut short: the run does not call itself completed (results.h5 keeps the modes)
  if (stop && outcome.status == RunStatus::completed && report.no_graphics.empty() &&
      (report.modes_animated < static_cast<int>(mo.modes.size()) || (mo.plot && !modes.modes.empty() && report.plot.empty()))) {
    outcome.status = RunStatus::interrupted;
    outcome.reason = "interrupted by the user while the mode pictures were drawn (" +
                     std::to_string(report.modes_animated) + " of " + std::to_string(mo.modes.size()) +
                     " modes animated); results.h5 holds every mode: `flexframe replay` draws them";
  }
  return report;
}

// Closes results.h5: the modes of an eigen-analysis, the twins' histories, the error bars and
// the render's attributes, then the outcome and metrics. Returns the outcome the file says.
RunOutcome close_results(StoredResults& stored, const ModeSet* modes, const OutputPipeline& pipeline, WriteFailure& failure,
                         const std::function<void()>& record_write_failure, const RunOutcome& outcome, RunResult& result) {
  std::unique_lock writer_lock(stored.mutex);
  io::ResultWriter& writer = *stored.writer;
  std::string err;
  // the modes, with the table, before the outcome (results_layout.md /modes)
  if (modes && !failure.any()) {
    result.modes = static_cast<int>(modes->modes.size());
    if (!writer.write_modes(*modes, &err)) failure.fail("results.h5: " + err);
  }
  // the twins' probe histories beside the run's frames (results_layout.md /error_bar_twins)
  for (const TwinRun& t : result.error_bars.twins) {
    if (t.history.time.empty() || failure.any()) continue;
    std::vector<std::string> names;
    for (const Quantity& q : t.info.probes) names.push_back(q.name);
    if (!writer.write_twin_history(t.name, t.description, t.history.time, names, t.history.probes, &err))
      failure.fail("results.h5: " + err);
  }
  record_write_failure();
  // the bars beside the frames they are about, for scripts and replay (results_layout.md /attributes)
  if (result.error_bars.on) writer.set_attribute("error_bars", error_bars_json(result.error_bars).dump());
  if (result.field_error) writer.set_attribute("field_error", field_error_json(*result.field_error).dump());
  if (!pipeline.render_backend.empty()) {
    writer.set_attribute("render_backend", pipeline.render_backend);
    writer.set_attribute("gl_renderer", pipeline.gl_renderer);
    if (pipeline.color_field >= 0) writer.set_attribute("color_range", format_range(pipeline.color_range));
  }
  const RunOutcome finished_with = outcome;  // what results.h5 says until amended
  if (!writer.finish(outcome, result.metrics, &err)) {
    // the writer's message says what is missing (the outcome, or frames after the last flush)
    std::fprintf(stderr, "error: results.h5 is incomplete: %s\n", err.c_str());
    failure.fail("results.h5: " + err);
    record_write_failure();
  }
  stored.writer.reset();
  stored.closed = true;
  return finished_with;
}

// results.h5 with the build's attributes; when it cannot be created, summary.json still says
// `failed` and why (nothing was computed), and the error is thrown
std::unique_ptr<io::ResultWriter> create_results(OutputFolder& folder, const std::string& h5_path, const RunInfo& info,
                                                 const scene::LoadedScene& scene) {
  std::string err;
  std::unique_ptr<io::ResultWriter> writer = io::ResultWriter::create(h5_path, info, &err);
  if (!writer) {
    folder.release_reserve();
    try {
      write_summary(folder, summary_before_any_frame(scene.name, scene.path, "results.h5 could not be created: " + err));
    } catch (const WriteError& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
    }
    throw std::runtime_error(err);
  }
  writer->set_attribute("flexframe_version", FF_VERSION);
  writer->set_attribute("git_commit", FF_GIT_COMMIT);
  writer->set_attribute("build_type", FF_BUILD_TYPE);
  return writer;
}

// The movie once the render thread has ended: its library loads while no other thread loads or
// unloads one (the GL driver does at the render thread's end; ThreadSanitizer cannot see the
// loader's own lock). Its failure still reaches results.h5's outcome, amended later.
void write_movie_after_frames(const RunOptions& opt, const fs::path& frames_dir, OutputFolder& folder,
                              WriteFailure& failure, RunResult& result, const std::atomic<bool>& stop) {
  if (!opt.movie || failure.any()) return;
  MovieReport m{false, "", "", 0, "no frames were rendered"};
  try {
    if (result.frames_rendered > 0) m = write_movie(frames_dir.string(), folder.file("movie.mp4").string(), opt.fps, stop);
  } catch (const WriteError& e) {
    m.message = e.what();
  }
  if (m.ok) result.movie = m.path;
  else if (result.frames_rendered > 0 && !stop) failure.fail("movie.mp4: " + m.message);
  else std::fprintf(stderr, "warning: no movie: %s\n", m.message.c_str());
}

// pictures the run could not make without failing: no graphics on this machine, frames beyond
// their memory budget
void warn_about_pictures(const OutputPipeline& pipeline) {
  if (pipeline.no_graphics && !pipeline.render_error.empty())
    std::fprintf(stderr, "warning: frames not rendered: %s\n", pipeline.render_error.c_str());
  if (!pipeline.frame_memory_note.empty()) std::fprintf(stderr, "warning: frames: %s\n", pipeline.frame_memory_note.c_str());
  if (pipeline.no_graphics && !pipeline.plot_error.empty())
    std::fprintf(stderr, "warning: plots: %s\n", pipeline.plot_error.c_str());
}

// Over MPI ranks, the caller's stop reaches the run's stop flag at a shared solver call, on
// every rank alike, while this lives (solver_ranks.h)
struct StopWithRanks {
  explicit StopWithRanks(std::atomic<bool>* flag) : on(flag != nullptr) {
    if (on) also_stop_with_ranks(flag);
  }
  ~StopWithRanks() {
    if (on) also_stop_with_ranks(nullptr);
  }
  StopWithRanks(const StopWithRanks&) = delete;
  StopWithRanks& operator=(const StopWithRanks&) = delete;
  bool on;
};

// A rank whose run does not complete (or throws) leaves the shared solvers before its model is
// destroyed (solver_ranks.h; nothing changes in one process)
struct LeaveSharedSolversUnlessCompleted {
  const bool& completed;
  ~LeaveSharedSolversUnlessCompleted() {
    if (!completed) leave_shared_solvers();
  }
};

// Progress on the calling thread until the solver is done: simulated time, steps/s and ETA.
void show_progress(const RunOptions& opt, const std::string& scene_name, const RunInfo& info, double t_end,
                   const StoredResults& results, SolverEnd& solver, std::atomic<bool>& run_stop, bool over_ranks_stop,
                   const std::atomic<bool>& stop) {
  const bool tty = isatty(STDERR_FILENO);
  const auto wall0 = std::chrono::steady_clock::now();
  auto last_print = wall0;
  while (!solver.done) {
    // over ranks run_stop changes only at a shared solver call (also_stop_with_ranks), where
    // every rank's does: set here, between two calls, it would stop rank 0 a step before the others
    if (stop && !over_ranks_stop) run_stop = true;
    {
      std::unique_lock lock(solver.mutex);
      solver.signal.wait_for(lock, std::chrono::milliseconds(100), [&] { return solver.done.load(); });
    }
    if (solver.done) break;
    const auto now = std::chrono::steady_clock::now();
    const double since = std::chrono::duration<double>(now - last_print).count();
    if (!opt.progress || since < (tty ? 0.25 : 2.0)) continue;
    last_print = now;
    const double wall = std::chrono::duration<double>(now - wall0).count();
    const double t = results.last_time, rate = results.last_step / std::max(wall, 1e-9);
    const double eta = t > 0 ? wall * (t_end - t) / t : NAN;
    std::fprintf(stderr, "%s%s: t = %.3f / %.3f %s | %lld steps | %.0f steps/s | ETA %s%s", tty ? "\r" : "",
                 scene_name.c_str(), t, t_end, info.time_unit.c_str(), static_cast<long long>(results.last_step), rate,
                 format_duration(eta).c_str(), tty ? "   " : "\n");
  }
}

}  // namespace

RunResult run_loaded_scene(const RunOptions& opt, scene::LoadedScene scene, const std::atomic<bool>& stop) {
  if (scene.mesh_quality)  // poor quads run, but the user hears of them before a long run
    for (const std::string& w : scene.mesh_quality->warnings()) std::fprintf(stderr, "warning: mesh quality: %s\n", w.c_str());
  for (const std::string& w : scene.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  Simulation& sim = *scene.simulation;
  const RunInfo info = sim.info();
  scene::OutputSettings out = scene.output;
  if (opt.frame_every) out.frame_every = *opt.frame_every;
  if (opt.width) out.width = *opt.width;
  if (opt.height) out.height = *opt.height;
  const bool want_frames = opt.frames && out.frames;
  // view and output options are checked before anything is written
  std::optional<render::Camera> camera;
  if (!opt.camera.empty()) camera = parse_camera(opt.camera);
  const ExportFormats formats = opt.export_formats.empty() ? ExportFormats{} : parse_export_formats(opt.export_formats);
  if (opt.movie && !want_frames) throw InputError("--movie needs the frames (no --no-frames, output.frames = true)");
  if (opt.fps < 1 || opt.fps > 240) throw InputError("--fps must be 1..240");
  if (opt.animate_modes < -1) throw InputError("--animate-modes must be 0 or more");

  RunResult result;
  result.scene_name = scene.name;
  // Over ranks, a run that does not complete here (or throws) leaves the other ranks in the solver
  // loop, and the model's MUMPS instances end with a call every rank must join: this rank leaves
  // the shared solvers before its model is destroyed, and the caller ends every rank next
  // (solver_ranks.h; nothing changes in one process)
  bool completed_here = false;
  const LeaveSharedSolversUnlessCompleted leave_unless_completed{completed_here};
  // the scene's name was checked to be one plain folder name (scene.cpp), so the default stays in out/
  result.out_dir = opt.out_dir.empty() ? (fs::path("out") / scene.name).string() : opt.out_dir;
  // the folder's lock comes before any file in it is touched (output_folder.h)
  OutputFolder folder(result.out_dir, "run");
  // what an earlier run wrote here would be mistaken for this run's: its recorded files go,
  // results.h5 is truncated by the writer (which refuses a file another process has open)
  for (const char* earlier : {"frames/", "plots/", "export/", "modes/", "movie.mp4", "summary.json"}) folder.remove_earlier(earlier);
  const fs::path frames_dir = folder.sub_folder("frames"), plots_dir = folder.sub_folder("plots");
  if (const std::size_t foreign = folder.unrecorded_files("frames", ".png"); foreign > 0)
    std::fprintf(stderr, "note: %zu PNG file(s) in %s were not written by a flexframe run and are left in place\n",
                 foreign, frames_dir.string().c_str());

  const std::string h5_path = folder.file("results.h5").string();
  StoredResults stored;
  stored.writer = create_results(folder, h5_path, info, scene);
  const auto run_start = std::chrono::steady_clock::now();

  // An output that cannot be written ends the run `failed` (exit 1) at once: the solver is
  // stopped through run_stop, which also follows the caller's stop flag.
  std::atomic<bool> run_stop{false};
  // over ranks the caller's stop reaches run_stop at a shared solver call, on every rank alike
  const bool over_ranks_stop = linear_solver_ranks() > 1;
  const StopWithRanks stop_with_ranks{over_ranks_stop ? &run_stop : nullptr};
  if (over_ranks_stop && stop) run_stop = true;  // a stop the set-up's shared calls already saw
  WriteFailure failure(folder, run_stop);

  OutputPipelineSettings drawing;
  drawing.scene_name = scene.name;
  drawing.out = out;
  drawing.frames = want_frames;
  drawing.plots = opt.plots && out.plots;
  drawing.plots_dir = plots_dir.string();
  drawing.camera = camera;
  drawing.frame_memory_mb = opt.frame_memory_mb > 0 ? opt.frame_memory_mb : default_frame_memory_mb();
  OutputPipeline pipeline(std::move(drawing), info, folder, stored, failure, stop);

  // solver on the worker thread
  SolverEnd solver;
  RunOutcome outcome;
  std::thread worker([&] {
    // frames render beside the solver: while a frame is being rendered the element loops leave
    // one core to the renderer, otherwise they use all (unless the user set OMP_NUM_THREADS); a
    // loop thread never waits at a barrier for a core the renderer holds (docs/performance.md)
    if (want_frames && !std::getenv("OMP_NUM_THREADS") && std::thread::hardware_concurrency() > 1)
      sim.set_element_threads(0, pipeline.render_busy());
    try {
      outcome = sim.run([&](Frame&& f) { pipeline.push(std::move(f)); }, run_stop);
      // Ctrl-C reaches the model's set-up through the scene context at once, and run_stop only at
      // the progress loop's next turn (at most 0.1 s): a set-up it stopped is an interruption
      if (outcome.status == RunStatus::failed && stop && !failure.any() && outcome.steps == 0)
        outcome.status = RunStatus::interrupted;
    } catch (const std::exception& e) {
      outcome.status = RunStatus::failed;
      outcome.reason = std::string("solver error: ") + e.what();
    }
    pipeline.close_input();
    solver.finish(outcome);
  });

  const bool over_ranks = linear_solver_ranks() > 1 && opt.stop_signal;
  LauncherWatchdog watchdog({opt.stop_signal, &stored, &solver, &folder, scene.name, scene.path, info.time_unit,
                             result.out_dir, run_start},
                            over_ranks);
  show_progress(opt, scene.name, info, sim.end_time(), stored, solver, run_stop, over_ranks_stop, stop);
  worker.join();
  pipeline.join_store();
  if (opt.progress && isatty(STDERR_FILENO)) std::fprintf(stderr, "\n");
  if (over_ranks && outcome.status == RunStatus::interrupted && *opt.stop_signal == SIGTERM)
    outcome.reason = launcher_stop_reason(outcome.steps, outcome.stop_time, info.time_unit);

  result.metrics = sim.metrics();
  result.totals = sim.totals();
  result.field_error = sim.field_error_estimate();  // the last state's, also of a run that stopped early
  bar_the_metrics(opt, scene, sim, outcome, result, stop);
  pipeline.provide_twins(result.error_bars.twins);
  pipeline.wait_frames();
  result.frames_rendered = pipeline.frames_rendered;
  result.render_seconds = pipeline.render_seconds;
  // the solve completed but its pictures did not: the run does not call itself completed
  if (!pipeline.drawing_stopped.empty() && outcome.status == RunStatus::completed) {
    outcome.status = RunStatus::interrupted;
    const bool by_launcher = over_ranks && *opt.stop_signal == SIGTERM;
    outcome.reason = std::string(by_launcher ? "stopped by SIGTERM from the MPI launcher" : "interrupted by the user") +
                     " while the frames were drawn (" + pipeline.drawing_stopped +
                     " drawn); the solve had completed and results.h5 holds every frame: `flexframe replay` draws them";
  }
  // a failed write is the run's outcome, whatever the solver would have said (it was stopped for it)
  const std::function<void()> record_write_failure = [&] {
    const std::string what = failure.what();
    if (what.empty() || outcome.status == RunStatus::failed) return;
    char at[64];
    std::snprintf(at, sizeof at, " (stopped at t = %g%s%s)", outcome.stop_time, info.time_unit.empty() ? "" : " ",
                  info.time_unit.c_str());
    outcome.status = RunStatus::failed;
    outcome.reason = "an output could not be written: " + what + at;
  };
  // results.h5 is closed under its lock; the launcher watchdog, once it has closed the file, keeps
  // the lock until it ends the process
  const ModeSet* modes = sim.modes();
  const RunOutcome finished_with = close_results(stored, modes, pipeline, failure, record_write_failure, outcome, result);
  pipeline.join_render();  // its last frames and the plots
  record_write_failure();  // the plots are written while results.h5 closes
  std::vector<std::string> plot_files = pipeline.plot_files;
  write_movie_after_frames(opt, frames_dir, folder, failure, result, stop);
  record_write_failure();
  warn_about_pictures(pipeline);
  const auto unreached = sim.metrics_unreached();  // kept in summary.json as null, with why
  for (const auto& [name, why] : unreached)
    std::fprintf(stderr, "warning: metric '%s' has no value: %s\n", name.c_str(), why.c_str());

  // exports and mode pictures read results.h5 back (closed by now): a failure here amends its
  // outcome below, as it goes into summary.json
  if (formats.any() && !failure.any()) {
    if (const std::string e = export_stored_frames(h5_path, info, out, formats, folder, result, stop); !e.empty()) {
      failure.fail("export: " + e);
      record_write_failure();
    }
  }
  ModeOutputReport mode_report;
  if (modes && !failure.any()) {
    std::string e;
    mode_report = write_run_mode_outputs(h5_path, opt, {want_frames, opt.plots && out.plots, camera, &out, &formats},
                                         info, *modes, folder, outcome, &e, stop);
    result.modes_animated = mode_report.modes_animated;
    if (!mode_report.plot.empty()) plot_files.push_back(mode_report.plot);
    if (!mode_report.no_graphics.empty()) std::fprintf(stderr, "warning: mode pictures not drawn: %s\n", mode_report.no_graphics.c_str());
    if (!e.empty()) {
      failure.fail("modes: " + e);
      record_write_failure();
    }
  }
  // one outcome in both records, summary.json written last: what the outputs after finish() did
  // to the verdict (a Ctrl-C, a full disk) goes into results.h5 first
  if (outcome.status != finished_with.status || outcome.reason != finished_with.reason) {
    folder.release_reserve();
    if (std::string e; !io::amend_outcome(h5_path, outcome, &e)) {
      std::fprintf(stderr, "error: %s\n", e.c_str());
      failure.fail("results.h5: " + e);
      outcome.status = RunStatus::failed;
      outcome.reason += "; results.h5 still says '" + std::string(to_string(finished_with.status)) +
                        "': its outcome could not be updated (" + e + ")";
    }
  }
  result.outcome = outcome;
  if (failure.any()) std::fprintf(stderr, "error: %s\n", outcome.reason.c_str());

  RunSummaryInputs summary{&scene, &info, &result, unreached, sim.effect_stats(), &pipeline, plot_files, modes,
                           &mode_report, out.color_field};
  try {
    write_summary(folder, run_summary(summary));
  } catch (const WriteError& e) {  // exit 1, and results.h5 says so too
    RunOutcome failed = outcome;
    failed.status = RunStatus::failed;
    failed.reason = std::string("summary.json could not be written: ") + e.what();
    folder.release_reserve();
    io::amend_outcome(h5_path, failed, nullptr);
    throw;
  }
  completed_here = result.outcome.status == RunStatus::completed;
  return result;
}

}  // namespace ff::app
