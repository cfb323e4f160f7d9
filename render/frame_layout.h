#pragma once
/// \file frame_layout.h
/// The decisions behind a rendered frame that need no OpenGL: camera fitting, tube size,
/// overlay text, colour-bar range, line cells joined into polylines. Pure functions, unit
/// tested without a GL context; frame_renderer.cpp applies them.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/frame/frame.h"
#include "render/camera.h"

namespace ff::render {

/// Result of fitting a view to a reference mesh.
struct ViewFit {
  Camera camera;                   ///< automatic = false, all fields filled
  std::array<double, 3> center{};  ///< p_W of the centre of the framed sphere/circle
  double radius = 0;               ///< radius of the framed sphere/circle (world units)
  int plane_normal_axis = -1;      ///< 0/1/2 when the mesh is planar normal to x/y/z, else -1
};

/// Margin between the framed circle and the image edge: half height = 1.1 * radius.
constexpr double kViewMargin = 1.1;

/// Fits the reference points so that the body stays in view through its plausible motion.
///  - Planar mesh (extent normal to a coordinate plane below 1e-6 of its size; z preferred,
///    then y, then x): look along the plane normal (down -z with +y up for z = const;
///    along +y with +z up; along -x with +z up). The framed circle is centred at the origin
///    when the origin lies inside the (5 % inflated) bounding box -- a body rotating about
///    the origin, like a hub with a beam, stays in view at any angle -- else at the bounding
///    box centre; its radius is the largest in-plane distance of a point from that centre.
///  - Otherwise an isometric view from direction (1, -1, 1), +z up, of the sphere about the
///    bounding-box centre through the farthest point.
/// The circle of radius kViewMargin * radius fits the image height and the width left of a
/// strip of reserved_right_px pixels (kept for the colour bar), and is centred in that area:
/// the camera is shifted sideways, so the circle centre is not the image centre then.
/// Parallel: parallel_scale = half the image height in world units. Perspective: 30° view
/// angle at the distance that shows the same circle.
/// A non-zero `direction` (from the framed centre towards the eye, any length) replaces the
/// automatic direction; `up` is then the image's up direction (projected to be normal to it;
/// when nearly parallel to it, +y is used for a view along z and +z otherwise). The centre and
/// radius are chosen as above. zoom > 1 magnifies: the framed half height is divided by it.
ViewFit fit_view(const FrameMesh& mesh, int width, int height, bool parallel,
                 int reserved_right_px = 0, std::array<double, 3> direction = {0, 0, 0},
                 std::array<double, 3> up = {0, 0, 1}, double zoom = 1.0);

/// Automatic tube radius for line cells: 1.1 % of the framed half height in world units.
double automatic_line_radius(const Camera& camera, double radius);

/// "t = 1.250 s" (3 decimals; 4 significant digits for |t| < 0.01 or >= 1e5; no unit if "").
std::string format_time(double t, const std::string& unit);
/// "λ = 0.500" (same number format as format_time).
std::string format_load_factor(double lambda);
/// "deformation ×5", "deformation ×0.5".
std::string format_deformation_scale(double scale);
/// The overlay below the title, one item per line (short lines stay in the image corner):
/// time, then load factor if non-zero, then deformation scale if != 1, then "step 120"
/// (the solver step that produced the frame) when the step is positive.
std::string status_line(const RunInfo& info, const Frame& frame, double deformation_scale);
/// "label [unit]" ("label" alone when unit is empty; name when label is empty).
std::string quantity_title(const Quantity& q);

/// [lo, hi] widened outward to multiples of the decade of its span (10^floor(log10(hi - lo))):
/// [0.0012, 0.0456] -> [0, 0.05], [0.97, 1.03] -> [0.97, 1.03]. Returns lo == hi unchanged.
std::array<double, 2> round_range(double lo, double hi);

/// The colour range FlexFrame shows for field values spanning [lo, hi] (the policy of
/// docs/guide/replay-and-export.md, "Colour range and camera"): a field that is nowhere negative
/// (a magnitude, von Mises, an all-zero initial state) gets a range from 0, one nowhere positive
/// a range up to 0, others round_range(lo, hi); a constant non-zero value c gets [0, c] rounded
/// (or [c, 0]), an all-zero field [0, 1]. Never lo == hi for finite input.
std::array<double, 2> color_range_for(double lo, double hi);

/// Colour-bar labels: round values inside [lo, hi] (steps of 1, 2, 2.5 or 5 times a power of
/// ten, at most max_ticks of them) and one printf format for all, fixed-point when the
/// largest magnitude is in [0.01, 1e5), else scientific, with the digits the step needs:
/// [0, 0.05] -> 0.00 0.01 ... 0.05; [0, 1e-3] -> 0.0e+00 2.0e-04 ... 1.0e-03.
struct Ticks {
  std::vector<double> values;
  std::string format;  ///< e.g. "%.2f" or "%.1e"
};
Ticks color_bar_ticks(double lo, double hi, int max_ticks = 6);

/// Joins 2-point line cells into polylines: chains run through points shared by exactly two
/// segments and stop at ends and junctions; closed loops repeat their first point.
/// Deterministic (follows input order). Segments with equal ends are dropped.
std::vector<std::vector<std::int32_t>> chain_polylines(const std::vector<std::int32_t>& segments);

}  // namespace ff::render
