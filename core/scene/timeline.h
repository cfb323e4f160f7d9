#pragma once
/// \file timeline.h
/// Scripted scenes: the `[[timeline]]` entries of a scene file, read into plain values.
/// Each entry has `at` (time in s for dynamics, load factor for statics) and any of
///  - `camera`: a view as `--camera` takes it (auto, iso, top, front, side, or AZIMUTH,ELEVATION,
///    each with an optional ,ZOOM). Between two camera entries the view's azimuth, elevation and
///    zoom are interpolated linearly in time (a camera path); the app applies it per frame.
///  - a parameter change the model's Simulation applies from `at` on (hub_beam: torque_scale;
///    shell_dynamic: gravity); the step containing `at` is split so the change happens exactly
///    at `at`.
/// No rendering types here: the app turns a ViewAngles into the renderer's camera.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/scene/schema.h"

namespace ff::scene {

/// A camera direction as angles: the eye direction from the centre is
/// (cos el cos az, cos el sin az, sin el) in world axes (z up); zoom > 0 magnifies the fitted
/// view. automatic = the renderer's own choice of direction (`auto`); the angles are then unused.
struct ViewAngles {
  bool automatic = false;
  double azimuth_deg = 0.0, elevation_deg = 0.0;
  double zoom = 1.0;
};

/// Parses a view string as `--camera` accepts it. Named views map to angles:
/// iso = (-45, 35.26), front = (-90, 0), side = (0, 0), top = (-90, 90). nullopt when invalid.
std::optional<ViewAngles> parse_view_angles(const std::string& spec);

/// One camera key of the path.
struct CameraKey {
  double at = 0.0;
  std::string spec;  ///< as written in the scene
  ViewAngles view;
};

/// The camera at time (or load factor) t: before the first key the first key, after the last
/// the last; in between, azimuth, elevation and zoom linear in t between the surrounding keys
/// (when either of them is `auto`, the earlier key holds until the next). nullopt without keys.
std::optional<ViewAngles> camera_at(const std::vector<CameraKey>& path, double t);

/// A change of one model parameter from `at` on.
struct ParameterChange {
  double at = 0.0;
  std::string key;             ///< "torque_scale", "gravity"
  std::vector<double> value;   ///< one number, or three for gravity
};

struct Timeline {
  std::vector<CameraKey> camera;
  std::vector<ParameterChange> changes;
  bool empty() const { return camera.empty() && changes.empty(); }
};

/// Declares `[[timeline]]` with `at`, `camera` and the parameter keys a model supports
/// (a subset of "torque_scale", "gravity"); `at_doc`/`at_unit` say what `at` measures.
void declare_timeline(Schema& s, const std::string& at_doc, const std::string& at_unit,
                      const std::vector<std::string>& parameters);

/// Reads and checks the timeline: `at` strictly ascending and within [0, end], every entry
/// changing something, camera views valid. Bad input throws SceneError at the offending key.
Timeline read_timeline(const Document& d, double end);

/// The [[timeline]] keys (besides `at`), as (name, TOML value text), that make the change of a live
/// edit `key` = `value` (TOML value text, already validated) in the scene whose document is `d`:
/// gravity.g = [gx, gy, gz] is gravity = [gx, gy, gz]; torque.amplitude = A is torque_scale =
/// A / torque.amplitude (the scale the model applies). Throws SceneError for a live key with no
/// timeline form or a torque amplitude of 0 in the scene (nothing to scale).
std::vector<std::pair<std::string, std::string>> live_edit_as_timeline(const Document& d, const std::string& key,
                                                                       const std::string& value);

}  // namespace ff::scene
