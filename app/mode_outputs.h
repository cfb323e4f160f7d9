#pragma once
/// \file mode_outputs.h
/// What `run` and `replay` make of an eigen-analysis' modes (issue 36; docs/guide/mode_outputs.md):
/// each mode as a short looping animation (PNG frames, optionally an MP4), a plot of the
/// spectrum, a .vtu with every mode as a point vector, and the summary.json table. The modes
/// are about one state of the structure, the run's last stored frame (the "base" frame here).

#include <atomic>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/output_folder.h"
#include "core/frame/frame.h"
#include "render/frame_renderer.h"

namespace ff::render {
class GraphicsContext;
}

namespace ff::app {

/// Pictures per period of a mode animation.
inline constexpr int kModeFramesPerCycle = 24;
/// The largest displacement drawn, as a fraction of the model's size (its bounding-box diagonal):
/// a mode's amplitude is arbitrary, this one makes it readable and the caption says so.
inline constexpr double kModeAmplitudeFraction = 0.10;
/// Periods a mode's MP4 repeats (a player that does not loop still shows the motion a while).
inline constexpr int kModeMovieCycles = 4;
/// Name (and colour bar title) of the field the animations are coloured by.
inline constexpr const char* kModeShapeField = "mode_shape";

/// The diagonal of the bounding box of 3n coordinates (0 for none or non-finite ones).
double model_size(const std::vector<double>& points);

/// "73.4 Hz", "0 Hz (rigid body)", "λ = 3.52": a mode's value as the pictures and messages say it.
std::string mode_value_text(const ModeSet& set, const Mode& mode);

/// One mode's animation, ready to render: the run's mesh with one field (|u| / max |u| of the
/// mode, the same for every picture), and frames base + a sin(2πk/K) u, k = 0..K-1.
struct ModeAnimation {
  RunInfo info;
  std::vector<Frame> frames;
  double amplitude = 0.0;   ///< a: the largest displacement drawn, in the run's length unit
  std::string title;        ///< e.g. "plate: mode 2 of 6, 73.4 Hz"
  std::string caption;      ///< says that the amplitude is arbitrary and what it is
};
/// Throws std::invalid_argument when the mode's displacement or the base frame's points do not
/// match info's mesh.
ModeAnimation mode_animation(const RunInfo& info, const Frame& base, const ModeSet& set, const Mode& mode,
                             int frames_per_cycle = kModeFramesPerCycle,
                             double amplitude_fraction = kModeAmplitudeFraction);

/// summary.json "modes": analysis, about, value name/unit/label, and one row per mode
/// (number, value, eigenvalue, rigid_body).
nlohmann::ordered_json modes_json(const ModeSet& set);

/// Mode numbers to show: `wanted` (each checked to exist; throws InputError naming the stored
/// numbers otherwise), or every mode of the set up to `cap` (cap <= 0: all).
std::vector<int> select_modes(const ModeSet& set, const std::vector<int>& wanted, int cap);

struct ModeOutputOptions {
  std::vector<int> modes;         ///< numbers to animate (select_modes); empty = none
  bool frames = true;             ///< frames/mode_NN/frame_KKKKK.png
  bool plot = true;               ///< plots/spectrum.png
  bool movie = false;             ///< modes/mode_NN.mp4 (needs frames)
  bool vtu = false;               ///< export/modes.vtu
  int fps = 25;
  int width = 960, height = 720;
  int frames_per_cycle = kModeFramesPerCycle;
  render::Camera camera;          ///< automatic: an isometric view fitted to the motion
  bool camera_given = false;      ///< `camera` was chosen by the user (--camera)
};

struct ModeOutputReport {
  int modes_animated = 0;                 ///< modes whose every frame was written
  int frames = 0;                         ///< PNGs written, all modes
  std::vector<std::string> written;       ///< every file, relative to the output folder
  std::vector<std::string> movies;        ///< relative paths of the MP4s
  std::string plot;                       ///< "plots/spectrum.png" or ""
  std::string vtu;                        ///< "export/modes.vtu" or ""
  std::string error;                      ///< first failure ("" = everything asked was written)
  std::string no_graphics;                ///< why no pictures were drawn (no OpenGL), else ""
};

/// Writes the mode outputs into `folder` (every file recorded in its manifest). `gc` may be null
/// (a context of its own is made). Never throws for a failed write: the report says it.
ModeOutputReport write_mode_outputs(OutputFolder& folder, const RunInfo& info, const Frame& base, const ModeSet& set,
                                    const ModeOutputOptions& options, render::GraphicsContext* gc,
                                    const std::atomic<bool>& stop);

}  // namespace ff::app
