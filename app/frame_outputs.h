#pragma once
/// \file frame_outputs.h
/// What `run` and `replay` make from stored frames besides PNGs: an MP4 movie of the PNG frames
/// and per-frame mesh exports (VTK XML .vtu + .pvd, glTF .glb, OBJ) read from results.h5.

#include <array>
#include <atomic>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "app/io/results.h"
#include "app/view_options.h"

namespace ff::app {

/// Stored frames to show: every `every`-th of `count` (0, every, 2 every, ...), plus the last
/// one when include_last and it is not already in.
std::vector<std::size_t> frame_selection(std::size_t count, int every, bool include_last);

/// Smallest and largest finite value of field `field` over the selected frames ({0, 0} when
/// there are none). Reads the frames.
std::array<double, 2> field_range(const io::ResultReader& reader, const std::vector<std::size_t>& frames,
                                  int field);

/// What every frame of one stored sequence shares, so that a run's frames, its replay and their
/// movies agree (docs/guide/replay-and-export.md, "Colour range and camera"): one colour range,
/// render::color_range_for() of the field's values over all the frames, and the drawn
/// positions (base + deformation_scale * (points - base)) the camera must keep in view.
struct SequenceView {
  std::array<double, 2> color_range{0, 0};  ///< {0, 0} without a field or a finite value
  std::vector<double> fit_points;           ///< 3 per point, from at most kMaxFitFrames frames
};
inline constexpr std::size_t kMaxFitFrames = 200;  // frames sampled to fit the camera to the motion

/// One pass over frames 0..count-1 of a sequence (frame_at(k) gives the k-th); field -1 = none.
/// Returns early (partial) when stop is set.
SequenceView sequence_view(std::size_t count, const std::function<Frame(std::size_t)>& frame_at, int field,
                           double deformation_scale, const std::atomic<bool>& stop);

/// Index of field `name` in info.fields, -1 if there is none.
int field_index(const RunInfo& info, const std::string& name);
/// "a, b, c" of the run's field names ("(none)" when it stores no fields).
std::string field_names(const RunInfo& info);

struct MovieReport {
  bool ok = false;
  std::string path;     ///< the movie written (when ok)
  std::string codec;    ///< encoder used, e.g. "libx264"
  int frames = 0;
  std::string message;  ///< why no movie was written (when !ok)
};

/// Encodes frames_dir/frame_*.png (name order, all the size of the first) as an MP4 at `fps`.
/// Never throws; a missing encoder or unreadable frame is reported in the message.
MovieReport write_movie(const std::string& frames_dir, const std::string& movie_path, int fps,
                        const std::atomic<bool>& stop);

struct ExportReport {
  int frames = 0;                   ///< frames exported (in every requested format)
  std::vector<std::string> files;   ///< the .pvd and the first file of each format, for messages
  std::vector<std::string> written; ///< every file written, by name inside the export folder
  std::string error;                ///< first failure; empty when everything was written
};

/// Writes the selected frames to dir (created): frame_00000.vtu ... with <scene>.pvd (times),
/// frame_00000.glb ..., frame_00000.obj ... (numbered in selection order, like the PNGs).
/// color_field / range colour the glTF/OBJ vertices (-1 = none).
ExportReport export_frames(const io::ResultReader& reader, const std::vector<std::size_t>& frames,
                           const ExportFormats& formats, const std::string& dir, int color_field,
                           std::array<double, 2> range, const std::atomic<bool>& stop);

}  // namespace ff::app
