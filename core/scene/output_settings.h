#pragma once
/// \file output_settings.h
/// What a scene's [output] table says about showing a run (scene_common.h declares and reads the
/// keys; load_scene adds the timeline's camera path).

#include <string>
#include <vector>

#include "core/scene/timeline.h"

namespace ff::scene {

/// How a run is shown; plain numbers the app hands to the renderer.
struct OutputSettings {
  bool frames = true;            ///< write PNG frames
  int frame_every = 1;           ///< render every n-th published frame
  int width = 960, height = 720;
  double deformation_scale = 1.0;
  std::string color_field = "deflection";  ///< a field name, or "none"
  bool plots = true;
  /// estimate the metrics' discretization errors from coarser twins (core/model/error_bars.md)
  bool error_bar = true;
  int error_bar_levels = 0;  ///< levels per source: 2 (formal order), 3 (observed order), 0 = auto
  std::string view = "auto";               ///< auto (renderer fits), iso, front (along +y), top (along -z)
  std::vector<double> view_center;         ///< empty = centre of the reference bounding box
  double view_radius = 0.0;                ///< half height of the view in world units; 0 = fit
  /// Camera keys of the scene's [[timeline]] (empty: none); the app interpolates them per frame
  /// with camera_at() unless --camera overrides them.
  std::vector<CameraKey> camera_path;
};

}  // namespace ff::scene
