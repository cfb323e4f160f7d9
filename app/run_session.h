#pragma once
/// \file run_session.h
/// One headless run: the solver on a worker thread publishes Frames to the output pipeline
/// (output_pipeline.h: a store thread writes every frame to results.h5 and forwards every n-th to
/// a render thread, which keeps them and draws them after the solve); the calling thread shows
/// progress; the error bars' twins, plots and summary.json (run_summary.h) at the end.

#include <atomic>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "app/error_bar_run.h"
#include "app/input_error.h"
#include "app/run_result.h"
#include "core/model/simulation.h"
#include "core/scene/scene.h"

namespace ff::app {

struct RunOptions {
  std::string scene_path;
  std::string out_dir;                     ///< "" = out/<scene name>
  std::vector<std::string> overrides;      ///< --set key=value
  std::optional<int> frame_every, width, height;
  bool frames = true;                      ///< PNG frames (also subject to output.frames)
  bool plots = true;
  bool progress = true;
  std::string camera;                      ///< --camera (see parse_camera); "" = the scene's view
  bool movie = false;                      ///< DIR/movie.mp4 from the frames
  int fps = 25;                            ///< movie frame rate
  std::string export_formats;              ///< --export: "" = none, else e.g. "vtu,gltf" (DIR/export/)
  /// --frame-memory: MB the frames to draw may hold while the solver runs (they are drawn after
  /// it, in one colour range and view); beyond it the rest is drawn as it comes, in the range and
  /// view of the frames kept. 0 = a quarter of the machine's memory, at most 2048 MB.
  double frame_memory_mb = 0.0;
  /// --animate-modes: after an eigen-analysis, at most this many modes are animated (frames,
  /// movies); -1 = every mode the analysis found, 0 = none (the table, plot and exports stay)
  int animate_modes = -1;
  /// --error-bar off|on|two|three: the metrics' discretization errors from coarser twins of the run
  /// (app/error_bar_run.h) with this many levels per source: 0 = none, -1 = the scene's
  /// output.error_bar_levels, 2, 3; unset = the scene's output.error_bar and levels (on, auto)
  std::optional<int> error_bar_levels;
  /// wall time of building the scene's model before the run (run_scene measures it; 0 when the
  /// caller hands a built scene): the error bars' cost share counts it, since every twin pays it too
  double setup_wall_s = 0.0;
  /// The signal that set the stop flag (the caller's handler stores it), or null. Over MPI ranks a
  /// SIGTERM is the launcher's: the outcome names it, and a solver blocked in a call shared with a
  /// dead rank does not keep results.h5 from being closed (run_session.cpp, the launcher watchdog).
  const std::atomic<int>* stop_signal = nullptr;
};

/// Runs a scene. Throws ff::scene::SceneError for bad input (before anything is written) and
/// std::runtime_error for output problems (unwritable directory, HDF5 failure).
RunResult run_scene(const RunOptions& options, const std::atomic<bool>& stop);
/// run_scene for a scene already loaded (options.scene_path and overrides are not read again):
/// the same run, also for a test that hands in a model of its own.
RunResult run_loaded_scene(const RunOptions& options, scene::LoadedScene scene, const std::atomic<bool>& stop);

/// One of the other ranks of `mpirun -n K flexframe run` (core/solve/distributed.md): builds the
/// same model and makes the same solver calls as rank 0, so that MUMPS factorizes over every rank,
/// and writes nothing (rank 0 alone writes results.h5, frames, plots and summary.json). It ignores
/// Ctrl-C itself: `stop` is rank 0's stop, copied to every rank at each shared solver call
/// (share_stop_over_ranks), so the ranks stop at the same step. Returns the exit code of its outcome.
int follow_run(const RunOptions& options, const std::atomic<bool>& stop);

/// Resolves "hub_beam_efg_tau1" or a path to a scene file; throws InputError naming
/// what was tried.
std::string resolve_scene(const std::string& name_or_path);
/// The bundled scene folder.
std::string scene_dir();
std::vector<std::string> bundled_scenes();
/// The scene `flexframe run` uses when none is given.
std::string default_scene();

}  // namespace ff::app
