#include "app/output_pipeline.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>

#include "app/frame_outputs.h"
#include "app/refine_picture.h"
#include "app/view_options.h"
#include "core/shell/error_indicator.h"
#include "render/frame_renderer.h"
#include "render/graphics_context.h"

namespace fs = std::filesystem;

namespace ff::app {

namespace {
constexpr std::size_t kStoreChannelCapacity = 256;  // frames the solver may run ahead of the store
constexpr std::size_t kRenderChannelCapacity = 8;   // frames queued for PNG output
}  // namespace

OutputPipeline::OutputPipeline(OutputPipelineSettings settings, const RunInfo& info, OutputFolder& folder,
                               StoredResults& results, WriteFailure& failure, const std::atomic<bool>& stop)
    : settings_(std::move(settings)),
      info_(info),
      folder_(folder),
      results_(results),
      failure_(failure),
      stop_(stop),
      store_ch_(kStoreChannelCapacity),
      render_ch_(kRenderChannelCapacity),
      twins_ready_(twins_done_.get_future().share()) {
  const scene::OutputSettings& out = settings_.out;
  von_mises = field_index(info_, "von_mises");
  color_field = out.color_field == "none" ? -1 : field_index(info_, out.color_field);
  store_ = std::thread([this] { store_frames(); });
  render_ = std::thread([this] {
    // nothing may escape a thread (std::terminate): an error drawing or recording an output is a
    // failed output, said in the outcome, and the channel is drained so the store thread goes on
    try {
      render_all();
    } catch (const std::exception& e) {
      render_busy_ = false;
      failure_.fail(std::string("drawing the frames and plots: ") + e.what());
      while (render_ch_.pop()) {
      }
      if (!frames_announced_) frames_done_.set_value();
    }
  });
}

OutputPipeline::~OutputPipeline() {
  store_ch_.close();
  if (store_.joinable()) store_.join();
  if (!twins_) twins_done_.set_value();  // the render thread may wait for them
  if (render_.joinable()) render_.join();
}

void OutputPipeline::join_store() { store_.join(); }

void OutputPipeline::provide_twins(const std::vector<TwinRun>& twins) {
  twins_ = &twins;
  twins_done_.set_value();
}

void OutputPipeline::wait_frames() { frames_done_.get_future().wait(); }

void OutputPipeline::join_render() { render_.join(); }

// the store thread: every frame to HDF5, every n-th to the renderer
void OutputPipeline::store_frames() {
  const bool want_frames = settings_.frames;
  const int frame_every = settings_.out.frame_every;
  long long index = 0;
  bool append_failed = false;  // results.h5 takes no more frames after a failed append
  std::optional<Frame> unrendered_last;  // the final state is always a frame, whatever the cadence
  while (std::optional<Frame> f = store_ch_.pop()) {
    std::string e;
    {
      std::lock_guard lock(results_.mutex);
      if (!results_.closed && !append_failed && !results_.writer->append(*f, &e)) {
        append_failed = true;
        failure_.fail("results.h5: " + e);
      }
      // with the append, so that the watchdog's outcome names the last frame in the file
      results_.last_time = f->time;
      results_.last_step = f->step;
    }
    {
      std::lock_guard lock(history_mutex_);
      history_.add(*f);
    }
    if (von_mises >= 0 && static_cast<std::size_t>(von_mises) < f->fields.size()) {
      const std::vector<double>& v = f->fields[von_mises];
      for (std::size_t i = 0; i < v.size(); ++i)
        if (v[i] > von_mises_peak.value || (std::isnan(von_mises_peak.value) && std::isfinite(v[i])))
          von_mises_peak = {v[i], f->time, f->load_factor, static_cast<long long>(i), index, f->step};
    }
    if (want_frames && index % frame_every == 0) {
      render_ch_.push(std::move(*f));
      unrendered_last.reset();
    } else if (want_frames) {
      unrendered_last = std::move(f);
    }
    ++index;
  }
  if (unrendered_last) render_ch_.push(std::move(*unrendered_last));
  render_ch_.close();
}

// The render thread: owns its GL context. The frames to draw are kept (positions and the colour
// field only) and drawn once the solver is done, so that they share one colour range and a
// camera that holds the whole motion, as replay draws them (SequenceView, frame_outputs.h):
// a live range or camera would have to change mid-movie. Drawing after the solve costs about
// what drawing beside it did, as the renderer took a core from the solver (docs/performance.md).
void OutputPipeline::render_all() {
  const scene::OutputSettings& out = settings_.out;
  const std::optional<render::Camera>& camera = settings_.camera;
  const std::atomic<bool> never{false};  // what the solver computed is drawn, also after Ctrl-C
  // the last frame's error indicator, drawn as plots/error_indicator.png: where to refine
  const int indicator_field = field_index(info_, shell::kErrorIndicatorField);
  Frame last_indicator;
  std::unique_ptr<render::GraphicsContext> gc;
  std::unique_ptr<render::FrameRenderer> renderer;
  std::vector<Frame> to_draw;
  SequenceView sequence;
  int n = 0;
  auto t0 = std::chrono::steady_clock::now();
  // one frame out, the renderer made at the first with the sequence's range and view; false
  // when drawing must end (no graphics on this machine, a renderer or write error)
  auto draw = [&](const Frame& f) -> bool {
    if (!render_error.empty() || failure_.any()) return false;
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
      style.title = settings_.scene_name;
      if (out.view != "auto" && !camera && out.camera_path.empty()) {
        style.camera = scene_camera(info_.mesh, out.view, out.view_center, out.view_radius, sequence.fit_points);
      } else {
        // an automatic camera (--camera, the camera path, view = "auto") fitted to the whole
        // motion, as replay fits it; the path's start sizes the tubes, each frame sets its own
        if (camera) style.camera = *camera;
        else if (!out.camera_path.empty()) style.camera = *camera_on_path(out.camera_path, f.time);
        style.fit_points = sequence.fit_points;
      }
      renderer = std::make_unique<render::FrameRenderer>(*gc, info_, style);
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
      if (!renderer->render_png(f, folder_.file(name).string(), &render_error)) {
        failure_.fail(render_error);
        return false;
      }
    } catch (const WriteError& e) {  // the manifest could not record the frame
      render_error = e.what();
      failure_.fail(render_error);
      return false;
    }
    ++n;
    return true;
  };
  // the kept frames, drawn in their one range and view; `stoppable`: a Ctrl-C (after a solve
  // that was not interrupted) ends the drawing
  auto draw_kept = [&](bool stoppable) {
    t0 = std::chrono::steady_clock::now();
    const bool solve_interrupted = stop_;
    sequence = sequence_view(
        to_draw.size(), [&](std::size_t k) { return to_draw[k]; }, color_field, out.deformation_scale, never);
    for (std::size_t k = 0; k < to_draw.size(); ++k) {
      if (stoppable && stop_ && !solve_interrupted) {
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
  while (std::optional<Frame> f = render_ch_.pop()) {
    // keep draining so the solver never blocks; after a failed write nothing more is drawn
    if (failure_.any()) continue;
    if (indicator_field >= 0 && static_cast<std::size_t>(indicator_field) < f->fields.size()) {
      last_indicator.time = f->time, last_indicator.load_factor = f->load_factor, last_indicator.step = f->step;
      last_indicator.points = f->points, last_indicator.base_points = f->base_points;
      last_indicator.fields.assign(indicator_field + 1, {});
      last_indicator.fields[indicator_field] = f->fields[indicator_field];
    }
    for (std::size_t k = 0; k < f->fields.size(); ++k)
      if (static_cast<int>(k) != color_field) std::vector<double>().swap(f->fields[k]);
    if (live) {
      render_busy_ = true;  // the element loops leave this core to the renderer while it draws
      draw(*f);
      render_busy_ = false;
      continue;
    }
    for (const std::vector<double>* v : {&f->points, &f->base_points}) kept_mb += 8e-6 * static_cast<double>(v->size());
    if (color_field >= 0 && static_cast<std::size_t>(color_field) < f->fields.size())
      kept_mb += 8e-6 * static_cast<double>(f->fields[static_cast<std::size_t>(color_field)].size());
    to_draw.push_back(std::move(*f));
    if (kept_mb > settings_.frame_memory_mb) {  // the frames so far set the range and view of the rest
      live = true;
      char held[96];
      std::snprintf(held, sizeof held, "%zu frames held %.3g MB, beyond --frame-memory %.3g MB", to_draw.size(), kept_mb,
                    settings_.frame_memory_mb);
      frame_memory_note = std::string(held) + ": the later frames were drawn as they came, in the first frames' colour range and "
                          "view (values beyond it saturate); `flexframe replay` draws every frame in one range";
      draw_kept(false);
    }
  }
  if (!live) draw_kept(true);
  to_draw.clear();
  to_draw.shrink_to_fit();
  frames_rendered = n;
  render_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  frames_done_.set_value();  // render_backend, gl_renderer, render_error and the counts are final
  frames_announced_ = true;
  // the plots, on this thread's GL context while the main thread closes results.h5: the store
  // thread closed render_ch_ after its last history.add, so the history is complete
  if (settings_.plots && gc && !last_indicator.points.empty()) draw_where_to_refine(*gc, last_indicator);
  if (settings_.plots) draw_plots(gc.get());
}

void OutputPipeline::draw_where_to_refine(render::GraphicsContext& gc, const Frame& last_indicator) {
  std::string why;
  try {
    if (!draw_refine_picture(gc, info_, settings_.out, settings_.scene_name, last_indicator,
                             folder_.file("plots/error_indicator.png").string(), &why))
      plot_error = "error_indicator.png: " + why;
    else
      refine_picture_drawn = true;
  } catch (const WriteError& e) {  // the manifest could not record it
    plot_error = e.what();
  }
}

// every probe against time (or load), with the twins' curves and the run's error band
void OutputPipeline::draw_plots(render::GraphicsContext* gc) {
  twins_ready_.wait();
  std::lock_guard lock(history_mutex_);
  // labelled as write_run_plots labels a run; the history has no other reader after the plots
  std::vector<LabelledRun> runs;
  runs.push_back({info_.scene_name, info_, std::move(history_)});
  static const std::vector<TwinRun> no_twins;
  for (const TwinRun& t : twins_ ? *twins_ : no_twins) {
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
  plot_files = write_overlay_plots(runs, settings_.plots_dir, &plot_error, gc);
  try {
    for (const std::string& p : plot_files) folder_.record("plots/" + fs::path(p).filename().string());
  } catch (const WriteError& e) {
    if (plot_error.empty()) plot_error = e.what();
  }
  if (!plot_error.empty() && !no_graphics) failure_.fail("plots: " + plot_error);
}

}  // namespace ff::app
