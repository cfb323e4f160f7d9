#include "render/frame_layout.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace ff::render {
namespace {

constexpr double kPerspectiveViewAngleDeg = 30.0;
constexpr double kLineRadiusFraction = 0.011;

std::string format_number(double v) {
  char buf[48];
  const double a = std::fabs(v);
  if (v == 0.0 || (a >= 0.01 && a < 1e5))
    std::snprintf(buf, sizeof buf, "%.3f", v);
  else
    std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

ViewFit fit_view(const FrameMesh& mesh, int width, int height, bool parallel,
                 int reserved_right_px, std::array<double, 3> direction,
                 std::array<double, 3> requested_up, double zoom) {
  ViewFit fit;
  Camera& cam = fit.camera;
  cam.automatic = false;
  cam.parallel = parallel;
  const std::size_t n = mesh.point_count();
  width = std::max(width, 1);
  height = std::max(height, 1);
  reserved_right_px = std::clamp(reserved_right_px, 0, width / 2);
  const int usable_width = width - reserved_right_px;

  std::array<double, 3> lo{0, 0, 0}, hi{0, 0, 0};
  bool any = false;
  for (std::size_t i = 0; i < n; ++i) {
    const double* p = &mesh.reference_points[3 * i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) continue;
    for (int k = 0; k < 3; ++k) {
      lo[k] = any ? std::min(lo[k], p[k]) : p[k];
      hi[k] = any ? std::max(hi[k], p[k]) : p[k];
    }
    any = true;
  }
  const double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});

  // a plane normal to a coordinate axis; z first: the common case is a planar model in x-y
  int axis = -1;
  if (any && size > 0) {
    for (int k : {2, 1, 0}) {
      if (hi[k] - lo[k] <= 1e-6 * size) {
        axis = k;
        break;
      }
    }
  }
  fit.plane_normal_axis = axis;

  std::array<double, 3> c{0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  if (axis >= 0) {
    // rotation about the origin is the plausible motion when the origin is on the body
    const double pad = 0.05 * size;
    bool origin_inside = true;
    for (int k = 0; k < 3; ++k)
      if (k != axis && (lo[k] - pad > 0.0 || hi[k] + pad < 0.0)) origin_inside = false;
    if (origin_inside)
      for (int k = 0; k < 3; ++k)
        if (k != axis) c[k] = 0.0;
  }
  double r2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double* p = &mesh.reference_points[3 * i];
    double d2 = 0;
    for (int k = 0; k < 3; ++k)
      if (k != axis) d2 += (p[k] - c[k]) * (p[k] - c[k]);
    if (std::isfinite(d2)) r2 = std::max(r2, d2);
  }
  double radius = std::sqrt(r2);
  if (!(radius > 0)) radius = 1.0;  // a single point or nothing: frame a unit circle
  fit.center = c;
  fit.radius = radius;

  std::array<double, 3> dir{0, 0, 1}, up{0, 1, 0};  // from focal point towards the eye
  if (axis == 1) {
    dir = {0, -1, 0};
    up = {0, 0, 1};
  } else if (axis == 0) {
    dir = {1, 0, 0};
    up = {0, 0, 1};
  } else if (axis < 0) {
    const double s = 1.0 / std::sqrt(3.0);
    dir = {s, -s, s};
    up = {0, 0, 1};
  }
  const double dir_len = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] +
                                   direction[2] * direction[2]);
  if (dir_len > 0 && std::isfinite(dir_len)) {
    for (int k = 0; k < 3; ++k) dir[k] = direction[k] / dir_len;
    // up made normal to the direction; a fallback when the two are (nearly) parallel
    auto orthogonal_up = [&](const std::array<double, 3>& u) {
      const double d = u[0] * dir[0] + u[1] * dir[1] + u[2] * dir[2];
      std::array<double, 3> v{u[0] - d * dir[0], u[1] - d * dir[1], u[2] - d * dir[2]};
      const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
      const double ulen = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
      if (!(len > 1e-3 * ulen) || !(ulen > 0)) return std::array<double, 3>{0, 0, 0};
      return std::array<double, 3>{v[0] / len, v[1] / len, v[2] / len};
    };
    up = orthogonal_up(requested_up);
    if (up == std::array<double, 3>{0, 0, 0})
      up = orthogonal_up(std::fabs(dir[2]) > 0.9 ? std::array<double, 3>{0, 1, 0}
                                                 : std::array<double, 3>{0, 0, 1});
  }
  // the circle must fit the height and the usable width
  const double usable_aspect = static_cast<double>(usable_width) / height;
  const double half_height = kViewMargin * radius / std::min(1.0, usable_aspect) /
                             (zoom > 0 && std::isfinite(zoom) ? zoom : 1.0);
  double distance = 4.0 * radius;
  if (!parallel) {
    const double half_angle = 0.5 * kPerspectiveViewAngleDeg * std::numbers::pi / 180.0;
    distance = std::max(distance, half_height / std::tan(half_angle) + radius);
  }
  // centre the circle in the usable area: the view centre sits half the strip to its right
  const std::array<double, 3> right{-dir[1] * up[2] + dir[2] * up[1], -dir[2] * up[0] + dir[0] * up[2],
                                    -dir[0] * up[1] + dir[1] * up[0]};  // (-dir) x up
  const double focal_half_height =
      parallel ? half_height
               : distance * std::tan(0.5 * kPerspectiveViewAngleDeg * std::numbers::pi / 180.0);
  const double shift = 0.5 * reserved_right_px * (2.0 * focal_half_height / height);
  for (int k = 0; k < 3; ++k) {
    cam.focal_point[k] = c[k] + shift * right[k];
    cam.position[k] = cam.focal_point[k] + distance * dir[k];
  }
  cam.view_up = up;
  cam.parallel_scale = half_height;
  return fit;
}

double automatic_line_radius(const Camera& camera, double radius) {
  double half_height = camera.parallel_scale;
  if (!camera.parallel || !(half_height > 0)) {
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double d = camera.position[k] - camera.focal_point[k];
      d2 += d * d;
    }
    const double half_angle = 0.5 * kPerspectiveViewAngleDeg * std::numbers::pi / 180.0;
    half_height = d2 > 0 ? std::sqrt(d2) * std::tan(half_angle) : kViewMargin * radius;
  }
  return kLineRadiusFraction * half_height;
}

// (strings are built by appending: GCC 12 warns falsely on "literal" + std::string)
std::string format_time(double t, const std::string& unit) {
  std::string s = "t = ";
  s += format_number(t);
  if (!unit.empty()) s.append(" ").append(unit);
  return s;
}

std::string format_load_factor(double lambda) {
  std::string s = "\u03bb = ";
  s += format_number(lambda);
  return s;
}

std::string format_deformation_scale(double scale) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%g", scale);
  std::string s = "deformation \u00d7";
  s += buf;
  return s;
}

std::string status_line(const RunInfo& info, const Frame& frame, double deformation_scale) {
  // a time without a unit is a static run's pseudo-time, its load factor: the λ line says it
  const bool pseudo_time = info.time_unit.empty();
  std::string s = pseudo_time ? format_load_factor(frame.load_factor) : format_time(frame.time, info.time_unit);
  if (!pseudo_time && frame.load_factor != 0.0) s.append("\n").append(format_load_factor(frame.load_factor));
  if (deformation_scale != 1.0)
    s.append("\n").append(format_deformation_scale(deformation_scale));
  if (frame.step > 0) s.append("\nstep ").append(std::to_string(frame.step));
  return s;
}

std::string quantity_title(const Quantity& q) {
  std::string s = q.label.empty() ? q.name : q.label;
  if (!q.unit.empty()) s.append(" [").append(q.unit).append("]");
  return s;
}

std::array<double, 2> round_range(double lo, double hi) {
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return {lo, hi};
  const double step = std::pow(10.0, std::floor(std::log10(hi - lo)));
  // a hair of slack so values that are already round stay put despite rounding error
  const double a = std::floor(lo / step + 1e-9) * step;
  const double b = std::ceil(hi / step - 1e-9) * step;
  return {std::min(a, lo), std::max(b, hi)};
}

std::array<double, 2> color_range_for(double lo, double hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || hi < lo) return {lo, hi};
  if (lo >= 0.0) return hi > 0.0 ? std::array<double, 2>{0.0, round_range(0.0, hi)[1]} : std::array<double, 2>{0.0, 1.0};
  if (hi <= 0.0) return {round_range(lo, 0.0)[0], 0.0};
  return round_range(lo, hi);
}

Ticks color_bar_ticks(double lo, double hi, int max_ticks) {
  Ticks t;
  max_ticks = std::max(max_ticks, 2);
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) {
    t.values = {lo};
    t.format = "%.3g";
    return t;
  }
  const double raw = (hi - lo) / (max_ticks - 1);
  const double decade = std::pow(10.0, std::floor(std::log10(raw)));
  double mantissa = 10.0;
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (m * decade >= raw * (1 - 1e-9)) {
      mantissa = m;
      break;
    }
  }
  const double step = mantissa * decade;
  const double first = std::ceil(lo / step - 1e-9), last = std::floor(hi / step + 1e-9);
  for (double k = first; k <= last; k += 1.0) {
    double v = k * step;
    if (std::fabs(v) < 1e-9 * step) v = 0.0;  // an exact zero, not -1e-20
    t.values.push_back(v);
  }
  const int extra = mantissa == 2.5 ? 1 : 0;  // 2.5 steps need one more digit
  const double amax = std::max(std::fabs(lo), std::fabs(hi));
  char buf[16];
  if (amax >= 1e-2 && amax < 1e5) {
    const int d = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)) + extra);
    std::snprintf(buf, sizeof buf, "%%.%df", d);
  } else {
    const double e = std::floor(std::log10(amax));
    const double m_step = step / std::pow(10.0, e);
    const int d = std::max(0, static_cast<int>(-std::floor(std::log10(m_step) + 1e-9)) + extra);
    std::snprintf(buf, sizeof buf, "%%.%de", d);
  }
  t.format = buf;
  return t;
}

std::vector<std::vector<std::int32_t>> chain_polylines(const std::vector<std::int32_t>& segments) {
  const std::size_t m = segments.size() / 2;
  std::int32_t max_index = -1;
  for (std::int32_t v : segments) max_index = std::max(max_index, v);
  std::vector<std::vector<std::size_t>> at(static_cast<std::size_t>(max_index + 1));
  std::vector<char> used(m, 0);
  for (std::size_t e = 0; e < m; ++e) {
    const std::int32_t a = segments[2 * e], b = segments[2 * e + 1];
    if (a < 0 || b < 0 || a == b) {
      used[e] = 1;  // degenerate or invalid: never drawn
      continue;
    }
    at[a].push_back(e);
    at[b].push_back(e);
  }
  auto other = [&](std::size_t e, std::int32_t v) {
    return segments[2 * e] == v ? segments[2 * e + 1] : segments[2 * e];
  };
  auto walk = [&](std::int32_t start, std::size_t first_edge) {
    std::vector<std::int32_t> line{start};
    std::int32_t cur = start;
    std::size_t e = first_edge;
    while (true) {
      used[e] = 1;
      cur = other(e, cur);
      line.push_back(cur);
      if (at[cur].size() != 2) break;  // an end or a junction
      const std::size_t next = at[cur][0] == e ? at[cur][1] : at[cur][0];
      if (used[next]) break;  // closed loop complete
      e = next;
    }
    return line;
  };

  std::vector<std::vector<std::int32_t>> lines;
  // open chains start at ends and junctions, in the order the segments list them
  for (std::size_t e = 0; e < m; ++e) {
    for (int side = 0; side < 2 && !used[e]; ++side) {
      const std::int32_t v = segments[2 * e + side];
      if (at[v].size() == 2) continue;
      for (std::size_t f : at[v])
        if (!used[f]) lines.push_back(walk(v, f));
    }
  }
  // what is left are closed loops
  for (std::size_t e = 0; e < m; ++e)
    if (!used[e]) lines.push_back(walk(segments[2 * e], e));
  return lines;
}

}  // namespace ff::render
