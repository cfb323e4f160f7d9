#include "app/view_options.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <sstream>

#include "app/input_error.h"
#include "core/scene/schema_text.h"

namespace ff::app {

const char* const kCameraHelp =
    "view: auto, iso, top, front, side, or AZIMUTH,ELEVATION in degrees; optionally ,ZOOM (e.g. iso,1.5 or -60,25,2)";

render::Camera parse_camera(const std::string& spec) {
  // one parser for the command line and the scene timeline (core/scene/timeline.h)
  const std::optional<scene::ViewAngles> view = scene::parse_view_angles(spec);
  if (!view)
    throw InputError(std::string("--camera '") + spec + "': expected " + kCameraHelp +
                     " (elevation within -90..90, zoom in (0, 1000])");
  return camera_from_view(*view);
}

render::Camera camera_from_view(const scene::ViewAngles& view) {
  render::Camera cam;  // automatic
  cam.zoom = view.zoom;
  if (view.automatic) return cam;
  const double a = view.azimuth_deg * std::numbers::pi / 180, e = view.elevation_deg * std::numbers::pi / 180;
  cam.view_direction = {std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e)};
  cam.view_up = {0, 0, 1};
  if (std::fabs(view.elevation_deg) > 89.9) {
    const double s = view.elevation_deg > 0 ? 1.0 : -1.0;
    cam.view_up = {-s * std::cos(a), -s * std::sin(a), 0};
  }
  return cam;
}

std::optional<render::Camera> camera_on_path(const std::vector<scene::CameraKey>& path, double t) {
  const std::optional<scene::ViewAngles> v = scene::camera_at(path, t);
  if (!v) return std::nullopt;
  return camera_from_view(*v);
}

std::pair<int, int> parse_size(const std::string& spec) {
  const std::string msg = "--size '" + spec + "': expected WIDTHxHEIGHT in pixels, each 64..8192 (e.g. 1280x720)";
  const std::size_t x = spec.find_first_of("xX");
  if (x == std::string::npos) throw InputError(msg);
  double w = 0, h = 0;
  if (!scene::text::parse_finite(spec.substr(0, x), &w) || !scene::text::parse_finite(spec.substr(x + 1), &h)) throw InputError(msg);
  if (w != std::floor(w) || h != std::floor(h) || w < 64 || h < 64 || w > 8192 || h > 8192) throw InputError(msg);
  return {static_cast<int>(w), static_cast<int>(h)};
}

ExportFormats parse_export_formats(const std::string& spec) {
  ExportFormats f;
  for (const std::string& p : scene::text::split_trimmed(spec, ',')) {
    if (p == "vtu") f.vtu = true;
    else if (p == "gltf" || p == "glb") f.gltf = true;
    else if (p == "obj") f.obj = true;
    else throw InputError("--export '" + spec + "': unknown format '" + p + "'; choose from vtu, gltf, obj (comma separated)");
  }
  if (!f.any()) throw InputError("--export '" + spec + "': name at least one of vtu, gltf, obj");
  return f;
}

render::Camera scene_camera(const FrameMesh& mesh, const std::string& view, const std::vector<double>& center,
                            double radius, const std::vector<double>& motion) {
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
  for (const std::vector<double>* p : {&mesh.reference_points, &motion})
    for (std::size_t i = 0; i < p->size() / 3 * 3; ++i)
      lo[i % 3] = std::min(lo[i % 3], (*p)[i]), hi[i % 3] = std::max(hi[i % 3], (*p)[i]);
  std::array<double, 3> c{0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  if (center.size() == 3) c = {center[0], center[1], center[2]};
  const double r = 0.5 * std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                   (hi[2] - lo[2]) * (hi[2] - lo[2]));
  std::array<double, 3> dir{1, -1, 1}, up{0, 0, 1};
  if (view == "front") dir = {0, -1, 0};
  if (view == "top") dir = {0, 0, 1}, up = {0, 1, 0};
  const double n = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]), dist = 10.0 * std::max(r, 1e-9);
  render::Camera cam;
  cam.automatic = false;
  cam.parallel = true;
  cam.focal_point = c;
  cam.position = {c[0] + dist * dir[0] / n, c[1] + dist * dir[1] / n, c[2] + dist * dir[2] / n};
  cam.view_up = up;
  cam.parallel_scale = radius > 0 ? radius : 1.1 * r;
  return cam;
}

}  // namespace ff::app
