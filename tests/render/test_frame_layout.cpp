// frame_layout: camera fitting, overlay text, colour range and polyline chaining, no GL.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "render/frame_layout.h"

namespace ff::render {
namespace {

FrameMesh hub_beam_mesh() {
  FrameMesh m;
  // hub rim points at radius 0.05 and a beam from x = 0.05 to 1.85
  for (int k = 0; k < 8; ++k) {
    const double a = 2 * std::numbers::pi * k / 8;
    m.reference_points.insert(m.reference_points.end(), {0.05 * std::cos(a), 0.05 * std::sin(a), 0});
  }
  for (int i = 0; i <= 10; ++i) m.reference_points.insert(m.reference_points.end(), {0.05 + 0.18 * i, 0, 0});
  return m;
}

TEST(FitView, PlanarRotatingBodyIsFramedAboutTheOrigin) {
  const ViewFit fit = fit_view(hub_beam_mesh(), 960, 720, true);
  EXPECT_EQ(fit.plane_normal_axis, 2);
  EXPECT_NEAR(fit.center[0], 0.0, 1e-15);
  EXPECT_NEAR(fit.center[1], 0.0, 1e-15);
  EXPECT_NEAR(fit.radius, 1.85, 1e-12);
  EXPECT_NEAR(fit.camera.parallel_scale, 1.1 * 1.85, 1e-12);
  // looking down -z with +y up
  EXPECT_GT(fit.camera.position[2], fit.camera.focal_point[2]);
  EXPECT_DOUBLE_EQ(fit.camera.position[0], fit.camera.focal_point[0]);
  EXPECT_DOUBLE_EQ(fit.camera.view_up[1], 1.0);
  // a point at radius 1.85 in any direction stays inside the image
  const double px_per_m = 360.0 / fit.camera.parallel_scale;
  EXPECT_LT(1.85 * px_per_m, 360.0);
  EXPECT_LT(1.85 * px_per_m, 480.0);
}

TEST(FitView, ReservedStripShiftsTheCircleLeftAndStillFits) {
  const int w = 960, h = 720, strip = 144;
  const ViewFit fit = fit_view(hub_beam_mesh(), w, h, true, strip);
  const double px_per_m = 0.5 * h / fit.camera.parallel_scale;
  // column of the origin
  const double col = 0.5 * w + (0.0 - fit.camera.focal_point[0]) * px_per_m;
  EXPECT_NEAR(col, 0.5 * (w - strip), 1e-9);
  EXPECT_LE(col + 1.1 * 1.85 * px_per_m, w - strip + 1e-9);
  // a square image with a strip: the width limits, the scale grows
  const ViewFit sq = fit_view(hub_beam_mesh(), 600, 600, true, 90);
  EXPECT_NEAR(sq.camera.parallel_scale, 1.1 * 1.85 * 600.0 / 510.0, 1e-12);
}

TEST(FitView, BodyAwayFromOriginIsFramedAboutItsBox) {
  FrameMesh m;
  m.reference_points = {10, 0, 0, 12, 0, 0, 12, 1, 0, 10, 1, 0};
  const ViewFit fit = fit_view(m, 800, 800, true);
  EXPECT_NEAR(fit.center[0], 11.0, 1e-12);
  EXPECT_NEAR(fit.center[1], 0.5, 1e-12);
  EXPECT_NEAR(fit.radius, std::sqrt(1.25), 1e-12);
}

TEST(FitView, SolidGetsAnIsometricView) {
  FrameMesh m;
  m.reference_points = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1};
  const ViewFit fit = fit_view(m, 960, 720, true);
  EXPECT_EQ(fit.plane_normal_axis, -1);
  const auto& p = fit.camera.position;
  const auto& f = fit.camera.focal_point;
  EXPECT_GT(p[0] - f[0], 0);
  EXPECT_LT(p[1] - f[1], 0);
  EXPECT_GT(p[2] - f[2], 0);
  EXPECT_NEAR(fit.radius, std::sqrt(0.75), 1e-12);
  EXPECT_DOUBLE_EQ(fit.camera.view_up[2], 1.0);
}

TEST(FitView, RequestedDirectionUpAndZoom) {
  // a side view of the planar hub-beam: the eye along +x, +z up; the circle about the origin
  const ViewFit fit = fit_view(hub_beam_mesh(), 960, 720, true, 0, {2, 0, 0}, {0, 0, 1}, 2.0);
  const auto& p = fit.camera.position;
  const auto& f = fit.camera.focal_point;
  EXPECT_GT(p[0] - f[0], 0);
  EXPECT_NEAR(p[1] - f[1], 0, 1e-12);
  EXPECT_NEAR(p[2] - f[2], 0, 1e-12);
  EXPECT_NEAR(fit.camera.view_up[2], 1.0, 1e-12);
  EXPECT_NEAR(fit.center[0], 0.0, 1e-15);
  EXPECT_NEAR(fit.camera.parallel_scale, 1.1 * 1.85 / 2.0, 1e-12) << "zoom 2 halves the framed height";
  // up not normal to the direction is made normal; up along the direction falls back
  const ViewFit oblique = fit_view(hub_beam_mesh(), 960, 720, true, 0, {1, 0, 1}, {0, 0, 1});
  const auto& u = oblique.camera.view_up;
  EXPECT_NEAR(u[0] + u[2], 0, 1e-12);
  EXPECT_NEAR(u[0] * u[0] + u[1] * u[1] + u[2] * u[2], 1, 1e-12);
  const ViewFit top = fit_view(hub_beam_mesh(), 960, 720, true, 0, {0, 0, 1}, {0, 0, 1});
  EXPECT_NEAR(top.camera.view_up[1], 1.0, 1e-12);
  // no direction: the automatic choice, as before
  const ViewFit automatic = fit_view(hub_beam_mesh(), 960, 720, true, 0, {0, 0, 0}, {1, 0, 0});
  EXPECT_DOUBLE_EQ(automatic.camera.view_up[1], 1.0);
}

TEST(FitView, EmptyMeshGivesAUsableCamera) {
  const ViewFit fit = fit_view(FrameMesh{}, 960, 720, false);
  EXPECT_GT(fit.camera.parallel_scale, 0);
  EXPECT_TRUE(std::isfinite(fit.camera.position[2]));
}

TEST(LineRadius, ScalesWithTheFramedHeight) {
  Camera c;
  c.parallel_scale = 2.0;
  EXPECT_NEAR(automatic_line_radius(c, 1.8), 0.022, 1e-12);
}

TEST(Overlay, TextFormats) {
  EXPECT_EQ(format_time(1.25, "s"), "t = 1.250 s");
  EXPECT_EQ(format_time(0.0, "s"), "t = 0.000 s");
  EXPECT_EQ(format_time(0.0005, "s"), "t = 0.0005 s");
  EXPECT_EQ(format_time(2.0, ""), "t = 2.000");
  EXPECT_EQ(format_load_factor(0.5), "\u03bb = 0.500");
  EXPECT_EQ(format_deformation_scale(5), "deformation \u00d75");
  EXPECT_EQ(format_deformation_scale(0.5), "deformation \u00d70.5");
  EXPECT_EQ(quantity_title({"hub_angle", "deg", "hub angle"}), "hub angle [deg]");
  EXPECT_EQ(quantity_title({"ratio", "", ""}), "ratio");

  RunInfo info;
  Frame f;
  f.time = 1.25;
  EXPECT_EQ(status_line(info, f, 1.0), "t = 1.250 s");
  f.load_factor = 0.5;
  EXPECT_EQ(status_line(info, f, 5.0), "t = 1.250 s\n\u03bb = 0.500\ndeformation \u00d75");
  f.step = 120;
  EXPECT_EQ(status_line(info, f, 1.0), "t = 1.250 s\n\u03bb = 0.500\nstep 120");
  // statics: the pseudo-time (no unit) is the load factor, printed once, also at λ = 0
  info.time_unit = "";
  f.time = f.load_factor = 0.0;
  f.step = 0;
  EXPECT_EQ(status_line(info, f, 1.0), "\u03bb = 0.000");
  f.time = f.load_factor = 0.5;
  f.step = 3;
  EXPECT_EQ(status_line(info, f, 10.0), "\u03bb = 0.500\ndeformation \u00d710\nstep 3");
}

TEST(ColourRange, RoundsOutwardToTheSpansDecade) {
  auto r = round_range(0.0012, 0.0456);
  EXPECT_NEAR(r[0], 0.0, 1e-18);
  EXPECT_NEAR(r[1], 0.05, 1e-15);
  r = round_range(0.97, 1.03);
  EXPECT_NEAR(r[0], 0.97, 1e-12);
  EXPECT_NEAR(r[1], 1.03, 1e-12);
  r = round_range(-3.2, 7.9);
  EXPECT_NEAR(r[0], -10.0, 1e-12);
  EXPECT_NEAR(r[1], 10.0, 1e-12);
  r = round_range(2.0, 2.0);
  EXPECT_EQ(r[0], 2.0);
  EXPECT_EQ(r[1], 2.0);
  // never narrower than the input
  r = round_range(0.1234, 0.9876);
  EXPECT_LE(r[0], 0.1234);
  EXPECT_GE(r[1], 0.9876);
}

TEST(ColourRange, AFieldNowhereNegativeStartsAtZero) {
  // a magnitude at t = 0 (all zero) and a constant magnitude: from 0, never below
  auto r = color_range_for(0.0, 0.0);
  EXPECT_DOUBLE_EQ(r[0], 0.0);
  EXPECT_DOUBLE_EQ(r[1], 1.0);
  r = color_range_for(0.37, 0.37);
  EXPECT_DOUBLE_EQ(r[0], 0.0);
  EXPECT_NEAR(r[1], 0.4, 1e-15);
  // a field nowhere negative starts at 0 although its smallest value is not 0
  r = color_range_for(0.2, 3.4);
  EXPECT_DOUBLE_EQ(r[0], 0.0);
  EXPECT_NEAR(r[1], 4.0, 1e-15);
  // nowhere positive: up to 0; both signs: rounded outward as round_range
  r = color_range_for(-0.0123, -0.002);
  EXPECT_NEAR(r[0], -0.02, 1e-17);
  EXPECT_DOUBLE_EQ(r[1], 0.0);
  r = color_range_for(-3.2, 7.9);
  EXPECT_NEAR(r[0], -10.0, 1e-12);
  EXPECT_NEAR(r[1], 10.0, 1e-12);
}

TEST(ColourBarTicks, RoundValuesAndOneFormat) {
  Ticks t = color_bar_ticks(0.0, 0.05);
  ASSERT_EQ(t.values.size(), 6u);
  EXPECT_NEAR(t.values[1], 0.01, 1e-15);
  EXPECT_EQ(t.format, "%.2f");
  t = color_bar_ticks(0.0, 1e-3);
  ASSERT_EQ(t.values.size(), 6u);
  EXPECT_EQ(t.values[0], 0.0);
  EXPECT_NEAR(t.values[5], 1e-3, 1e-18);
  EXPECT_EQ(t.format, "%.1e");
  t = color_bar_ticks(-10.0, 10.0);
  EXPECT_EQ(t.values, (std::vector<double>{-10, -5, 0, 5, 10}));
  EXPECT_EQ(t.format, "%.0f");
  t = color_bar_ticks(0.0, 1.0, 5);
  EXPECT_EQ(t.values, (std::vector<double>{0, 0.25, 0.5, 0.75, 1.0}));
  EXPECT_EQ(t.format, "%.2f");
  // all ticks inside the range, never more than asked for
  t = color_bar_ticks(0.13, 0.97, 6);
  EXPECT_LE(t.values.size(), 6u);
  for (double v : t.values) {
    EXPECT_GE(v, 0.13);
    EXPECT_LE(v, 0.97);
  }
}

TEST(Polylines, SegmentsAreChainedThroughSharedPoints) {
  // a beam 0-1-2-3 given out of order, and a separate segment 7-8
  const auto lines = chain_polylines({2, 3, 0, 1, 1, 2, 7, 8});
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0], (std::vector<std::int32_t>{3, 2, 1, 0}));
  EXPECT_EQ(lines[1], (std::vector<std::int32_t>{7, 8}));
}

TEST(Polylines, JunctionsSplitAndLoopsClose) {
  // a T: 0-1-2 with a branch 1-3; and a triangle loop 5-6-7
  const auto lines = chain_polylines({0, 1, 1, 2, 1, 3, 5, 6, 6, 7, 7, 5, 4, 4});
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], (std::vector<std::int32_t>{0, 1}));
  EXPECT_EQ(lines[1], (std::vector<std::int32_t>{1, 2}));
  EXPECT_EQ(lines[2], (std::vector<std::int32_t>{1, 3}));
  EXPECT_EQ(lines[3], (std::vector<std::int32_t>{5, 6, 7, 5}));
  // every segment is used exactly once
  std::size_t segments = 0;
  for (const auto& l : lines) segments += l.size() - 1;
  EXPECT_EQ(segments, 6u);
}

}  // namespace
}  // namespace ff::render
