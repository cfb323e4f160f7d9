#pragma once
/// \file camera.h
/// The camera of a rendered frame: what frame_layout.h fits and frame_renderer.h draws through.

#include <array>

namespace ff::render {

/// Where the camera is. With automatic = true the view is fitted to the reference mesh once
/// per run (fixed across frames, so motion is visible): see fit_view() in frame_layout.h.
struct Camera {
  std::array<double, 3> focal_point{0, 0, 0};  ///< p_W of the point looked at
  std::array<double, 3> position{0, 0, 1};     ///< p_W of the eye
  std::array<double, 3> view_up{0, 1, 0};      ///< world direction that points up in the image
  double parallel_scale = 0;  ///< half the image height in world units; 0 = fit the mesh
  bool parallel = true;       ///< parallel (orthographic) projection; false = perspective 30°
  bool automatic = true;      ///< ignore focal_point/position and fit the mesh
  /// With automatic = true: the direction from the framed centre towards the eye (any length),
  /// with view_up as the image's up; {0, 0, 0} = the fit's own choice (plane normal or
  /// isometric) and view_up is ignored. See fit_view().
  std::array<double, 3> view_direction{0, 0, 0};
  double zoom = 1.0;          ///< with automatic = true: > 1 magnifies the fitted view
};

}  // namespace ff::render
