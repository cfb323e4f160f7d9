#pragma once
/// \file frame_renderer.h
/// Frames to PNG images, headless. The pipeline is built once per run from the RunInfo; each
/// frame only updates point positions and field values, so a sequence renders quickly.
///
/// What a frame shows:
///  - line cells (beams) as tubes of radius FrameStyle::line_radius (world units), joined
///    into polylines so bends are smooth;
///  - triangles and quads as lit, shaded surfaces, with thin element edges when elements are
///    at least ~14 px across in the image. Normals are recomputed from each frame's drawn
///    points (split at creases sharper than 45°, so a fold shows two flat faces), both faces of
///    a shell are lit alike, and the lights (a key light above the eye,
///    fill, head and back lights, all moving with the camera) keep a face turned away from the
///    eye readable: a plate in the isometric view is about as bright as seen face-on, one turned
///    70° from the eye keeps over half of that; surfaces have no highlights (field colours stay
///    true);
///  - with FrameStyle::show_base, a faint grey ghost of Frame::base_points (the undeformed
///    body carried by its rigid motion): thin grey tubes inside/behind the beams, and surfaces
///    drawn beneath the body (a layer under it, opaque but coloured as 20 % grey over the
///    background: cheaper than translucency on llvmpipe); hidden when a frame has no base_points;
///  - a colour bar titled "label [unit]" when a field is chosen ('cool to warm' map with a
///    mid grey, round tick values) in a strip at the right (15 % of the width); the
///    automatic camera centres the body in the area left of it;
///  - top-left text: the title, then "t = 1.250 s", "λ = 0.500" (when the load factor is
///    non-zero) and "deformation ×5" (when deformation_scale != 1).
///  - with FrameStyle::show_triad, an orientation triad in the bottom-left corner: the world
///    axes x (red), y (green), z (blue) as labelled arrows, turned with the camera (off by
///    default: `run` and `replay` frames keep that corner empty; the window turns it on);
///  - node markers set with FrameRenderer::set_markers: dots drawn over everything else at the
///    nodes' drawn positions.
/// Positions are world coordinates p_W in the run's length unit; colours are RGB in [0, 1].

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/frame/frame.h"
#include "render/camera.h"
#include "render/graphics_context.h"

namespace ff::render {

/// How frames look. Copied into the renderer; constant for a run.
struct FrameStyle {
  int width = 960, height = 720;  ///< image size in pixels
  double deformation_scale = 1.0;  ///< drawn points = base + scale * (points - base)
  std::string color_field;         ///< name from RunInfo::fields; "" = uniform colour
  /// Colour range of the field. Equal values = automatic (live views such as the window): the
  /// range of the first frame whose field is not constant by color_range_for() (from 0 for a
  /// field nowhere negative), kept for later frames and only ever widened (to round numbers
  /// again) when a later frame goes outside it, so colours do not flicker and never saturate.
  /// `run` and `replay` pass the range of the whole stored sequence (app/frame_outputs.h,
  /// sequence_view), so every frame and movie of a run shares one range.
  double color_min = 0, color_max = 0;
  Camera camera;
  /// Extra world points (3*m coordinates p_W) the automatic camera keeps in view besides the
  /// reference mesh, e.g. positions from every frame of a stored run on replay.
  std::vector<double> fit_points;
  std::string title;         ///< first overlay line, e.g. the scene name; "" = none
  /// Fixed lines shown under the title instead of the time / λ / deformation / step lines,
  /// for pictures where those would mislead (a mode animation states its arbitrary amplitude
  /// here); "" = the status lines.
  std::string caption;
  double line_radius = 0;    ///< tube radius of line cells in world units; 0 = automatic
                             ///< (1.1 % of the framed half height: ~8 px wide at 720 px)
  bool show_base = true;     ///< faint ghost of base_points
  std::array<double, 3> background{1, 1, 1};
  /// An orientation triad (x red, y green, z blue, labelled) in the bottom-left corner, turning
  /// with the camera; a square of 16 % of the smaller image side (at least 56 px), clear of the
  /// automatic view's framed circle and of the colour bar.
  bool show_triad = false;
  /// Smooth edges with FXAA. Off by default: on Mesa's llvmpipe it roughly triples the
  /// frame time (measured ~50 -> ~220 ms at 960x720) for a small gain in looks.
  bool antialias = false;
};

/// A set of marked mesh nodes (FrameRenderer::set_markers), e.g. the probed node or the nodes a
/// selection picks. Each node is drawn as a dot of `color` with a thin dark rim, centred on
/// the node's drawn position (deformed and scaled as the body) in every later frame, over
/// everything else: over the body, also where the node lies on the far side of it.
struct NodeMarkers {
  std::vector<std::int32_t> nodes;              ///< point indices of RunInfo::mesh (0-based)
  std::array<double, 3> color{1.0, 0.85, 0.0};  ///< fill colour, RGB in [0, 1]
  double size_px = 8.0;  ///< dot size in image pixels, rim included: < 8 a square, >= 8 a disc
};

/// Renders the frames of one run. Use it on the thread that owns its GraphicsContext.
class FrameRenderer {
 public:
  /// Builds the pipeline for info.mesh. Problems (bad indices, unknown color_field, no GL
  /// context) do not throw: ok() turns false and render_png reports them.
  FrameRenderer(GraphicsContext& gc, const RunInfo& info, FrameStyle style);
  ~FrameRenderer();
  FrameRenderer(const FrameRenderer&) = delete;
  FrameRenderer& operator=(const FrameRenderer&) = delete;

  bool ok() const;
  const std::string& error() const;

  /// Renders one frame to png_path (the directory must exist). Only point positions and field
  /// values are updated per call. Returns false and fills *error (if non-null) on failure:
  /// frame sizes that do not match the mesh, non-finite positions, an unwritable path.
  /// The same frame always gives the same bytes.
  bool render_png(const Frame& frame, const std::string& png_path, std::string* error);

  // ---- interactive use (the GUI's viewport) ----------------------------------------------------

  /// Renders one frame into memory: 3 bytes (RGB) per pixel, rows from the bottom up (OpenGL
  /// order), style.width x style.height. Fails like render_png.
  bool render_rgb(const Frame& frame, std::vector<unsigned char>* rgb, std::string* error);
  /// Turns the camera about its focal point: azimuth about the view-up axis, elevation about the
  /// screen's horizontal axis (degrees).
  void orbit(double azimuth_deg, double elevation_deg);
  /// Zooms by `factor` (> 1 brings the body closer).
  void zoom(double factor);
  /// Moves the view by a drag of (dx, dy) pixels (x right, y down), the body following the mouse.
  void pan(double dx_px, double dy_px);
  /// Back to the camera of the style (or the fitted view).
  void reset_camera();
  /// Replaces the camera for the following frames (a scripted camera path): an automatic camera
  /// is fitted to the same mesh and extra points as the style's; the tube radius and the colour
  /// range stay as they are. reset_camera() then returns to this camera.
  void set_camera(const Camera& camera);
  /// The camera as it is now (after orbit/zoom/pan); pass it in FrameStyle::camera to keep the
  /// view when a renderer is rebuilt (a new window size, a new mesh).
  Camera current_camera() const;
  /// Index of the mesh point drawn nearest to pixel (x, y) of the last rendered frame (origin
  /// top left): the point closest to where the body is hit, or, where no body is hit, the point
  /// projected nearest within max_px; -1 when none.
  int pick_point(double x_px, double y_px, double max_px = 24.0);
  /// Indices of the mesh points drawn inside the pixel rectangle with corners (x0, y0) and
  /// (x1, y1) of the last rendered frame (origin top left), front or back: box picking.
  std::vector<int> points_in_rect(double x0_px, double y0_px, double x1_px, double y1_px);
  /// Marks nodes in the following frames, replacing the sets given before; {} removes every
  /// marker. Sets are drawn in order, a later one over an earlier one (put the probed node
  /// last). The dots are a 2D overlay placed per frame from the drawn points and the camera
  /// (after orbit/zoom/pan too). Dots under 8 px are squares drawn as GL points: tens of
  /// thousands cost next to nothing (10 201 nodes at 5 px: no measurable change of a ~30 ms
  /// frame on llvmpipe). From 8 px up they are round discs of a dozen triangles: meant for a
  /// few nodes (the probed one), ~10 ms per thousand on llvmpipe.
  /// Returns false, keeps the previous sets and fills *error (if non-null) when a node index is
  /// outside the mesh or a size is not a finite number in [1, 200] px, or a colour channel is
  /// outside [0, 1].
  bool set_markers(std::vector<NodeMarkers> sets, std::string* error = nullptr);
  /// The marker sets in use.
  const std::vector<NodeMarkers>& markers() const;
  /// Image size in pixels.
  int width() const;
  int height() const;

  /// Current colour range of the field (after automatic choice); {0, 0} without a field.
  std::array<double, 2> color_range() const;
  /// The camera actually used (after automatic fitting).
  Camera camera() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ff::render
