#include "core/scene/timeline.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "core/scene/schema_text.h"

namespace ff::scene {

namespace {

const char* const kViewForms =
    "auto, iso, top, front, side, or AZIMUTH,ELEVATION in degrees (elevation within -90..90); "
    "optionally ,ZOOM in (0, 1000] (e.g. iso,1.5 or -60,25,2)";

}  // namespace

std::optional<ViewAngles> parse_view_angles(const std::string& spec) {
  const std::vector<std::string> parts = text::split_trimmed(spec, ',');
  if (parts.empty() || parts.size() > 3) return std::nullopt;
  ViewAngles v;
  std::size_t used = 1;
  if (parts[0] == "auto") {
    v.automatic = true;
  } else if (parts[0] == "iso") {
    v.azimuth_deg = -45.0;
    v.elevation_deg = std::atan(1.0 / std::sqrt(2.0)) * 180.0 / M_PI;
  } else if (parts[0] == "front") {
    v.azimuth_deg = -90.0;
  } else if (parts[0] == "side") {
    v.azimuth_deg = 0.0;
  } else if (parts[0] == "top") {
    v.azimuth_deg = -90.0;
    v.elevation_deg = 90.0;
  } else {
    if (parts.size() < 2 || !text::parse_finite(parts[0], &v.azimuth_deg) || !text::parse_finite(parts[1], &v.elevation_deg) ||
        std::fabs(v.elevation_deg) > 90.0)
      return std::nullopt;
    used = 2;
  }
  if (parts.size() > used + 1) return std::nullopt;
  if (parts.size() == used + 1) {
    if (!text::parse_finite(parts[used], &v.zoom) || !(v.zoom > 0) || v.zoom > 1000) return std::nullopt;
  }
  return v;
}

std::optional<ViewAngles> camera_at(const std::vector<CameraKey>& path, double t) {
  if (path.empty()) return std::nullopt;
  if (t <= path.front().at) return path.front().view;
  for (std::size_t k = 1; k < path.size(); ++k) {
    if (t >= path[k].at) continue;
    const ViewAngles& a = path[k - 1].view;
    const ViewAngles& b = path[k].view;
    if (a.automatic || b.automatic) return a;
    const double s = (t - path[k - 1].at) / (path[k].at - path[k - 1].at);
    ViewAngles v;
    v.azimuth_deg = a.azimuth_deg + s * (b.azimuth_deg - a.azimuth_deg);
    v.elevation_deg = a.elevation_deg + s * (b.elevation_deg - a.elevation_deg);
    v.zoom = a.zoom + s * (b.zoom - a.zoom);
    return v;
  }
  return path.back().view;
}

void declare_timeline(Schema& s, const std::string& at_doc, const std::string& at_unit,
                      const std::vector<std::string>& parameters) {
  s.table_array("timeline",
                "scripted events: camera path and parameter changes at given times (docs/guide/timeline.md)")
      .number("timeline.at", at_doc, std::nullopt, Range::non_negative(), at_unit)
      .string("timeline.camera",
              std::string("camera key of the path (interpolated linearly in time between keys): ") + kViewForms +
                  "; \"\" = none",
              std::string{});
  for (const std::string& p : parameters) {
    if (p == "torque_scale")
      s.number("timeline.torque_scale", "multiplies the hub torque tau(t) from `at` on (0 switches it off)", 1.0,
               Range::non_negative());
    else if (p == "gravity")
      s.number_list("timeline.gravity",
                    "gravity vector [gx, gy, gz] from `at` on (needs the effect gravity); as gravity.g, each component "
                    "within [-1e100, 1e100]",
                    std::vector<double>{}, Range::closed(-1e100, 1e100), 0, 3, "m/s^2");
  }
}

Timeline read_timeline(const Document& d, double end) {
  Timeline tl;
  const std::size_t n = d.count("timeline");
  const std::vector<std::string> keys = d.element_key_paths("timeline");
  auto declared = [&](const char* k) {
    for (const std::string& p : keys)
      if (p == k) return true;
    return false;
  };
  std::vector<Issue> issues;
  double previous = -1.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double at = d.number("timeline.at", i);
    if (at <= previous && i > 0)
      issues.push_back(d.issue("timeline.at", i, "expected entries in ascending order of `at`: " + d.value_text("timeline.at", i) +
                                                     " does not exceed the previous entry's " +
                                                     d.value_text("timeline.at", i - 1)));
    if (at > end)
      issues.push_back(d.issue("timeline.at", i, "expected a value within [0, " + std::to_string(end) +
                                                     "] (the run's end), got " + d.value_text("timeline.at", i)));
    previous = at;
    bool changes = false;
    if (d.present("timeline.camera", i)) {
      const std::string& spec = d.string("timeline.camera", i);
      const std::optional<ViewAngles> v = parse_view_angles(spec);
      if (!v)
        issues.push_back(d.issue("timeline.camera", i, std::string("expected ") + kViewForms + ", got \"" + spec + "\""));
      else
        tl.camera.push_back({at, spec, *v});
      changes = true;
    }
    if (declared("timeline.torque_scale") && d.present("timeline.torque_scale", i)) {
      tl.changes.push_back({at, "torque_scale", {d.number("timeline.torque_scale", i)}});
      changes = true;
    }
    if (declared("timeline.gravity") && d.present("timeline.gravity", i)) {
      const std::vector<double> g = d.numbers("timeline.gravity", i);
      if (g.size() != 3)
        issues.push_back(d.issue("timeline.gravity", i, "expected three components [gx, gy, gz]"));
      tl.changes.push_back({at, "gravity", g});
      changes = true;
    }
    if (!changes) {
      std::string what = "camera";
      for (const std::string& k : keys)
        if (k != "timeline.at" && k != "timeline.camera") what += ", " + k.substr(k.find('.') + 1);
      issues.push_back(d.issue("timeline.at", i, "this entry changes nothing: give at least one of " + what));
    }
  }
  if (!issues.empty()) throw SceneError(std::move(issues));
  return tl;
}

std::vector<std::pair<std::string, std::string>> live_edit_as_timeline(const Document& d, const std::string& key,
                                                                       const std::string& value) {
  if (key == "gravity.g") return {{"gravity", value}};
  if (key == "torque.amplitude") {
    const double base = d.number("torque.amplitude");
    if (base == 0.0)
      throw SceneError({d.issue("torque.amplitude", "is 0, so a live torque amplitude has no timeline torque_scale "
                                                    "to be written as; set torque.amplitude before the run instead")});
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", std::strtod(value.c_str(), nullptr) / base);
    return {{"torque_scale", text}};
  }
  throw SceneError({Issue{"", 0, 0, key, "has no [[timeline]] form (timeline keys: gravity, torque_scale)"}});
}

}  // namespace ff::scene
