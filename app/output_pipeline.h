#pragma once
/// \file output_pipeline.h
/// The outputs of one headless run beside its solver: a store thread writes every frame the
/// solver publishes to results.h5 and forwards every n-th to a render thread, which keeps them
/// and draws them once the solve is done (one colour range and one camera for the whole
/// motion, as replay draws them), then the plots with the error-bar twins' curves.
///
/// Order of use (run_session.cpp): construct (both threads start), push() every frame,
/// close_input(), join_store(), provide_twins(), wait_frames(), then close results.h5, then
/// join_render(). Every result below is final after join_render(); the frame counts,
/// render_backend and gl_renderer already after wait_frames().

#include <array>
#include <atomic>
#include <cstddef>
#include <future>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "app/channel.h"
#include "app/error_bar_run.h"
#include "app/plots.h"
#include "app/run_shared.h"
#include "core/frame/frame.h"
#include "core/scene/output_settings.h"
#include "render/camera.h"

namespace ff::render {
class GraphicsContext;
}

namespace ff::app {

struct OutputPipelineSettings {
  std::string scene_name;
  scene::OutputSettings out;            ///< with the command line's cadence and size
  bool frames = true;                   ///< PNG frames
  bool plots = true;                    ///< plots/*.png, the error indicator's picture included
  std::string plots_dir;                ///< the folder's plots/, made
  std::optional<render::Camera> camera;  ///< --camera: fixes the view
  double frame_memory_mb = 0.0;         ///< what the kept frames may hold (RunOptions::frame_memory_mb, resolved)
};

/// summary.json "stresses": the run's largest von Mises stress, at which node (mesh point) and
/// frame (row of results.h5), when the run records its stress fields
struct StressPeak {
  double value = std::numeric_limits<double>::quiet_NaN(), time = 0.0, load_factor = 0.0;
  long long node = -1, frame = -1, step = -1;
};

class OutputPipeline {
 public:
  OutputPipeline(OutputPipelineSettings settings, const RunInfo& info, OutputFolder& folder, StoredResults& results,
                 WriteFailure& failure, const std::atomic<bool>& stop);
  /// Joins what is still running (after a throw on the way), closing the input first.
  ~OutputPipeline();
  OutputPipeline(const OutputPipeline&) = delete;
  OutputPipeline& operator=(const OutputPipeline&) = delete;

  /// One frame from the solver; blocks while the store thread is kStoreChannelCapacity behind.
  void push(Frame&& frame) { store_ch_.push(std::move(frame)); }
  /// The solver is done: the store thread drains what is queued and ends.
  void close_input() { store_ch_.close(); }
  void join_store();
  /// The twins whose curves join the plots (kept by the caller until join_render); the render
  /// thread waits for them after the frames.
  void provide_twins(const std::vector<TwinRun>& twins);
  /// Until every frame is drawn (or the drawing stopped).
  void wait_frames();
  /// Until the plots are written too.
  void join_render();

  /// Set while a frame is being drawn beside the solver: the element loops leave it a core.
  const std::atomic<bool>* render_busy() const { return &render_busy_; }

  // ---- what it did --------------------------------------------------------------------------
  int frames_rendered = 0;
  double render_seconds = 0.0;     ///< wall time drawing the frames
  std::string render_backend, gl_renderer;
  std::string render_error;        ///< why the frames stopped (with no_graphics: a warning only)
  std::string plot_error;
  bool no_graphics = false;        ///< no OpenGL on this machine: the run goes on without pictures
  std::vector<std::string> plot_files;
  std::array<double, 2> color_range{0, 0};  ///< the frames' one colour range
  int color_field = -1;            ///< index in info.fields of the frames' colour, -1 none
  std::string drawing_stopped;     ///< "k of n" frames drawn when a Ctrl-C stopped the drawing
  std::string frame_memory_note;   ///< what drawing did when the kept frames outgrew their budget
  bool refine_picture_drawn = false;  ///< plots/error_indicator.png
  int von_mises = -1;              ///< index of the von Mises field, -1: none recorded
  StressPeak von_mises_peak;

 private:
  void store_frames();
  void render_all();
  void draw_where_to_refine(render::GraphicsContext& gc, const Frame& last_indicator);
  void draw_plots(render::GraphicsContext* gc);

  OutputPipelineSettings settings_;
  const RunInfo& info_;
  OutputFolder& folder_;
  StoredResults& results_;
  WriteFailure& failure_;
  const std::atomic<bool>& stop_;
  BoundedChannel<Frame> store_ch_;
  BoundedChannel<Frame> render_ch_;
  std::mutex history_mutex_;
  PlotHistory history_;  // probe time series for the plots
  std::atomic<bool> render_busy_{false};
  std::promise<void> frames_done_;
  bool frames_announced_ = false;  // frames_done_ is set (by the render thread only)
  std::promise<void> twins_done_;
  std::shared_future<void> twins_ready_;
  const std::vector<TwinRun>* twins_ = nullptr;
  std::thread store_, render_;
};

}  // namespace ff::app
