// Throughput of FrameRenderer at the default 960x720 for the hub-beam (60 beam points):
// a rotating sequence, the way the app writes an animation. Prints frames per second.

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "render/frame_renderer.h"
#include "render/graphics_context.h"
#include "render_test_support.h"

namespace ff::render {
namespace {

TEST(RenderFps, HubBeamSequenceAt960x720) {
  unsetenv("DISPLAY");
  std::string err;
  auto gc = GraphicsContext::create(&err);
  ASSERT_NE(gc, nullptr) << err;
  const RunInfo info = test::hub_beam_run();
  ASSERT_EQ(test::kBeamPoints, 60);
  FrameStyle style;
  style.color_field = "axial_strain";
  style.title = "hub-beam fps";
  style.deformation_scale = 5.0;
  FrameRenderer renderer(*gc, info, style);
  ASSERT_TRUE(renderer.ok()) << renderer.error();
  const std::string dir = test::out_dir() + "/fps";
  std::filesystem::create_directories(dir);

  // the first frame pays for shader compilation; time the steady state after it
  ASSERT_TRUE(renderer.render_png(test::hub_beam_frame(info, 0, 0, 0), dir + "/warmup.png", &err)) << err;
  constexpr int frames = 40;
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < frames; ++i) {
    const double angle = std::numbers::pi * i / frames;
    char name[64];
    std::snprintf(name, sizeof name, "/frame_%03d.png", i);
    ASSERT_TRUE(renderer.render_png(test::hub_beam_frame(info, angle, 0.03 * std::sin(angle), 0.05 * i),
                                    dir + name, &err))
        << err;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double fps = frames / seconds;
  std::printf("FrameRenderer 960x720, %d beam points, %s (%s): %.1f frames/s (%.1f ms/frame, PNG included)\n",
              test::kBeamPoints, gc->backend().c_str(), gc->gl_renderer().c_str(), fps,
              1000.0 / fps);
  RecordProperty("fps", std::to_string(fps));
  // a floor far below what llvmpipe does on two cores; catches a pipeline rebuilt per frame
  EXPECT_GT(fps, 3.0);
}

}  // namespace
}  // namespace ff::render
