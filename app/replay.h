#pragma once
/// \file replay.h
/// `flexframe replay`: frames, plots, a movie and mesh exports from a stored results.h5, with no
/// scene file and no solve. Works on finished, diverged, interrupted and killed runs (the file
/// keeps the frames so far; the replay says how far the run got and why it stopped).

#include <atomic>
#include <optional>
#include <string>
#include <vector>

namespace ff::app {

struct ReplayOptions {
  std::string results;                 ///< results.h5, or a run folder holding one
  std::string out_dir;                 ///< "" = <run folder>/replay
  std::optional<std::string> field;    ///< colour field; "none" = uniform; unset = the run's
  std::string camera = "auto";         ///< see parse_camera(); "auto" = the run's view
  std::string size;                    ///< "WxH"; "" = the run's frame size
  int frame_every = 1;                 ///< every n-th stored frame (the last is always shown)
  bool frames = true, plots = true;
  bool movie = false;
  int fps = 25;
  std::string export_formats;          ///< "" = none; else see parse_export_formats()
  /// of a stored eigen-analysis (results.h5 /modes), the modes to animate; empty = every one
  std::vector<int> modes;
};

/// Runs the replay and prints what it did. Throws InputError for bad input (missing or
/// foreign file, unknown field, bad size/camera/format) before writing anything. Returns 0
/// when every requested output was written, 1 when one failed, 130 when stopped.
int replay(const ReplayOptions& options, const std::atomic<bool>& stop);

}  // namespace ff::app
