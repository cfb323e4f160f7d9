#pragma once
/// \file view_options.h
/// Command-line view options shared by `run` and `replay`: --camera, --size, --export, and the
/// camera of a scene's [output] view keys.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/frame/frame.h"
#include "core/scene/timeline.h"
#include "render/frame_renderer.h"

namespace ff::app {

/// Help text of --camera (one line).
extern const char* const kCameraHelp;

/// --camera: `auto` (the renderer's fit), a named view `iso`, `top`, `front`, `side`, or
/// `AZIMUTH,ELEVATION` in degrees (eye direction from the centre: azimuth in the x-y plane from
/// +x towards +y, elevation above it; z up), each optionally followed by `,ZOOM` (> 0; 2 = twice
/// as large). The result is an automatic camera (fitted to the body) looking along that
/// direction: iso = (1, -1, 1), top = (0, 0, 1) with +y up, front = (0, -1, 0), side = (1, 0, 0).
/// Throws InputError naming the accepted forms.
render::Camera parse_camera(const std::string& spec);

/// The automatic camera looking along a view's angles (a point of a scene's camera path):
/// eye direction (cos el cos az, cos el sin az, sin el), z up; looking straight down or up
/// (|el| > 89.9°) the image's up is the horizontal direction away from the eye's azimuth, so
/// `top` is (0, 0, 1) with +y up, as parse_camera("top") gives. `auto` = the fit's own choice.
render::Camera camera_from_view(const scene::ViewAngles& view);

/// The camera of a frame at time (or load factor) t on a scene's camera path; nullopt without
/// keys (the run's fixed camera applies).
std::optional<render::Camera> camera_on_path(const std::vector<scene::CameraKey>& path, double t);

/// --size WxH (e.g. 1280x720; each 64..8192). Throws InputError.
std::pair<int, int> parse_size(const std::string& spec);

/// --export: comma-separated vtu, gltf, obj.
struct ExportFormats {
  bool vtu = false, gltf = false, obj = false;
  bool any() const { return vtu || gltf || obj; }
};
/// Throws InputError naming the accepted formats.
ExportFormats parse_export_formats(const std::string& spec);

/// The fixed camera of a scene's output.view (iso, front, top), output.view_center (empty =
/// centre of the bounding box) and output.view_radius (0 = fit the mesh). The bounding box holds
/// the reference mesh and `motion` (3 coordinates per point, e.g. SequenceView::fit_points): with
/// the positions of every frame, the view holds the body for the whole sequence.
render::Camera scene_camera(const FrameMesh& mesh, const std::string& view, const std::vector<double>& center,
                            double radius, const std::vector<double>& motion = {});

}  // namespace ff::app
