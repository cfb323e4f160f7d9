// FrameRenderer end to end: synthetic hub-beam frames rendered headless to PNG, read back,
// and checked where the beam must be and where nothing may be.

#include <gtest/gtest.h>

#include <vtkNew.h>
#include <vtkPNGReader.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numbers>
#include <thread>
#include <tuple>

#include "render/frame_renderer.h"
#include "render/graphics_context.h"
#include "render_test_support.h"

namespace ff::render {
namespace {

using test::any_near;
using test::is_background;
using test::is_ink;

class FrameRendererTest : public ::testing::Test {
 protected:
  void SetUp() override {
    unsetenv("DISPLAY");  // the headless path is the one under test
    std::string err;
    gc_ = GraphicsContext::create(&err);
    ASSERT_NE(gc_, nullptr) << err;
    info_ = test::hub_beam_run();
  }
  FrameStyle field_style() const {
    FrameStyle s;
    s.color_field = "axial_strain";
    s.title = info_.scene_name;
    return s;
  }
  std::unique_ptr<GraphicsContext> gc_;
  RunInfo info_;
};

// count of beam sample points (x from 0.25 m to tip - 0.1 m, along direction angle) drawn
int beam_hits(const test::Image& img, const Camera& cam, double angle) {
  int hits = 0;
  for (int k = 0; k < 20; ++k) {
    const double r = 0.25 + (test::kBeamLength - 0.2) * k / 19.0;
    const auto px = test::to_pixel(cam, img.width, img.height, r * std::cos(angle), r * std::sin(angle));
    hits += any_near(img, px[0], px[1], 1, is_ink);
  }
  return hits;
}

// count of samples in a 1.0 m x 0.4 m block centred at distance 0.9 m, 0.6 m off the beam
// axis (on the +90° side), that are exact background
int clear_hits(const test::Image& img, const Camera& cam, double angle, int* total) {
  int clear = 0;
  *total = 0;
  const double c = std::cos(angle), s = std::sin(angle);
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 5; ++j) {
      const double along = 0.4 + 1.0 * i / 9.0, across = 0.4 + 0.4 * j / 4.0;
      const auto px = test::to_pixel(cam, img.width, img.height, c * along - s * across,
                                     s * along + c * across);
      clear += is_background(img.at(px[0], px[1]));
      ++*total;
    }
  return clear;
}

TEST_F(FrameRendererTest, BeamIsDrawnWhereItIsAndNothingElsewhere) {
  FrameRenderer renderer(*gc_, info_, field_style());
  ASSERT_TRUE(renderer.ok()) << renderer.error();
  const std::string path = test::out_dir() + "/hub_beam_0deg.png";
  std::string err;
  ASSERT_TRUE(renderer.render_png(test::hub_beam_frame(info_, 0.0, 0.02, 1.25), path, &err)) << err;

  const test::Image img = test::read_png(path);
  ASSERT_EQ(img.width, 960);
  ASSERT_EQ(img.height, 720);
  const Camera cam = renderer.camera();
  // fitted to the circle swept by the beam about the origin, looking down -z, centred in
  // the area left of the colour-bar strip (15 % of the width)
  EXPECT_NEAR(cam.focal_point[1], 0.0, 1e-12);
  EXPECT_NEAR(cam.parallel_scale, 1.1 * (test::kHubRadius + test::kBeamLength), 1e-9);
  EXPECT_NEAR(test::to_pixel(cam, 960, 720, 0.0, 0.0)[0], (960 - 144) / 2, 1);

  EXPECT_EQ(beam_hits(img, cam, 0.0), 20) << "beam not drawn along +x";
  int total = 0;
  EXPECT_EQ(clear_hits(img, cam, 0.0, &total), total) << "something drawn above the beam";
  // nothing along -x, where the beam is not
  EXPECT_EQ(beam_hits(img, cam, std::numbers::pi), 0);
  // the hub disc is drawn at the origin
  const auto o = test::to_pixel(cam, img.width, img.height, 0.0, 0.0);
  EXPECT_TRUE(is_ink(img.at(o[0], o[1])));
}

TEST_F(FrameRendererTest, RotatedBeamMovesInTheImage) {
  FrameRenderer renderer(*gc_, info_, field_style());
  ASSERT_TRUE(renderer.ok()) << renderer.error();
  const std::string p0 = test::out_dir() + "/rotation_0deg.png";
  const std::string p90 = test::out_dir() + "/rotation_90deg.png";
  std::string err;
  ASSERT_TRUE(renderer.render_png(test::hub_beam_frame(info_, 0.0, 0.0, 0.0), p0, &err)) << err;
  ASSERT_TRUE(renderer.render_png(test::hub_beam_frame(info_, std::numbers::pi / 2, 0.0, 0.5), p90, &err))
      << err;
  const test::Image a = test::read_png(p0), b = test::read_png(p90);
  const Camera cam = renderer.camera();
  EXPECT_EQ(beam_hits(a, cam, 0.0), 20);
  EXPECT_EQ(beam_hits(a, cam, std::numbers::pi / 2), 0);
  EXPECT_EQ(beam_hits(b, cam, 0.0), 0) << "beam still drawn along +x after a 90° rotation";
  EXPECT_EQ(beam_hits(b, cam, std::numbers::pi / 2), 20) << "beam not drawn along +y";
  int total = 0;
  EXPECT_EQ(clear_hits(b, cam, std::numbers::pi / 2, &total), total);
}

TEST_F(FrameRendererTest, FieldColoursBeamAndShowsColourBarAndText) {
  FrameRenderer renderer(*gc_, info_, field_style());
  const std::string path = test::out_dir() + "/field_and_overlay.png";
  std::string err;
  ASSERT_TRUE(renderer.render_png(test::hub_beam_frame(info_, 0.3, 0.05, 1.25, 0.5), path, &err))
      << err;
  const test::Image img = test::read_png(path);
  const Camera cam = renderer.camera();
  // root (strain 1e-3 -> warm) and tip (0 -> cool) differ in colour: red vs blue dominance
  auto px_at = [&](double r) {
    const double a = 0.3;
    const double v = 0.05 * std::pow((r - test::kHubRadius) / test::kBeamLength, 2);
    return test::to_pixel(cam, img.width, img.height, r * std::cos(a) - v * std::sin(a),
                          r * std::sin(a) + v * std::cos(a));
  };
  const auto root = px_at(0.15), tip = px_at(1.75);
  const auto& cr = img.at(root[0], root[1]);
  const auto& ct = img.at(tip[0], tip[1]);
  EXPECT_GT(int(cr[0]) - int(cr[2]), 60) << "root not warm";
  EXPECT_GT(int(ct[2]) - int(ct[0]), 60) << "tip not cool";
  // automatic range: round numbers around [0, 1e-3]
  EXPECT_DOUBLE_EQ(renderer.color_range()[0], 0.0);
  EXPECT_NEAR(renderer.color_range()[1], 1e-3, 1e-15);

  // colour bar in the right margin: both ends of the map present
  int warm = 0, cool = 0;
  for (int r = 0; r < img.height; ++r)
    for (int c = static_cast<int>(0.8 * img.width); c < img.width; ++c) {
      const auto& p = img.at(c, r);
      warm += p[0] > 150 && p[2] < 80;
      cool += p[2] > 150 && p[0] < 100;
    }
  EXPECT_GT(warm, 200);
  EXPECT_GT(cool, 200);
  // text in the top-left corner: dark glyph pixels
  int dark = 0;
  for (int r = 0; r < img.height / 8; ++r)
    for (int c = 0; c < img.width / 3; ++c) {
      const auto& p = img.at(c, r);
      dark += p[0] < 80 && p[1] < 80 && p[2] < 80;
    }
  EXPECT_GT(dark, 300) << "no title/time overlay";
}

TEST_F(FrameRendererTest, ColourBarTitleTooLongForTheTopLineGivesWayToTheFieldName) {
  // a stress field's label is a one-line description; right-aligned on the title's line it would
  // run into the scene title: the field's name stands there instead
  for (Quantity& q : info_.fields)
    if (q.name == "axial_strain")
      q.label = "axial strain of the beam's neutral axis, the largest over the cross-section's stations (a long "
                "description of the kind results.h5 keeps for a reader)";
  FrameRenderer renderer(*gc_, info_, field_style());
  ASSERT_TRUE(renderer.ok()) << renderer.error();
  const std::string path = test::out_dir() + "/long_field_label.png";
  std::string err;
  ASSERT_TRUE(renderer.render_png(test::hub_beam_frame(info_, 0.3, 0.05, 1.25, 0.5), path, &err)) << err;
  const test::Image img = test::read_png(path);
  // the top line between the title (about a third of the width) and the bar title's column
  int dark = 0;
  for (int r = 0; r < img.height / 20; ++r)
    for (int c = static_cast<int>(0.45 * img.width); c < static_cast<int>(0.75 * img.width); ++c) {
      const auto& p = img.at(c, r);
      dark += p[0] < 80 && p[1] < 80 && p[2] < 80;
    }
  EXPECT_EQ(dark, 0) << "the colour-bar title runs across the top line";
  // and the name is drawn at the top right
  int named = 0;
  for (int r = 0; r < img.height / 20; ++r)
    for (int c = static_cast<int>(0.8 * img.width); c < img.width; ++c) {
      const auto& p = img.at(c, r);
      named += p[0] < 80 && p[1] < 80 && p[2] < 80;
    }
  EXPECT_GT(named, 30) << "no colour-bar title";
}

TEST_F(FrameRendererTest, DeformationScaleMagnifiesElasticPartOnly) {
  FrameStyle s1 = field_style(), s5 = field_style();
  s5.deformation_scale = 5.0;
  FrameRenderer r1(*gc_, info_, s1), r5(*gc_, info_, s5);
  const Frame f = test::hub_beam_frame(info_, 0.0, 0.06, 2.0);
  const std::string p1 = test::out_dir() + "/deformation_x1.png";
  const std::string p5 = test::out_dir() + "/deformation_x5.png";
  std::string err;
  ASSERT_TRUE(r1.render_png(f, p1, &err)) << err;
  ASSERT_TRUE(r5.render_png(f, p5, &err)) << err;
  const test::Image a = test::read_png(p1), b = test::read_png(p5);
  const Camera cam = r1.camera();
  // tip drawn at y = 0.06 (x1) and 0.30 (x5)
  const double tip_x = test::kHubRadius + test::kBeamLength - 0.05;
  const auto near_tip5 = test::to_pixel(cam, a.width, a.height, tip_x, 5 * 0.06 * 0.945);
  const auto near_tip1 = test::to_pixel(cam, a.width, a.height, tip_x, 0.06 * 0.945);
  EXPECT_TRUE(is_background(a.at(near_tip5[0], near_tip5[1])));
  EXPECT_TRUE(is_ink(b.at(near_tip5[0], near_tip5[1])));
  EXPECT_TRUE(is_ink(a.at(near_tip1[0], near_tip1[1])));
  // the ghost (undeformed, rigidly moved) beam shows along y = 0 near the tip at x5
  const auto ghost = test::to_pixel(cam, b.width, b.height, tip_x, 0.0);
  EXPECT_TRUE(any_near(b, ghost[0], ghost[1], 1, [](const auto& p) {
    return !is_background(p) && std::abs(int(p[0]) - int(p[2])) < 20;  // grey
  }));
}

TEST_F(FrameRendererTest, SameFrameGivesSameBytes) {
  FrameRenderer renderer(*gc_, info_, field_style());
  const Frame f = test::hub_beam_frame(info_, 0.7, 0.03, 0.25);
  const std::string a = test::out_dir() + "/repeat_a.png", b = test::out_dir() + "/repeat_b.png";
  std::string err;
  ASSERT_TRUE(renderer.render_png(f, a, &err)) << err;
  // a different frame in between must not leave traces
  ASSERT_TRUE(renderer.render_png(test::hub_beam_frame(info_, 2.0, 0.1, 0.5), b, &err)) << err;
  ASSERT_TRUE(renderer.render_png(f, b, &err)) << err;
  const std::string ba = test::file_bytes(a), bb = test::file_bytes(b);
  ASSERT_GT(ba.size(), 1000u);
  EXPECT_TRUE(ba == bb);
}

// A caption takes the place of the status lines (time, λ, step): the pictures of a mode animation
// state their arbitrary amplitude there, and show no time they do not have (app/mode_outputs.h)
TEST_F(FrameRendererTest, CaptionReplacesTheStatusLines) {
  FrameStyle plain = field_style();
  plain.color_min = 0.0;  // a fixed range: only the text may differ between the pictures
  plain.color_max = 1e-3;
  FrameStyle captioned = plain;
  captioned.caption = "displacement \u00d70.1, an arbitrary scale";
  FrameRenderer with_status(*gc_, info_, plain), with_caption(*gc_, info_, captioned);
  const Frame early = test::hub_beam_frame(info_, 0.3, 0.05, 1.25), late = test::hub_beam_frame(info_, 0.3, 0.05, 2.5);
  const std::string dir = test::out_dir();
  std::string err;
  ASSERT_TRUE(with_status.render_png(early, dir + "/status_early.png", &err)) << err;
  ASSERT_TRUE(with_status.render_png(late, dir + "/status_late.png", &err)) << err;
  ASSERT_TRUE(with_caption.render_png(early, dir + "/caption_early.png", &err)) << err;
  ASSERT_TRUE(with_caption.render_png(late, dir + "/caption_late.png", &err)) << err;
  EXPECT_NE(test::file_bytes(dir + "/status_early.png"), test::file_bytes(dir + "/status_late.png")) << "the time line";
  EXPECT_EQ(test::file_bytes(dir + "/caption_early.png"), test::file_bytes(dir + "/caption_late.png"))
      << "a caption shows no time";
  const test::Image s = test::read_png(dir + "/status_early.png"), c = test::read_png(dir + "/caption_early.png");
  ASSERT_EQ(s.width, c.width);
  int differ_top_left = 0, differ_elsewhere = 0;
  for (int r = 0; r < s.height; ++r)
    for (int col = 0; col < s.width; ++col) {
      if (s.at(col, r) == c.at(col, r)) continue;
      (r < s.height / 4 && col < s.width / 2 ? differ_top_left : differ_elsewhere) += 1;
    }
  EXPECT_GT(differ_top_left, 100) << "the caption is drawn under the title";
  EXPECT_EQ(differ_elsewhere, 0);
}

TEST_F(FrameRendererTest, WorkerThreadGivesSameBytesAsMainThread) {
  const Frame f = test::hub_beam_frame(info_, -2.5, 0.04, 3.0);
  const std::string main_png = test::out_dir() + "/thread_main.png";
  const std::string worker_png = test::out_dir() + "/thread_worker.png";
  std::string err;
  {
    FrameRenderer renderer(*gc_, info_, field_style());
    ASSERT_TRUE(renderer.render_png(f, main_png, &err)) << err;
  }
  bool worker_ok = false;
  std::string worker_err, worker_backend;
  std::thread worker([&] {
    auto gc = GraphicsContext::create(&worker_err);
    if (!gc) return;
    worker_backend = gc->backend();
    FrameRenderer renderer(*gc, info_, field_style());
    worker_ok = renderer.render_png(f, worker_png, &worker_err);
  });
  worker.join();
  ASSERT_TRUE(worker_ok) << worker_err;
  EXPECT_EQ(worker_backend, "egl-surfaceless");
  const std::string a = test::file_bytes(main_png), b = test::file_bytes(worker_png);
  ASSERT_GT(a.size(), 1000u);
  EXPECT_TRUE(a == b);
}

// a hemispherical shell of quads (radius 10, pole up +z) with a field varying with height
RunInfo hemisphere_run(int rings, int sectors) {
  RunInfo info;
  info.scene_name = std::string("hemisphere");
  info.fields = {{"w", "mm", "radial displacement"}};
  auto& p = info.mesh.reference_points;
  for (int i = 0; i <= rings; ++i) {
    const double phi = 0.5 * std::numbers::pi * i / rings;  // from the equator to the pole
    for (int j = 0; j < sectors; ++j) {
      const double th = 2 * std::numbers::pi * j / sectors;
      p.insert(p.end(), {10 * std::cos(phi) * std::cos(th), 10 * std::cos(phi) * std::sin(th),
                         10 * std::sin(phi)});
    }
  }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const int a = i * sectors + j, b = i * sectors + (j + 1) % sectors;
      info.mesh.quads.insert(info.mesh.quads.end(), {a, b, b + sectors, a + sectors});
    }
  return info;
}

Frame hemisphere_frame(const RunInfo& info, double squash) {
  Frame f;
  f.time = 1.0;
  f.base_points = info.mesh.reference_points;
  f.points = f.base_points;
  std::vector<double> w(info.mesh.point_count());
  for (std::size_t i = 0; i < w.size(); ++i) {
    const double z = f.base_points[3 * i + 2];
    w[i] = -squash * z / 10.0;
    f.points[3 * i + 2] = z * (1.0 - squash / 10.0);
  }
  f.fields = {w};
  return f;
}

TEST_F(FrameRendererTest, ShellIsShadedInAnIsometricView) {
  const RunInfo info = hemisphere_run(8, 24);
  FrameStyle style;
  style.color_field = "w";
  style.title = "hemisphere";
  FrameRenderer renderer(*gc_, info, style);
  ASSERT_TRUE(renderer.ok()) << renderer.error();
  const std::string path = test::out_dir() + "/hemisphere.png";
  std::string err;
  ASSERT_TRUE(renderer.render_png(hemisphere_frame(info, 2.0), path, &err)) << err;
  const test::Image img = test::read_png(path);
  const Camera cam = renderer.camera();
  // isometric: the eye is above (+z) and to the side
  EXPECT_GT(cam.position[2] - cam.focal_point[2], 0);
  // the shell covers the middle of the drawing area; the bottom corners stay empty
  const int mid_col = (img.width - 144) / 2, mid_row = img.height / 2;
  EXPECT_TRUE(is_ink(img.at(mid_col, mid_row)));
  EXPECT_TRUE(is_background(img.at(5, img.height - 5)));
  EXPECT_TRUE(is_background(img.at(img.width / 2, img.height - 5)));
  // shaded: not one flat colour over the shell
  int distinct = 0;
  std::array<std::uint8_t, 3> last{};
  for (int c = mid_col - 150; c <= mid_col + 150; c += 10) {
    const auto& p = img.at(c, mid_row);
    distinct += p != last;
    last = p;
  }
  EXPECT_GT(distinct, 10);
}

// The ghost of a shell (its base_points) is drawn beneath the body, opaque but coloured as 20 %
// grey over the background: where the moved body lies behind the ghost the body shows, where only
// the ghost is the pixel is (1 - 0.2) background + 0.2 ghost colour (top view, lit head-on), and
// the rest is background (frame_renderer.cpp, kGhostSurfaceOpacity).
TEST_F(FrameRendererTest, ShellGhostLiesBeneathTheBodyAsAFaintGrey) {
  RunInfo info;
  info.scene_name = "plate";
  auto& p = info.mesh.reference_points;
  const int nx = 8, ny = 4;  // 2 m x 1 m in the xy-plane
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) p.insert(p.end(), {2.0 * i / nx, 1.0 * j / ny, 0.0});
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i;
      info.mesh.quads.insert(info.mesh.quads.end(), {a, a + 1, a + nx + 2, a + nx + 1});
    }
  Frame f;
  f.base_points = p;
  f.points = p;
  for (std::size_t i = 0; i < f.points.size(); i += 3) f.points[i] += 0.8, f.points[i + 2] -= 0.3;  // right, behind
  FrameStyle style;
  style.fit_points = f.points;
  style.camera.view_direction = {0, 0, 1};  // from above, y up
  style.camera.view_up = {0, 1, 0};
  FrameRenderer renderer(*gc_, info, style);
  ASSERT_TRUE(renderer.ok()) << renderer.error();
  const std::string path = test::out_dir() + "/ghost_beneath.png";
  std::string err;
  ASSERT_TRUE(renderer.render_png(f, path, &err)) << err;
  const test::Image img = test::read_png(path);
  const Camera cam = renderer.camera();
  ASSERT_GT(cam.position[2] - cam.focal_point[2], 0);  // looking down on the plane
  const auto blue = [](const std::array<std::uint8_t, 3>& q) { return q[2] > q[0] + 60; };
  const auto at = [&](double x, double y) {
    const auto px = test::to_pixel(cam, img.width, img.height, x, y);
    return img.at(px[0], px[1]);
  };
  // body behind the ghost: drawn over it, untinted, the same colour as where it is alone (both
  // points mid-quad, away from the drawn edges)
  EXPECT_TRUE(blue(at(2.425, 0.375)));
  EXPECT_EQ(at(1.425, 0.375), at(2.425, 0.375));
  const auto ghost = at(0.4, 0.375);  // ghost alone
  const double expected[3] = {255 * (0.8 + 0.2 * 0.74), 255 * (0.8 + 0.2 * 0.74), 255 * (0.8 + 0.2 * 0.76)};
  for (int c = 0; c < 3; ++c) { EXPECT_NEAR(ghost[c], expected[c], 6.0) << "channel " << c; }
  EXPECT_TRUE(is_background(at(1.4, 1.3)));  // above both
}

// a flat square plate [-1, 1]^2 in z = 0, fine enough that no element edges are drawn
RunInfo square_plate_run(int cells) {
  RunInfo info;
  info.scene_name = "square plate";
  auto& p = info.mesh.reference_points;
  for (int j = 0; j <= cells; ++j)
    for (int i = 0; i <= cells; ++i) p.insert(p.end(), {2.0 * i / cells - 1, 2.0 * j / cells - 1, 0.0});
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i) {
      const int a = j * (cells + 1) + i;
      info.mesh.quads.insert(info.mesh.quads.end(), {a, a + 1, a + cells + 2, a + cells + 1});
    }
  return info;
}

// points turned by angle_deg about the x axis (axis 0) or the y axis (axis 1)
std::vector<double> turned(std::vector<double> p, int axis, double angle_deg) {
  const double a = angle_deg * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
  const int u = axis == 0 ? 1 : 2, v = axis == 0 ? 2 : 0;  // the plane of the rotation
  for (std::size_t i = 0; i < p.size(); i += 3) {
    const double pu = p[i + u], pv = p[i + v];
    p[i + u] = c * pu - s * pv;
    p[i + v] = s * pu + c * pv;
  }
  return p;
}

// mean luminance (Rec. 709 weights, 0..255) of the pixels that are not background
double mean_body_luminance(const test::Image& img, int* count) {
  double sum = 0;
  *count = 0;
  for (const auto& q : img.rgb) {
    if (is_background(q)) continue;
    sum += 0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2];
    ++*count;
  }
  return *count > 0 ? sum / *count : 0.0;
}

// Issue 34: strongly deformed regions were drawn very dark. The shading follows the drawn surface
// (its normals are recomputed from each frame's points, both faces lit), and a surface seen
// obliquely is not left to the ambient light: under a lone headlight a plate in the isometric
// view had half the brightness of the same plate seen face-on (measured 65 vs 125), and one
// turned 70° from the eye a third.
TEST_F(FrameRendererTest, ShadingFollowsTheDrawnSurfaceAndObliqueFacesStayLit) {
  const RunInfo flat = square_plate_run(48);
  std::string err;
  auto render = [&](const RunInfo& info, const std::vector<double>& points, std::array<double, 3> direction,
                    std::array<double, 3> up, const std::string& name) {
    FrameStyle style;
    style.show_base = false;
    style.camera.view_direction = direction;
    style.camera.view_up = up;
    style.fit_points = points;
    FrameRenderer renderer(*gc_, info, style);
    EXPECT_TRUE(renderer.ok()) << renderer.error();
    Frame f;
    f.points = points;
    const std::string path = test::out_dir() + "/shading_" + name + ".png";
    EXPECT_TRUE(renderer.render_png(f, path, &err)) << err;
    int count = 0;
    const double lum = mean_body_luminance(test::read_png(path), &count);
    EXPECT_GT(count, 20000) << name << ": the plate is not drawn";
    std::printf("%-22s mean luminance %.1f over %d px\n", name.c_str(), lum, count);
    return lum;
  };
  const std::array<double, 3> down_z{0, 0, 1}, y_up{0, 1, 0};
  const double face_on = render(flat, flat.mesh.reference_points, down_z, y_up, "face_on");
  // the same plate meshed standing (x-z plane) and drawn lying flat: its normals are the drawn ones
  RunInfo standing = flat;
  standing.mesh.reference_points = turned(flat.mesh.reference_points, 0, 90.0);
  EXPECT_NEAR(render(standing, flat.mesh.reference_points, down_z, y_up, "standing_drawn_flat"), face_on, 1.0);
  // both faces are lit alike
  EXPECT_NEAR(render(flat, flat.mesh.reference_points, {0, 0, -1}, y_up, "back_face"), face_on, 1.0);
  // the isometric view of the plate (55° from its normal)
  EXPECT_GT(render(flat, flat.mesh.reference_points, {1, -1, 1}, {0, 0, 1}, "isometric"), 0.85 * face_on);
  // turned 70° away from the eye, whichever way (the normal towards the image's bottom, top, ...)
  for (const auto& [axis, angle, name] : {std::tuple{0, 70.0, "facing_down"}, std::tuple{0, -70.0, "facing_up"},
                                          std::tuple{1, 70.0, "facing_right"}, std::tuple{1, -70.0, "facing_left"}})
    EXPECT_GT(render(flat, turned(flat.mesh.reference_points, axis, angle), down_z, y_up, name), 0.5 * face_on)
        << name;
}

// A shell folded back on itself (a crease of 170°, as in a crushed wall) is shaded as two flat
// faces: next to the crease as away from it. With normals averaged across the crease the nodes on
// it got a normal lying in the faces (the two nearly opposite normals cancel), and the row of
// elements beside the crease was shaded as if seen edge-on: a dark band.
TEST_F(FrameRendererTest, ACreaseIsShadedAsTwoFacesWithoutADarkBand) {
  const RunInfo plate = square_plate_run(16);
  Frame f;
  f.points = plate.mesh.reference_points;
  const double fold = 0.25, a = 170.0 * std::numbers::pi / 180.0;
  for (std::size_t i = 0; i < f.points.size(); i += 3)
    if (f.points[i] > fold + 1e-9) {
      const double r = f.points[i] - fold;
      f.points[i] = fold + r * std::cos(a);
      f.points[i + 2] = r * std::sin(a);  // above the unfolded half
    }
  FrameStyle style;
  style.show_base = false;
  style.camera.view_direction = {0, 0, 1};
  style.camera.view_up = {0, 1, 0};
  FrameRenderer renderer(*gc_, plate, style);
  ASSERT_TRUE(renderer.ok()) << renderer.error();
  const std::string path = test::out_dir() + "/crease.png";
  std::string err;
  ASSERT_TRUE(renderer.render_png(f, path, &err)) << err;
  const test::Image img = test::read_png(path);
  const Camera cam = renderer.camera();
  // mean luminance over x in [x0, x1], |y| < 0.8, of the folded half seen from above
  auto band = [&](double x0, double x1) {
    double sum = 0;
    int count = 0;
    const auto lo = test::to_pixel(cam, img.width, img.height, x0, 0.8), hi = test::to_pixel(cam, img.width, img.height, x1, -0.8);
    for (int r = lo[1]; r <= hi[1]; ++r)
      for (int c = lo[0]; c <= hi[0]; ++c) {
        const auto& q = img.at(c, r);
        sum += 0.2126 * q[0] + 0.7152 * q[1] + 0.0722 * q[2];
        ++count;
      }
    return sum / std::max(1, count);
  };
  const double at_crease = band(fold - 0.11, fold - 0.01), away = band(fold - 0.6, fold - 0.3);
  std::printf("luminance beside the crease %.1f, away from it %.1f\n", at_crease, away);
  EXPECT_GT(at_crease, 0.95 * away);
}

// The orientation triad (FrameStyle::show_triad) sits in the bottom-left corner, changes no pixel
// outside it, and turns with the camera: seen from above (+y up) the x arrow points right and
// the y arrow up; seen from the front (-y, z up) the z arrow points up.
TEST_F(FrameRendererTest, OrientationTriadSitsInTheBottomLeftCornerAndTurnsWithTheCamera) {
  auto render = [&](bool triad, std::array<double, 3> direction, std::array<double, 3> up, const std::string& name) {
    FrameStyle style = field_style();
    style.show_triad = triad;
    style.camera.view_direction = direction;
    style.camera.view_up = up;
    FrameRenderer renderer(*gc_, info_, style);
    EXPECT_TRUE(renderer.ok()) << renderer.error();
    std::string err;
    const std::string path = test::out_dir() + "/triad_" + name + ".png";
    EXPECT_TRUE(renderer.render_png(test::hub_beam_frame(info_, 0.3, 0.05, 1.25), path, &err)) << err;
    return test::read_png(path);
  };
  const test::Image plain = render(false, {0, 0, 1}, {0, 1, 0}, "off");
  const test::Image top = render(true, {0, 0, 1}, {0, 1, 0}, "top");
  const test::Image front = render(true, {0, -1, 0}, {0, 0, 1}, "front");
  ASSERT_EQ(plain.rgb.size(), top.rgb.size());
  // the corner square (rows from the top): margin 0.018 h, side 16 % of the smaller side
  const int w = plain.width, h = plain.height;
  const int margin = static_cast<int>(std::lround(0.018 * h)), side = static_cast<int>(std::lround(0.16 * h));
  const int left = margin, right = margin + side, bottom = h - margin, upper = h - margin - side;
  int outside_changed = 0, inside_changed = 0;
  for (int r = 0; r < h; ++r)
    for (int c = 0; c < w; ++c) {
      const bool inside = c >= left - 1 && c <= right && r >= upper - 1 && r <= bottom;
      (inside ? inside_changed : outside_changed) += plain.at(c, r) != top.at(c, r);
    }
  EXPECT_EQ(outside_changed, 0) << "the triad drew outside its corner";
  EXPECT_GT(inside_changed, 500) << "no triad drawn";
  // which way the coloured arrows point from the square's centre
  const int cc = (left + right) / 2, cr = (upper + bottom) / 2;
  auto reddish = [](const std::array<std::uint8_t, 3>& q) { return q[0] > q[1] + 60 && q[0] > q[2] + 60; };
  auto greenish = [](const std::array<std::uint8_t, 3>& q) { return q[1] > q[0] + 40 && q[1] > q[2] + 40; };
  auto bluish = [](const std::array<std::uint8_t, 3>& q) { return q[2] > q[0] + 60 && q[2] > q[1] + 40; };
  auto count = [&](const test::Image& img, auto pred, int c0, int c1, int r0, int r1) {
    int n = 0;
    for (int r = r0; r < r1; ++r)
      for (int c = c0; c < c1; ++c) n += pred(img.at(c, r));
    return n;
  };
  const int q = side / 8;  // stay clear of the shafts' overlap at the centre
  EXPECT_GT(count(top, reddish, cc + q, right, cr - q, cr + q), 30) << "x does not point right from above";
  EXPECT_EQ(count(top, reddish, left, cc - q, upper, bottom), 0);
  EXPECT_GT(count(top, greenish, cc - q, cc + q, upper, cr - q), 30) << "y does not point up from above";
  EXPECT_EQ(count(top, greenish, left, right, cr + q, bottom), 0);
  EXPECT_GT(count(front, bluish, cc - q, cc + q, upper, cr - q), 30) << "z does not point up from the front";
  EXPECT_GT(count(front, reddish, cc + q, right, cr - q, cr + q), 30) << "x does not point right from the front";
  EXPECT_EQ(count(front, bluish, left, right, cr + q, bottom), 0);
}

// Node markers (FrameRenderer::set_markers) are drawn in their colour at the nodes' drawn
// positions (deformed and scaled as the body), over the body; later sets over earlier ones; an
// empty list draws nothing; a node outside the mesh is refused and the markers stay.
TEST_F(FrameRendererTest, NodeMarkersAreDrawnAtTheNodesDrawnPositions) {
  FrameStyle style = field_style();
  style.deformation_scale = 4.0;
  const Frame f = test::hub_beam_frame(info_, 0.3, 0.05, 1.25);
  std::string err;
  const std::string plain_png = test::out_dir() + "/markers_none.png";
  {
    FrameRenderer plain(*gc_, info_, style);
    ASSERT_TRUE(plain.render_png(f, plain_png, &err)) << err;
  }
  FrameRenderer renderer(*gc_, info_, style);
  ASSERT_TRUE(renderer.set_markers({}, &err)) << err;
  const std::string empty_png = test::out_dir() + "/markers_empty.png";
  ASSERT_TRUE(renderer.render_png(f, empty_png, &err)) << err;
  EXPECT_TRUE(test::file_bytes(plain_png) == test::file_bytes(empty_png)) << "an empty marker list drew something";

  const int tip = 1 + test::kHubRim + test::kBeamPoints - 1, mid = 1 + test::kHubRim + test::kBeamPoints / 2;
  std::vector<std::int32_t> rim;
  for (int k = 1; k <= test::kHubRim; ++k) rim.push_back(k);
  rim.push_back(mid);
  const std::array<double, 3> yellow{1.0, 0.85, 0.0}, green{0.1, 0.9, 0.3};
  ASSERT_TRUE(renderer.set_markers({{rim, yellow, 6.0}, {{tip, mid}, green, 14.0}}, &err)) << err;
  ASSERT_EQ(renderer.markers().size(), 2u);
  const std::string path = test::out_dir() + "/markers.png";
  ASSERT_TRUE(renderer.render_png(f, path, &err)) << err;
  const test::Image img = test::read_png(path);
  const Camera cam = renderer.camera();
  auto drawn_at = [&](int node) {  // base + scale * (points - base), as the body is drawn
    double p[2];
    for (int k = 0; k < 2; ++k)
      p[k] = f.base_points[3 * node + k] + 4.0 * (f.points[3 * node + k] - f.base_points[3 * node + k]);
    return test::to_pixel(cam, img.width, img.height, p[0], p[1]);
  };
  auto near_colour = [](const std::array<std::uint8_t, 3>& q, const std::array<double, 3>& c) {
    for (int k = 0; k < 3; ++k)
      if (std::abs(int(q[k]) - int(std::lround(255 * c[k]))) > 1) return false;
    return true;
  };
  // the tip's drawn position (4x its deflection) carries the large green dot
  const auto t = drawn_at(tip);
  EXPECT_TRUE(near_colour(img.at(t[0], t[1]), green)) << "tip marker missing";
  // the undeformed tip position, away from the drawn one, does not
  const double undeformed_x = f.base_points[3 * tip], undeformed_y = f.base_points[3 * tip + 1];
  const auto u = test::to_pixel(cam, img.width, img.height, undeformed_x, undeformed_y);
  ASSERT_GT(std::hypot(u[0] - t[0], u[1] - t[1]), 20.0);
  EXPECT_FALSE(any_near(img, u[0], u[1], 2, [&](const auto& q) { return near_colour(q, green); }));
  // the beam's middle node is in both sets: the later (green) lies over the earlier (yellow)
  const auto m = drawn_at(mid);
  EXPECT_TRUE(near_colour(img.at(m[0], m[1]), green));
  // a hub rim node carries a small yellow dot, with a dark rim around it
  const auto r = drawn_at(1 + test::kHubRim / 4);
  EXPECT_TRUE(any_near(img, r[0], r[1], 1, [&](const auto& q) { return near_colour(q, yellow); }));
  int yellow_px = 0, green_px = 0;
  for (const auto& q : img.rgb) yellow_px += near_colour(q, yellow), green_px += near_colour(q, green);
  EXPECT_GT(green_px, 2 * 50);          // two dots of ~10 px fill diameter
  EXPECT_LT(green_px, 2 * 150);
  EXPECT_GT(yellow_px, test::kHubRim);  // the rim dots overlap each other on the small hub

  // bad input: refused with the reason, the markers kept
  EXPECT_FALSE(renderer.set_markers({{{0, 99999}, green, 8.0}}, &err));
  EXPECT_NE(err.find("99999"), std::string::npos) << err;
  EXPECT_FALSE(renderer.set_markers({{{0}, green, 0.0}}, &err));
  EXPECT_NE(err.find("size_px"), std::string::npos) << err;
  EXPECT_EQ(renderer.markers().size(), 2u);
  // removed again: the picture without markers
  ASSERT_TRUE(renderer.set_markers({}, &err));
  ASSERT_TRUE(renderer.render_png(f, empty_png, &err)) << err;
  EXPECT_TRUE(test::file_bytes(plain_png) == test::file_bytes(empty_png));
}

// A marked node of a shell shows over the surface it lies on, and over the body where the node is
// hidden behind it (a plate folded over the node).
TEST_F(FrameRendererTest, NodeMarkersShowOverTheSurface) {
  const RunInfo plate = square_plate_run(16);
  // fold the half x > 0.25 over the rest (turned 180° about the line x = 0.25, 0.2 above it)
  Frame f;
  f.points = plate.mesh.reference_points;
  for (std::size_t i = 0; i < f.points.size(); i += 3)
    if (f.points[i] > 0.25 + 1e-9) f.points[i] = 0.5 - f.points[i], f.points[i + 2] = 0.2;
  FrameStyle style;
  style.show_base = false;
  style.camera.view_direction = {0, 0, 1};
  style.camera.view_up = {0, 1, 0};
  FrameRenderer renderer(*gc_, plate, style);
  ASSERT_TRUE(renderer.ok()) << renderer.error();
  const int open_node = 2 * 17 + 2;          // (-0.75, -0.75): on the open part
  const int hidden_node = 8 * 17 + 6;        // (-0.25, 0): under the folded half (x < 0.25 beneath)
  ASSERT_NEAR(f.points[3 * hidden_node], -0.25, 1e-12);
  const std::array<double, 3> magenta{0.9, 0.1, 0.8};
  std::string err;
  ASSERT_TRUE(renderer.set_markers({{{open_node, hidden_node}, magenta, 12.0}}, &err)) << err;
  const std::string path = test::out_dir() + "/markers_over_shell.png";
  ASSERT_TRUE(renderer.render_png(f, path, &err)) << err;
  const test::Image img = test::read_png(path);
  const Camera cam = renderer.camera();
  for (int node : {open_node, hidden_node}) {
    const auto px = test::to_pixel(cam, img.width, img.height, f.points[3 * node], f.points[3 * node + 1]);
    const auto& q = img.at(px[0], px[1]);
    EXPECT_NEAR(q[0], 230, 1) << "node " << node;
    EXPECT_NEAR(q[1], 26, 1) << "node " << node;
    EXPECT_NEAR(q[2], 204, 1) << "node " << node;
  }
}

TEST_F(FrameRendererTest, AutomaticColourRangeIsKeptAndOnlyWidened) {
  FrameRenderer renderer(*gc_, info_, field_style());
  const std::string path = test::out_dir() + "/range.png";
  std::string err;
  Frame f = test::hub_beam_frame(info_, 0, 0, 0);
  auto scale_field = [&](double s) {
    Frame g = test::hub_beam_frame(info_, 0, 0, 0);
    for (double& v : g.fields[0]) v *= s;
    return g;
  };
  // a zero field first (the initial state): a provisional range from 0 (never -1..1), not kept
  ASSERT_TRUE(renderer.render_png(scale_field(0.0), path, &err)) << err;
  EXPECT_DOUBLE_EQ(renderer.color_range()[0], 0.0);
  EXPECT_DOUBLE_EQ(renderer.color_range()[1], 1.0);
  // the first varying field chooses it: [0, 1e-3]
  ASSERT_TRUE(renderer.render_png(scale_field(1.0), path, &err)) << err;
  EXPECT_NEAR(renderer.color_range()[0], 0.0, 1e-18);
  EXPECT_NEAR(renderer.color_range()[1], 1e-3, 1e-15);
  // smaller values: unchanged (no flicker)
  ASSERT_TRUE(renderer.render_png(scale_field(0.3), path, &err)) << err;
  EXPECT_NEAR(renderer.color_range()[1], 1e-3, 1e-15);
  // larger values: widened to round numbers, never saturated
  ASSERT_TRUE(renderer.render_png(scale_field(2.3), path, &err)) << err;
  EXPECT_NEAR(renderer.color_range()[0], 0.0, 1e-18);
  EXPECT_NEAR(renderer.color_range()[1], 3e-3, 1e-15);
  ASSERT_TRUE(renderer.render_png(scale_field(1.0), path, &err)) << err;
  EXPECT_NEAR(renderer.color_range()[1], 3e-3, 1e-15);

  // a range given by the caller is used as is
  FrameStyle fixed = field_style();
  fixed.color_min = -1e-3;
  fixed.color_max = 5e-4;
  FrameRenderer given(*gc_, info_, fixed);
  ASSERT_TRUE(given.render_png(scale_field(2.3), path, &err)) << err;
  EXPECT_DOUBLE_EQ(given.color_range()[0], -1e-3);
  EXPECT_DOUBLE_EQ(given.color_range()[1], 5e-4);
}

TEST_F(FrameRendererTest, BadInputIsReportedNotCrashed) {
  std::string err;
  {
    FrameStyle s = field_style();
    s.color_field = "no_such_field";
    FrameRenderer r(*gc_, info_, s);
    EXPECT_FALSE(r.ok());
    EXPECT_FALSE(r.render_png(test::hub_beam_frame(info_, 0, 0, 0), test::out_dir() + "/x.png", &err));
    EXPECT_NE(err.find("no_such_field"), std::string::npos) << err;
  }
  {
    RunInfo bad = info_;
    bad.mesh.lines.push_back(0);
    bad.mesh.lines.push_back(9999);
    FrameRenderer r(*gc_, bad, FrameStyle{});
    EXPECT_FALSE(r.ok());
  }
  FrameRenderer r(*gc_, info_, field_style());
  Frame short_frame = test::hub_beam_frame(info_, 0, 0, 0);
  short_frame.points.resize(6);
  EXPECT_FALSE(r.render_png(short_frame, test::out_dir() + "/short.png", &err));
  Frame nan_frame = test::hub_beam_frame(info_, 0, 0, 0);
  nan_frame.points[3 * 30 + 1] = std::nan("");
  EXPECT_FALSE(r.render_png(nan_frame, test::out_dir() + "/nan.png", &err));
  EXPECT_NE(err.find("non-finite"), std::string::npos) << err;
  const bool wrote = r.render_png(test::hub_beam_frame(info_, 0, 0, 0),
                                  test::out_dir() + "/no_such_dir/frame.png", &err);
  EXPECT_FALSE(wrote);
  // the path and the system's reason (frames are written by libpng, render/png_file.h)
  EXPECT_NE(err.find("no_such_dir"), std::string::npos) << err;
  EXPECT_NE(err.find(std::strerror(ENOENT)), std::string::npos) << err;
  // and the renderer keeps working afterwards
  EXPECT_TRUE(r.render_png(test::hub_beam_frame(info_, 0, 0, 0), test::out_dir() + "/after_error.png", &err))
      << err;
}

// A real VTK error (here a reader's, on a missing file) still reaches the user, prefixed
// "[vtk]", once the renderer's message filter is installed (render/vtk_messages.h).
TEST_F(FrameRendererTest, VtkErrorsReachStderr) {
  FrameRenderer r(*gc_, info_, field_style());  // installs the filter, as every run does
  ASSERT_TRUE(r.ok());
  testing::internal::CaptureStderr();
  vtkNew<vtkPNGReader> reader;
  reader->SetFileName((test::out_dir() + "/no_such_dir/missing.png").c_str());
  reader->Update();
  const std::string stderr_text = testing::internal::GetCapturedStderr();
  EXPECT_NE(stderr_text.find("[vtk]"), std::string::npos) << stderr_text;
}

}  // namespace
}  // namespace ff::render
