// What the GUI's viewport asks of FrameRenderer: a frame into memory (the same picture as the
// PNG), a click picks the mesh point drawn there, the camera turns, zooms, pans and resets.
#include <gtest/gtest.h>

#include <cmath>

#include "render/frame_renderer.h"
#include "render_test_support.h"

namespace ff::render::test {
namespace {

class ViewportInteraction : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string err;
    gc_ = GraphicsContext::create(&err);
    ASSERT_TRUE(gc_) << err;
    info_ = hub_beam_run();
    FrameStyle style;
    style.width = 480;
    style.height = 360;
    renderer_ = std::make_unique<FrameRenderer>(*gc_, info_, style);
    ASSERT_TRUE(renderer_->ok()) << renderer_->error();
  }
  void TearDown() override {
    renderer_.reset();
    gc_.reset();
  }
  std::unique_ptr<GraphicsContext> gc_;
  RunInfo info_;
  std::unique_ptr<FrameRenderer> renderer_;
};

TEST_F(ViewportInteraction, RgbMatchesThePngAndAClickPicksThePointDrawnThere) {
  const Frame f = hub_beam_frame(info_, 0.0, 0.0, 0.0);
  std::vector<unsigned char> rgb;
  std::string err;
  ASSERT_TRUE(renderer_->render_rgb(f, &rgb, &err)) << err;
  ASSERT_EQ(rgb.size(), 3u * 480 * 360);
  const std::string png = out_dir() + "/viewport_interaction.png";
  ASSERT_TRUE(renderer_->render_png(f, png, &err)) << err;
  const Image img = read_png(png);
  ASSERT_EQ(img.width, 480);
  // rgb rows run bottom up, the PNG's top down
  int mismatches = 0;
  for (int row = 0; row < 360; row += 9)
    for (int col = 0; col < 480; col += 7)
      for (int k = 0; k < 3; ++k)
        mismatches += rgb[3 * ((359 - row) * 480 + col) + k] != img.at(col, row)[k];
  EXPECT_EQ(mismatches, 0);

  // a click on the beam's middle picks a beam point near it
  const int first = 1 + kHubRim, mid = first + kBeamPoints / 2;
  const auto& ref = info_.mesh.reference_points;
  const auto px = to_pixel(renderer_->camera(), 480, 360, ref[3 * mid], ref[3 * mid + 1]);
  const int picked = renderer_->pick_point(px[0], px[1]);
  EXPECT_NEAR(picked, mid, 1) << "clicked at " << px[0] << "," << px[1];
  // the hub centre
  const auto hub = to_pixel(renderer_->camera(), 480, 360, 0.0, 0.0);
  const int h = renderer_->pick_point(hub[0], hub[1]);
  EXPECT_TRUE(h >= 0 && h < first) << h;
  // empty space far from the body: nothing
  EXPECT_EQ(renderer_->pick_point(5, 350, 10), -1);
}

TEST_F(ViewportInteraction, CameraTurnsZoomsPansAndResets) {
  const Frame f = hub_beam_frame(info_, 0.0, 0.0, 0.0);
  std::vector<unsigned char> before, after;
  std::string err;
  ASSERT_TRUE(renderer_->render_rgb(f, &before, &err)) << err;
  const Camera fitted = renderer_->current_camera();
  renderer_->zoom(2.0);
  EXPECT_NEAR(renderer_->current_camera().parallel_scale, 0.5 * fitted.parallel_scale, 1e-12);
  renderer_->orbit(30.0, 20.0);
  renderer_->pan(15.0, -10.0);
  ASSERT_TRUE(renderer_->render_rgb(f, &after, &err)) << err;
  EXPECT_NE(before, after);
  renderer_->reset_camera();
  const Camera back = renderer_->current_camera();
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(back.focal_point[k], fitted.focal_point[k], 1e-9);
    EXPECT_NEAR(back.position[k], fitted.position[k], 1e-9);
  }
  EXPECT_NEAR(back.parallel_scale, fitted.parallel_scale, 1e-12);
  ASSERT_TRUE(renderer_->render_rgb(f, &after, &err)) << err;
  EXPECT_EQ(before, after);
}

}  // namespace
}  // namespace ff::render::test
