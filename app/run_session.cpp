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
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <future>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "app/io/mesh_import.h"
#include "app/channel.h"
#include "app/frame_outputs.h"
#include "app/io/results.h"
#include "app/mode_outputs.h"
#include "app/output_folder.h"
#include "app/plots.h"
#include "app/refine_picture.h"
#include "app/view_options.h"
#include "core/assembly/element_threads.h"
#include "core/frame/input_file.h"
#include "core/solve/solver_ranks.h"
#include "core/scene/scene.h"
#include "core/shell/error_indicator.h"
#include "render/frame_layout.h"
#include "render/frame_renderer.h"
#include "render/graphics_context.h"

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
// Over MPI ranks, how long after SIGTERM the run may take to close results.h5 itself before the
// launcher watchdog closes it (Open MPI sends SIGKILL 1 s after SIGTERM: odls_base_sigkill_timeout)
constexpr double kLauncherGraceS = 0.3;

// The outcome's reason when the MPI launcher's SIGTERM stopped a run shared over ranks
std::string launcher_stop_reason(long long steps, double t, const std::string& unit) {
  char at[96];
  std::snprintf(at, sizeof at, " at step %lld, t = %g %s", steps, t, unit.c_str());
  return std::string("stopped by SIGTERM from the MPI launcher") + at +
         ": another rank may have died, or the job was cancelled";
}

constexpr std::size_t kStoreChannelCapacity = 256;  // frames the solver may run ahead of the store
constexpr std::size_t kRenderChannelCapacity = 8;   // frames queued for PNG output

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "--:--";
  const long t = std::lround(s);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld", t / 60, t % 60);
  return buf;
}

// summary.json "mesh_quality": counts, per metric the worst quad (number and name), the median,
// the limit and the quads past it (worst first, at most 20 numbers), and the warnings' sentences
nlohmann::ordered_json mesh_quality_json(const scene::MeshQualityReport& r) {
  using Json = nlohmann::ordered_json;
  Json metrics = Json::object();
  for (int k = 0; k < mesh::quality_metric_count; ++k) {
    const mesh::MetricSummary& s = r.quality.metrics[k];
    const auto m = static_cast<mesh::QualityMetric>(k);
    Json past = Json::array();
    for (std::size_t i = 0; i < s.beyond.size() && i < 20; ++i) past.push_back(s.beyond[i]);
    metrics[mesh::metric_key(m)] = {{"unit", mesh::metric_unit(m)},
                                    {"worst", s.worst_quad >= 0 ? Json(s.worst) : Json()},
                                    {"worst_quad", s.worst_quad},
                                    {"worst_element", s.worst_quad >= 0 ? r.quad_name(s.worst_quad) : ""},
                                    {"typical", s.worst_quad >= 0 ? Json(s.typical) : Json()},
                                    {"limit", s.limit},
                                    {"past_limit", s.beyond.size()},
                                    {"past_limit_quads", past}};
  }
  return {{"quads", r.quality.quad_count}, {"nodes", r.quality.node_count}, {"parts", r.part_names.size()},
          {"poor_quads", r.quality.poor_count()}, {"metrics", metrics}, {"warnings", r.warnings()}};
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

int exit_code(const RunOutcome& o) {
  switch (o.status) {
    case RunStatus::completed: return 0;
    case RunStatus::incomplete: return 4;
    case RunStatus::diverged: return 3;
    case RunStatus::interrupted: return 130;
    case RunStatus::failed: return 1;
  }
  return 1;
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
  struct LeaveSharedSolversUnlessCompleted {
    const bool& completed;
    ~LeaveSharedSolversUnlessCompleted() {
      if (!completed) leave_shared_solvers();
    }
  } leave_unless_completed{completed_here};
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

  std::string err;
  const std::string h5_path = folder.file("results.h5").string();
  std::unique_ptr<io::ResultWriter> writer = io::ResultWriter::create(h5_path, info, &err);
  if (!writer) {
    // nothing was computed; summary.json still says `failed` and why, as after any failed write
    folder.release_reserve();
    const nlohmann::ordered_json summary = {{"scene", scene.name},   {"scene_path", scene.path},
                                            {"status", "failed"},    {"reason", "results.h5 could not be created: " + err},
                                            {"steps", 0},            {"metrics", nlohmann::ordered_json::object()},
                                            {"outputs", nlohmann::ordered_json::object()}};
    try {
      write_text_file(folder.file("summary.json"), summary.dump(2) + "\n");
    } catch (const WriteError& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
    }
    throw std::runtime_error(err);
  }
  writer->set_attribute("flexframe_version", FF_VERSION);
  writer->set_attribute("git_commit", FF_GIT_COMMIT);
  writer->set_attribute("build_type", FF_BUILD_TYPE);
  // the writer is used by one thread at a time: the store thread's appends, the closing below and,
  // over MPI ranks, the launcher watchdog, which may close it while the solver thread is blocked
  std::mutex writer_mutex;
  std::atomic<bool> writer_closed{false};  // set under writer_mutex
  const auto run_start = std::chrono::steady_clock::now();

  // An output that cannot be written ends the run `failed` (exit 1) at once: the solver is
  // stopped through run_stop, which also follows the caller's stop flag.
  std::atomic<bool> run_stop{false};
  // over ranks the caller's stop reaches run_stop at a shared solver call, on every rank alike
  const bool over_ranks_stop = linear_solver_ranks() > 1;
  struct StopWithRanks {
    explicit StopWithRanks(std::atomic<bool>* flag) : on(flag != nullptr) {
      if (on) also_stop_with_ranks(flag);
    }
    ~StopWithRanks() {
      if (on) also_stop_with_ranks(nullptr);
    }
    bool on;
  } stop_with_ranks{over_ranks_stop ? &run_stop : nullptr};
  if (over_ranks_stop && stop) run_stop = true;  // a stop the set-up's shared calls already saw
  std::mutex failure_mutex;
  std::string write_failure;  // the first failed write, for the reason
  const auto fail_write = [&](const std::string& what) {
    {
      std::lock_guard lock(failure_mutex);
      if (write_failure.empty()) write_failure = what;
    }
    folder.release_reserve();  // room for the outcome in results.h5 and for summary.json
    run_stop = true;
  };
  const auto failed_write = [&] {
    std::lock_guard lock(failure_mutex);
    return write_failure;
  };

  BoundedChannel<Frame> store_ch(kStoreChannelCapacity);
  BoundedChannel<Frame> render_ch(kRenderChannelCapacity);
  std::atomic<double> progress_time{0.0};
  std::atomic<long long> progress_steps{0};
  std::atomic<bool> solver_done{false};
  RunOutcome solver_outcome;  // the solver's outcome, under done_mutex once solver_done (for the watchdog)
  std::mutex done_mutex;
  std::condition_variable done_signal;  // wakes the progress loop at once when the solver ends
  std::mutex history_mutex;
  PlotHistory history;  // probe time series for the plots
  std::string store_error, render_error, render_backend, gl_renderer, plot_error;
  bool no_graphics = false;  // set by the render thread before frames_done
  std::vector<std::string> plot_files;
  std::promise<void> frames_done;
  // the twins' curves join the plots: the render thread waits for them after the frames
  std::promise<void> twins_done;
  std::shared_future<void> twins_ready = twins_done.get_future().share();

  // summary.json "stresses": the run's largest von Mises stress, at which node (mesh point) and
  // frame (row of results.h5), when the run records its stress fields
  const int von_mises = field_index(info, "von_mises");
  struct StressPeak {
    double value = std::numeric_limits<double>::quiet_NaN(), time = 0.0, load_factor = 0.0;
    long long node = -1, frame = -1, step = -1;
  } von_mises_peak;

  // store thread: every frame to HDF5, every n-th to the renderer
  std::thread store([&] {
    long long index = 0;
    std::optional<Frame> unrendered_last;  // the final state is always a frame, whatever the cadence
    while (std::optional<Frame> f = store_ch.pop()) {
      std::string e;
      {
        std::lock_guard lock(writer_mutex);
        if (!writer_closed && store_error.empty() && !writer->append(*f, &e)) {
          store_error = e;
          fail_write("results.h5: " + e);
        }
        // with the append, so that the watchdog's outcome names the last frame in the file
        progress_time = f->time;
        progress_steps = f->step;
      }
      {
        std::lock_guard lock(history_mutex);
        history.add(*f);
      }
      if (von_mises >= 0 && static_cast<std::size_t>(von_mises) < f->fields.size()) {
        const std::vector<double>& v = f->fields[von_mises];
        for (std::size_t i = 0; i < v.size(); ++i)
          if (v[i] > von_mises_peak.value || (std::isnan(von_mises_peak.value) && std::isfinite(v[i])))
            von_mises_peak = {v[i], f->time, f->load_factor, static_cast<long long>(i), index, f->step};
      }
      if (want_frames && index % out.frame_every == 0) {
        render_ch.push(std::move(*f));
        unrendered_last.reset();
      } else if (want_frames) {
        unrendered_last = std::move(f);
      }
      ++index;
    }
    if (unrendered_last) render_ch.push(std::move(*unrendered_last));
    render_ch.close();
  });

  // render thread: owns its GL context. The frames to draw are kept (positions and the colour
  // field only) and drawn once the solver is done, so that they share one colour range and a
  // camera that holds the whole motion, as replay draws them (SequenceView, frame_outputs.h):
  // a live range or camera would have to change mid-movie. Drawing after the solve costs about
  // what drawing beside it did, as the renderer took a core from the solver (docs/performance.md).
  std::atomic<bool> render_busy{false};
  const std::atomic<bool> never{false};  // what the solver computed is drawn, also after Ctrl-C
  std::array<double, 2> color_range{0, 0};  // the frames' one colour range, set before frames_done
  std::string drawing_stopped;  // "k of n" frames drawn when a Ctrl-C stopped the drawing
  std::string frame_memory_note;  // what drawing did when the kept frames outgrew their budget
  const double frame_memory_mb = opt.frame_memory_mb > 0 ? opt.frame_memory_mb : default_frame_memory_mb();
  const int color_field = out.color_field == "none" ? -1 : field_index(info, out.color_field);
  // the last frame's error indicator, drawn as plots/error_indicator.png: where to refine
  const int indicator_field = field_index(info, shell::kErrorIndicatorField);
  Frame last_indicator;
  bool refine_picture_drawn = false;  // set by the render thread, read after it joined
  bool frames_announced = false;  // frames_done is set (by the render thread only)
  const auto render_all = [&] {
    std::unique_ptr<render::GraphicsContext> gc;
    std::unique_ptr<render::FrameRenderer> renderer;
    std::vector<Frame> to_draw;
    SequenceView sequence;
    int n = 0;
    auto t0 = std::chrono::steady_clock::now();
    // one frame out, the renderer made at the first with the sequence's range and view; false
    // when drawing must end (no graphics on this machine, a renderer or write error)
    auto draw = [&](const Frame& f) -> bool {
      if (!render_error.empty() || !failed_write().empty()) return false;
      if (!gc) {
        gc = render::GraphicsContext::create(&render_error);
        if (!gc) {  // no OpenGL on this machine: a warning, the run goes on without pictures
          no_graphics = true;
          return false;
        }
        render_backend = gc->backend();
        gl_renderer = gc->gl_renderer();
        render::FrameStyle style;
        style.width = out.width;
        style.height = out.height;
        style.deformation_scale = out.deformation_scale;
        style.color_field = color_field >= 0 ? out.color_field : "";
        style.color_min = sequence.color_range[0];  // one range for the whole movie
        style.color_max = sequence.color_range[1];
        color_range = sequence.color_range;
        style.title = scene.name;
        if (out.view != "auto" && !camera && out.camera_path.empty()) {
          style.camera = scene_camera(info.mesh, out.view, out.view_center, out.view_radius, sequence.fit_points);
        } else {
          // an automatic camera (--camera, the camera path, view = "auto") fitted to the whole
          // motion, as replay fits it; the path's start sizes the tubes, each frame sets its own
          if (camera) style.camera = *camera;
          else if (!out.camera_path.empty()) style.camera = *camera_on_path(out.camera_path, f.time);
          style.fit_points = sequence.fit_points;
        }
        renderer = std::make_unique<render::FrameRenderer>(*gc, info, style);
        if (!renderer->ok()) {
          render_error = renderer->error();
          return false;
        }
      }
      // the scene's camera path, unless --camera fixed the view
      if (!camera && !out.camera_path.empty()) renderer->set_camera(*camera_on_path(out.camera_path, f.time));
      char name[32];
      std::snprintf(name, sizeof name, "frames/frame_%05d.png", n);
      try {
        if (!renderer->render_png(f, folder.file(name).string(), &render_error)) {
          fail_write(render_error);
          return false;
        }
      } catch (const WriteError& e) {  // the manifest could not record the frame
        render_error = e.what();
        fail_write(render_error);
        return false;
      }
      ++n;
      return true;
    };
    // the kept frames, drawn in their one range and view; `stoppable`: a Ctrl-C (after a solve
    // that was not interrupted) ends the drawing
    auto draw_kept = [&](bool stoppable) {
      t0 = std::chrono::steady_clock::now();
      const bool solve_interrupted = stop;
      sequence = sequence_view(
          to_draw.size(), [&](std::size_t k) { return to_draw[k]; }, color_field, out.deformation_scale, never);
      for (std::size_t k = 0; k < to_draw.size(); ++k) {
        if (stoppable && stop && !solve_interrupted) {
          drawing_stopped = std::to_string(n) + " of " + std::to_string(to_draw.size());
          break;
        }
        if (!draw(to_draw[k])) break;
      }
      to_draw.clear();
      to_draw.shrink_to_fit();
    };
    double kept_mb = 0.0;
    bool live = false;  // over the budget: the kept frames are out, the rest is drawn as it comes
    while (std::optional<Frame> f = render_ch.pop()) {
      // keep draining so the solver never blocks; after a failed write nothing more is drawn
      if (!failed_write().empty()) continue;
      if (indicator_field >= 0 && static_cast<std::size_t>(indicator_field) < f->fields.size()) {
        last_indicator.time = f->time, last_indicator.load_factor = f->load_factor, last_indicator.step = f->step;
        last_indicator.points = f->points, last_indicator.base_points = f->base_points;
        last_indicator.fields.assign(indicator_field + 1, {});
        last_indicator.fields[indicator_field] = f->fields[indicator_field];
      }
      for (std::size_t k = 0; k < f->fields.size(); ++k)
        if (static_cast<int>(k) != color_field) std::vector<double>().swap(f->fields[k]);
      if (live) {
        render_busy = true;  // the element loops leave this core to the renderer while it draws
        draw(*f);
        render_busy = false;
        continue;
      }
      for (const std::vector<double>* v : {&f->points, &f->base_points})
        kept_mb += 8e-6 * static_cast<double>(v->size());
      if (color_field >= 0 && static_cast<std::size_t>(color_field) < f->fields.size())
        kept_mb += 8e-6 * static_cast<double>(f->fields[static_cast<std::size_t>(color_field)].size());
      to_draw.push_back(std::move(*f));
      if (kept_mb > frame_memory_mb) {  // the frames so far set the range and view of the rest
        live = true;
        char held[96];
        std::snprintf(held, sizeof held, "%zu frames held %.3g MB, beyond --frame-memory %.3g MB", to_draw.size(), kept_mb,
                      frame_memory_mb);
        frame_memory_note = std::string(held) + ": the later frames were drawn as they came, in the first frames' colour range and "
                            "view (values beyond it saturate); `flexframe replay` draws every frame in one range";
        draw_kept(false);
      }
    }
    if (!live) draw_kept(true);
    to_draw.clear();
    to_draw.shrink_to_fit();
    result.frames_rendered = n;
    result.render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    frames_done.set_value();  // render_backend, gl_renderer, render_error and the counts are final
    frames_announced = true;
    // the plots, on this thread's GL context while the main thread closes results.h5: the store
    // thread closed render_ch after its last history.add, so the history is complete
    if (opt.plots && out.plots && gc && !last_indicator.points.empty()) {
      std::string why;
      try {
        if (!draw_refine_picture(*gc, info, out, scene.name, last_indicator,
                                 folder.file("plots/error_indicator.png").string(), &why))
          plot_error = "error_indicator.png: " + why;
        else
          refine_picture_drawn = true;
      } catch (const WriteError& e) {  // the manifest could not record it
        plot_error = e.what();
      }
    }
    if (opt.plots && out.plots) {
      twins_ready.wait();
      std::lock_guard lock(history_mutex);
      // labelled as write_run_plots labels a run; the history has no other reader after the plots
      std::vector<LabelledRun> runs;
      runs.push_back({info.scene_name, info, std::move(history)});
      for (const TwinRun& t : result.error_bars.twins) {
        if (t.history.time.empty()) continue;
        // the name alone keeps the legend inside the plot; what the twin changed is in summary.json
        LabelledRun twin{t.name + " twin", t.info, t.history};
        twin.info.references.clear();  // drawn once, with the run
        // the run's error bar along its curves, from the twin directly below it (a mesh twin
        // first: in dynamics the time bar is the integrator's and has no curve)
        if (t.ratio > 0 && (runs.front().bands.empty() || t.name == "mesh"))
          runs.front().bands = richardson_bands(runs.front(), twin, t.ratio,
                                                 t.name == "mesh" ? "mesh error bar (GCI from the mesh twin)"
                                                                  : "time-step error bar (GCI from the time twin)");
        runs.push_back(std::move(twin));
      }
      plot_files = write_overlay_plots(runs, plots_dir.string(), &plot_error, gc.get());
      try {
        for (const std::string& p : plot_files) folder.record("plots/" + fs::path(p).filename().string());
      } catch (const WriteError& e) {
        if (plot_error.empty()) plot_error = e.what();
      }
      if (!plot_error.empty() && !no_graphics) fail_write("plots: " + plot_error);
    }
  };
  std::thread render([&] {
    // nothing may escape a thread (std::terminate): an error drawing or recording an output is a
    // failed output, said in the outcome, and the channel is drained so the store thread goes on
    try {
      render_all();
    } catch (const std::exception& e) {
      render_busy = false;
      fail_write(std::string("drawing the frames and plots: ") + e.what());
      while (render_ch.pop()) {
      }
      if (!frames_announced) frames_done.set_value();
    }
  });

  // solver on the worker thread
  RunOutcome outcome;
  std::thread worker([&] {
    // frames render beside the solver: while a frame is being rendered the element loops leave
    // one core to the renderer, otherwise they use all (unless the user set OMP_NUM_THREADS); a
    // loop thread never waits at a barrier for a core the renderer holds (docs/performance.md)
    if (want_frames && !std::getenv("OMP_NUM_THREADS") && std::thread::hardware_concurrency() > 1)
      sim.set_element_threads(0, &render_busy);
    try {
      outcome = sim.run([&](Frame&& f) { store_ch.push(std::move(f)); }, run_stop);
      // Ctrl-C reaches the model's set-up through the scene context at once, and run_stop only at
      // the progress loop's next turn (at most 0.1 s): a set-up it stopped is an interruption
      if (outcome.status == RunStatus::failed && stop && failed_write().empty() && outcome.steps == 0)
        outcome.status = RunStatus::interrupted;
    } catch (const std::exception& e) {
      outcome.status = RunStatus::failed;
      outcome.reason = std::string("solver error: ") + e.what();
    }
    store_ch.close();
    {
      std::lock_guard lock(done_mutex);
      solver_outcome = outcome;
      solver_done = true;
    }
    done_signal.notify_all();
  });

  // Over MPI ranks (core/solve/distributed.md) Open MPI's launcher answers a rank's death with
  // SIGTERM to every other rank and SIGKILL a second later. The solver thread may then wait inside
  // a MUMPS call for the dead rank and never return: unless this run has closed results.h5 within
  // kLauncherGraceS of the SIGTERM, the watchdog closes it, with an outcome that says so, writes
  // summary.json and ends the process (rank 0 alone runs this function; the others write nothing).
  std::atomic<bool> run_over{false};
  const auto watch_launcher = [&] {
    using namespace std::chrono_literals;
    while (!run_over && opt.stop_signal->load() != SIGTERM) std::this_thread::sleep_for(20ms);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(kLauncherGraceS);
    while (!run_over && !writer_closed && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(5ms);
    std::unique_lock lock(writer_mutex);  // not while the store thread appends a frame
    if (run_over || writer_closed) return;  // the run closed its results in time and ends as usual
    RunOutcome o;
    o.status = RunStatus::interrupted;
    o.steps = progress_steps;  // the last frame stored: the store thread sets them after its append
    o.stop_time = progress_time;
    o.reason = launcher_stop_reason(o.steps, o.stop_time, info.time_unit) +
               "; the solver did not return from a call shared with the other ranks, so rank 0 closed results.h5 "
               "itself with the frames stored until then";
    {
      std::lock_guard done_lock(done_mutex);
      if (solver_done) {  // the solve had ended: the SIGTERM came while the frames or other outputs were made
        o = solver_outcome;
        const std::string after = "stopped by SIGTERM from the MPI launcher while the run wrote its outputs";
        if (o.status == RunStatus::completed) {
          o.status = RunStatus::interrupted;
          o.reason = after + ", after the solve had completed; results.h5 holds every frame: `flexframe replay` draws them";
        } else {
          o.reason += " (then " + after + ")";
        }
      }
    }
    o.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - run_start).count();
    folder.release_reserve();  // room for the outcome and summary.json
    std::string e;
    if (!writer->finish(o, {}, &e)) std::fprintf(stderr, "error: results.h5 is incomplete: %s\n", e.c_str());
    writer_closed = true;  // the lock is kept until the process ends: nothing touches the writer again
    // summary.json without the metrics: the blocked solver thread holds them
    const nlohmann::ordered_json summary = {
        {"scene", scene.name}, {"scene_path", scene.path}, {"status", to_string(o.status)}, {"reason", o.reason},
        {"stop_time", o.stop_time}, {"time_unit", info.time_unit}, {"wall_time_s", o.wall_time_s},
        {"steps", o.steps}, {"metrics", nlohmann::ordered_json::object()},
        {"outputs", {{"results", "results.h5"}}}};
    try {
      write_text_file(folder.file("summary.json"), summary.dump(2) + "\n");
    } catch (const std::exception& x) {
      std::fprintf(stderr, "error: %s\n", x.what());
    }
    std::printf("%s: %s at t = %g after %lld steps\n  reason: %s\n  outputs: %s/{results.h5, summary.json}\n",
                scene.name.c_str(), to_string(o.status), o.stop_time, static_cast<long long>(o.steps), o.reason.c_str(),
                result.out_dir.c_str());
    std::fflush(stdout);
    std::fflush(stderr);
    std::_Exit(exit_code(o));  // without joining the blocked solver thread; the launcher ends the others
  };
  const bool over_ranks = linear_solver_ranks() > 1 && opt.stop_signal;
  struct JoinAtEnd {  // the watchdog ends with the run, also when it throws
    std::atomic<bool>& over;
    std::thread thread;
    ~JoinAtEnd() {
      over = true;
      if (thread.joinable()) thread.join();
    }
  } watchdog{run_over, over_ranks ? std::thread(watch_launcher) : std::thread()};

  // progress on this thread
  const bool tty = isatty(STDERR_FILENO);
  const auto wall0 = std::chrono::steady_clock::now();
  auto last_print = wall0;
  const double t_end = sim.end_time();
  while (!solver_done) {
    // over ranks run_stop changes only at a shared solver call (also_stop_with_ranks above), where
    // every rank's does: set here, between two calls, it would stop rank 0 a step before the others
    if (stop && !over_ranks_stop) run_stop = true;
    {
      std::unique_lock lock(done_mutex);
      done_signal.wait_for(lock, std::chrono::milliseconds(100), [&] { return solver_done.load(); });
    }
    if (solver_done) break;
    const auto now = std::chrono::steady_clock::now();
    const double since = std::chrono::duration<double>(now - last_print).count();
    if (!opt.progress || since < (tty ? 0.25 : 2.0)) continue;
    last_print = now;
    const double wall = std::chrono::duration<double>(now - wall0).count();
    const double t = progress_time, rate = progress_steps / std::max(wall, 1e-9);
    const double eta = t > 0 ? wall * (t_end - t) / t : NAN;
    std::fprintf(stderr, "%s%s: t = %.3f / %.3f %s | %lld steps | %.0f steps/s | ETA %s%s", tty ? "\r" : "",
                 scene.name.c_str(), t, t_end, info.time_unit.c_str(), static_cast<long long>(progress_steps), rate,
                 format_duration(eta).c_str(), tty ? "   " : "\n");
  }
  worker.join();
  store.join();
  if (opt.progress && tty) std::fprintf(stderr, "\n");
  if (over_ranks && outcome.status == RunStatus::interrupted && *opt.stop_signal == SIGTERM)
    outcome.reason = launcher_stop_reason(outcome.steps, outcome.stop_time, info.time_unit);

  result.metrics = sim.metrics();
  result.totals = sim.totals();
  result.field_error = sim.field_error_estimate();  // the last state's, also of a run that stopped early
  // every answer metric with its discretization error, from coarser twins solved while the render
  // thread draws the frames (core/model/error_bars.md); only a completed run has answers to bar
  const int bar_levels = opt.error_bar_levels.value_or(scene.output.error_bar ? -1 : 0);
  if (bar_levels != 0) {
    ErrorBarReport& bars = result.error_bars;
    bars.on = true;
    if (outcome.status != RunStatus::completed) {
      bars.not_estimated = "the run did not complete";
    } else if (linear_solver_ranks() > 1) {
      bars.not_estimated = "a run over MPI ranks runs no twins yet (--error-bar off skips this note)";
    } else {
      if (opt.progress) std::fprintf(stderr, "error bars: solving the coarser twins (--error-bar off skips them)\n");
      const int elements = scene.mesh_quality ? scene.mesh_quality->quality.quad_count : 0;
      try {
        bars = estimate_error_bars(opt.scene_path, opt.overrides, sim, outcome, opt.setup_wall_s, elements,
                                   bar_levels < 0 ? 0 : bar_levels, result.field_error, stop);
      } catch (const std::exception& e) {  // the scene file changed under the run, or no file (a test's model)
        bars.not_estimated = std::string("the twins could not be planned: ") + e.what();
      }
      // a twin whose path differs in kind is no coarser answer: its metrics are flagged, and the run
      // says so where the user looks and records it with its path's events (error_bars.md §6)
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
  }
  twins_done.set_value();
  frames_done.get_future().wait();
  // the solve completed but its pictures did not: the run does not call itself completed
  if (!drawing_stopped.empty() && outcome.status == RunStatus::completed) {
    outcome.status = RunStatus::interrupted;
    const bool by_launcher = over_ranks && *opt.stop_signal == SIGTERM;
    outcome.reason = std::string(by_launcher ? "stopped by SIGTERM from the MPI launcher" : "interrupted by the user") +
                     " while the frames were drawn (" + drawing_stopped +
                     " drawn); the solve had completed and results.h5 holds every frame: `flexframe replay` draws them";
  }
  // a failed write is the run's outcome, whatever the solver would have said (it was stopped for it)
  const auto record_write_failure = [&] {
    const std::string what = failed_write();
    if (what.empty() || outcome.status == RunStatus::failed) return;
    char at[64];
    std::snprintf(at, sizeof at, " (stopped at t = %g%s%s)", outcome.stop_time, info.time_unit.empty() ? "" : " ",
                  info.time_unit.c_str());
    outcome.status = RunStatus::failed;
    outcome.reason = "an output could not be written: " + what + at;
  };
  // results.h5 is closed under its lock; the launcher watchdog, once it has closed the file, keeps
  // the lock until it ends the process
  std::unique_lock writer_lock(writer_mutex);
  // the modes of an eigen-analysis, with the table, before the outcome (results_layout.md /modes)
  const ModeSet* modes = sim.modes();
  if (modes && failed_write().empty()) {
    result.modes = static_cast<int>(modes->modes.size());
    if (!writer->write_modes(*modes, &err)) fail_write("results.h5: " + err);
  }
  // the twins' probe histories beside the run's frames (results_layout.md /error_bar_twins)
  for (const TwinRun& t : result.error_bars.twins) {
    if (t.history.time.empty() || !failed_write().empty()) continue;
    std::vector<std::string> names;
    for (const Quantity& q : t.info.probes) names.push_back(q.name);
    if (!writer->write_twin_history(t.name, t.description, t.history.time, names, t.history.probes, &err))
      fail_write("results.h5: " + err);
  }
  record_write_failure();
  // the bars beside the frames they are about, for scripts and replay (results_layout.md /attributes)
  if (result.error_bars.on) writer->set_attribute("error_bars", error_bars_json(result.error_bars).dump());
  if (result.field_error) writer->set_attribute("field_error", field_error_json(*result.field_error).dump());
  if (!render_backend.empty()) {
    writer->set_attribute("render_backend", render_backend);
    writer->set_attribute("gl_renderer", gl_renderer);
    if (color_field >= 0) writer->set_attribute("color_range", format_range(color_range));
  }
  const RunOutcome finished_with = outcome;  // what results.h5 says until amended below
  if (!writer->finish(outcome, result.metrics, &err)) {
    // the writer's message says what is missing (the outcome, or frames after the last flush)
    std::fprintf(stderr, "error: results.h5 is incomplete: %s\n", err.c_str());
    fail_write("results.h5: " + err);
    record_write_failure();
  }
  writer.reset();
  writer_closed = true;
  writer_lock.unlock();
  render.join();  // its last frames and the plots
  record_write_failure();  // the plots are written while results.h5 closes
  // the movie once the render thread has ended: its library loads while no other thread loads or
  // unloads one (the GL driver does at the render thread's end; ThreadSanitizer cannot see the
  // loader's own lock). Its failure still reaches results.h5's outcome, amended below.
  if (opt.movie && failed_write().empty()) {
    MovieReport m{false, "", "", 0, "no frames were rendered"};
    try {
      if (result.frames_rendered > 0) m = write_movie(frames_dir.string(), folder.file("movie.mp4").string(), opt.fps, stop);
    } catch (const WriteError& e) {
      m.message = e.what();
    }
    if (m.ok) result.movie = m.path;
    else if (result.frames_rendered > 0 && !stop) fail_write("movie.mp4: " + m.message);
    else std::fprintf(stderr, "warning: no movie: %s\n", m.message.c_str());
  }
  record_write_failure();
  if (no_graphics && !render_error.empty()) std::fprintf(stderr, "warning: frames not rendered: %s\n", render_error.c_str());
  if (!frame_memory_note.empty()) std::fprintf(stderr, "warning: frames: %s\n", frame_memory_note.c_str());
  if (no_graphics && !plot_error.empty()) std::fprintf(stderr, "warning: plots: %s\n", plot_error.c_str());
  const auto unreached = sim.metrics_unreached();  // kept in summary.json as null, with why
  for (const auto& [name, why] : unreached)
    std::fprintf(stderr, "warning: metric '%s' has no value: %s\n", name.c_str(), why.c_str());

  // mesh exports of the frames, read back from results.h5 (closed by now: a failure here amends
  // its outcome below, as it goes into summary.json)
  if (formats.any() && failed_write().empty()) {
    std::string e;
    const auto reader = io::ResultReader::open(h5_path, &e);
    if (reader) {
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
      e = x.error;
    }
    if (!e.empty()) {
      fail_write("export: " + e);
      record_write_failure();
    }
  }
  // the modes' pictures, plot and export, about the last stored frame (as `replay` makes them)
  ModeOutputReport mode_report;
  if (modes && failed_write().empty()) {
    std::string e;
    const auto reader = io::ResultReader::open(h5_path, &e);
    if (reader && reader->frame_count() > 0) {
      ModeOutputOptions mo;
      mo.modes = opt.animate_modes == 0 ? std::vector<int>{} : select_modes(*modes, {}, opt.animate_modes);
      mo.frames = want_frames;
      mo.plot = opt.plots && out.plots;
      mo.movie = opt.movie;
      mo.vtu = formats.vtu;
      mo.fps = opt.fps;
      mo.width = out.width;
      mo.height = out.height;
      if (camera) mo.camera = *camera, mo.camera_given = true;
      mode_report = write_mode_outputs(folder, info, reader->frame(reader->frame_count() - 1), *modes, mo, nullptr, stop);
      e = mode_report.error;
      // pictures a Ctrl-C cut short: the run does not call itself completed (results.h5 keeps the modes)
      if (stop && outcome.status == RunStatus::completed && mode_report.no_graphics.empty() &&
          (mode_report.modes_animated < static_cast<int>(mo.modes.size()) || (mo.plot && !modes->modes.empty() && mode_report.plot.empty()))) {
        outcome.status = RunStatus::interrupted;
        outcome.reason = "interrupted by the user while the mode pictures were drawn (" +
                         std::to_string(mode_report.modes_animated) + " of " + std::to_string(mo.modes.size()) +
                         " modes animated); results.h5 holds every mode: `flexframe replay` draws them";
      }
    } else if (reader) {
      e = "no stored frame holds the state the modes are about";
    }
    result.modes_animated = mode_report.modes_animated;
    if (!mode_report.plot.empty()) plot_files.push_back(mode_report.plot);
    if (!mode_report.no_graphics.empty()) std::fprintf(stderr, "warning: mode pictures not drawn: %s\n", mode_report.no_graphics.c_str());
    if (!e.empty()) {
      fail_write("modes: " + e);
      record_write_failure();
    }
  }
  // one outcome in both records, summary.json written last: what the outputs after finish() did
  // to the verdict (a Ctrl-C, a full disk) goes into results.h5 first
  if (outcome.status != finished_with.status || outcome.reason != finished_with.reason) {
    folder.release_reserve();
    if (std::string e; !io::amend_outcome(h5_path, outcome, &e)) {
      std::fprintf(stderr, "error: %s\n", e.c_str());
      fail_write("results.h5: " + e);
      outcome.status = RunStatus::failed;
      outcome.reason += "; results.h5 still says '" + std::string(to_string(finished_with.status)) +
                        "': its outcome could not be updated (" + e + ")";
    }
  }
  result.outcome = outcome;
  if (!failed_write().empty()) std::fprintf(stderr, "error: %s\n", outcome.reason.c_str());

  // summary.json: what scripts and benchmarks read (keys in this order; NaN is written as null)
  using Json = nlohmann::ordered_json;
  Json metrics = Json::object();
  for (const auto& [k, v] : result.metrics) metrics[k] = v;
  Json metrics_unreached = Json::object();
  for (const auto& [name, why] : unreached) {
    metrics[name] = nullptr;
    metrics_unreached[name] = why;
  }
  Json effect_stats = Json::object();  // only the effects that ran
  for (const EffectStat& e : sim.effect_stats()) {
    Json one = {{"evaluations", e.evaluations}, {"time_s", e.seconds}};  // NaN (fused, not timed apart): null
    if (!e.included_in.empty()) one["included_in"] = e.included_in;
    effect_stats[e.effect] = one;
  }
  Json outputs = {{"results", "results.h5"},
                        {"frames_dir", "frames"},
                        {"frames", result.frames_rendered},
                        {"plots", plot_files},
                        {"movie", result.movie.empty() ? "" : "movie.mp4"},
                        {"export_frames", result.frames_exported}};
  const Json render_info = {
      {"backend", render_backend},
      {"gl_renderer", gl_renderer},
      {"frames_per_second", result.render_seconds > 0 ? result.frames_rendered / result.render_seconds : 0.0},
      {"color_field", color_field >= 0 && result.frames_rendered > 0 ? out.color_field : ""},
      {"color_range", color_field >= 0 && result.frames_rendered > 0 ? Json::array({color_range[0], color_range[1]})
                                                                      : Json::array()},
      {"frame_memory_note", frame_memory_note}};
  Json events = Json::array();  // what the path did (statics: limit points, bifurcations, turn-backs)
  for (const PathEvent& e : outcome.events)
    events.push_back({{"kind", e.kind}, {"step", e.step}, {"load_factor", e.load_factor}, {"detail", e.detail}});
  // how each mesh file was read (format, what became of triangles, directors, named groups)
  Json mesh_import = Json::object();
  for (const auto& [key, value] : info.settings)
    if (key.rfind("mesh_import", 0) == 0) mesh_import[key] = value;
  if (modes)
    outputs["modes"] = {{"animated", mode_report.modes_animated},
                        {"frames", mode_report.frames},
                        {"frames_per_cycle", kModeFramesPerCycle},
                        {"amplitude_fraction_of_model_size", kModeAmplitudeFraction},
                        {"movies", mode_report.movies},
                        {"spectrum_plot", mode_report.plot},
                        {"vtu", mode_report.vtu}};
  Json summary = {
      {"scene", scene.name},
      {"scene_path", scene.path},
      {"status", to_string(outcome.status)},
      {"reason", outcome.reason},
      {"stop_time", outcome.stop_time},
      {"time_unit", info.time_unit},
      {"wall_time_s", outcome.wall_time_s},
      {"steps", result.totals.steps},
      {"newton_iterations", result.totals.newton_iterations},
      {"jacobian_updates", result.totals.jacobian_updates},
      {"cutbacks", result.totals.cutbacks >= 0 ? Json(result.totals.cutbacks) : Json()},  // null: not counted
      {"steps_per_second", outcome.wall_time_s > 0 ? result.totals.steps / outcome.wall_time_s : 0.0},
      {"effects", info.effects},
      {"metrics", metrics},
      {"metrics_unreached", metrics_unreached},
      {"events", events},
      {"effect_stats", effect_stats},
      {"mesh_import", mesh_import},
      {"outputs", outputs},
      {"render", render_info}};
  if (result.error_bars.on) summary["error_bars"] = error_bars_json(result.error_bars);
  if (result.field_error) {
    summary["field_error"] = field_error_json(*result.field_error);
    summary["field_error"]["picture"] = refine_picture_drawn ? Json("plots/error_indicator.png") : Json(nullptr);
  }
  if (modes) summary["modes"] = modes_json(*modes);
  if (scene.mesh_quality) summary["mesh_quality"] = mesh_quality_json(*scene.mesh_quality);
  if (von_mises >= 0)  // null node and frame: no stored frame had a finite value
    summary["stresses"] = {
        {"von_mises_max", von_mises_peak.value},
        {"node", von_mises_peak.node >= 0 ? Json(von_mises_peak.node) : Json()},
        {"frame", von_mises_peak.frame >= 0 ? Json(von_mises_peak.frame) : Json()},
        {"step", von_mises_peak.step >= 0 ? Json(von_mises_peak.step) : Json()},
        {"time", von_mises_peak.frame >= 0 ? Json(von_mises_peak.time) : Json()},
        {"load_factor", von_mises_peak.frame >= 0 ? Json(von_mises_peak.load_factor) : Json()},
        {"unit", info.fields[von_mises].unit}};
  try {
    write_text_file(folder.file("summary.json"), summary.dump(2) + "\n");
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
