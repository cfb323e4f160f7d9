// The frames show the beam: a short EFG run rendered at 320x240 every 5th step. The hub sits
// near the image centre (the colour bar strip on the right shifts it a little left) and the
// undeformed beam extends right along +x, so the centre row's right half is drawn; the left
// side away from the title is background. The plots folder is filled too.

#include <gtest/gtest.h>

#include "cli_support.h"

namespace ff::cli::test {
namespace {

constexpr int kWidth = 320, kHeight = 240;

bool is_background(const std::array<std::uint8_t, 3>& p) { return p[0] >= 245 && p[1] >= 245 && p[2] >= 245; }

/// Pixels in [x0, x1) x [y0, y1) (top row = 0) that are not background.
int drawn_pixels(const Image& img, int x0, int x1, int y0, int y1) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) n += !is_background(img.at(x, y));
  return n;
}

/// Two PNGs pixel for pixel equal (a run's frame and replay's drawing of it).
void expect_same_picture(const std::string& run_png, const std::string& replay_png) {
  const std::string name = fs::path(run_png).filename().string();
  const Image a = read_png(run_png), b = read_png(replay_png);
  ASSERT_EQ(a.rgb.size(), b.rgb.size()) << name;
  EXPECT_TRUE(a.rgb == b.rgb) << name << " differs between run and replay";
}

/// The body is in view in a frame at kWidth x kHeight: nothing drawn on the picture's left, bottom
/// or right edge of the 3D view (the colour bar's strip, the right 15 %, and the text at the top
/// left aside), nor on its top edge right of the text when `top` is asked for.
void expect_body_in_view(const std::string& path, bool top) {
  const std::string name = fs::path(path).filename().string();
  const Image img = read_png(path);
  ASSERT_EQ(img.width, kWidth) << name;
  const int view_right = kWidth - static_cast<int>(std::lround(0.15 * kWidth));
  EXPECT_EQ(drawn_pixels(img, 0, 2, kHeight / 6, kHeight), 0) << name << ": the body leaves the view on the left";
  EXPECT_EQ(drawn_pixels(img, 0, view_right, kHeight - 2, kHeight), 0) << name << ": the body leaves the view below";
  EXPECT_EQ(drawn_pixels(img, view_right - 2, view_right, kHeight / 6, kHeight), 0)
      << name << ": the body leaves the view on the right";
  if (top) { EXPECT_EQ(drawn_pixels(img, kWidth / 3, view_right, 0, 2), 0) << name << ": the body leaves the view above"; }
}

TEST(CliFrames, FramesShowTheBeamAndPlotsAreWritten) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  const ProcResult r = run_flexframe({"run", "hub_beam_efg_tau1", "--out", out, "--quiet", "--set", "solver.end=0.5",
                                      "--frame-every", "5", "--width", std::to_string(kWidth), "--height",
                                      std::to_string(kHeight)},
                                     dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.describe();

  // 11 frames (t = 0, 0.05, ..., 0.5), every 5th rendered: 0, 5, 10
  for (int i = 0; i < 3; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "/frames/frame_%05d.png", i);
    EXPECT_TRUE(fs::is_regular_file(out + name)) << name;
  }
  EXPECT_FALSE(fs::exists(out + "/frames/frame_00003.png"));
  std::string err;
  const std::optional<Json> s = read_summary(out, &err);
  ASSERT_TRUE(s) << err;
  const Json* outputs = s->get("outputs");
  ASSERT_TRUE(outputs);
  ASSERT_TRUE(outputs->get("frames"));
  EXPECT_EQ(outputs->get("frames")->number, 3);

  const Image img = read_png(out + "/frames/frame_00000.png");
  ASSERT_EQ(img.width, kWidth);
  ASSERT_EQ(img.height, kHeight);
  // the beam: along the centre row (+-3 px), from the image centre to 70 % of the width, most
  // columns carry a drawn pixel
  int columns = 0, drawn_columns = 0;
  for (int x = kWidth / 2; x < kWidth * 7 / 10; ++x, ++columns)
    drawn_columns += drawn_pixels(img, x, x + 1, kHeight / 2 - 3, kHeight / 2 + 4) > 0;
  EXPECT_GE(drawn_columns, columns * 9 / 10) << drawn_columns << " of " << columns << " columns show the beam";
  // a wider band above and below the beam (away from the colour bar) is empty at t = 0
  EXPECT_EQ(drawn_pixels(img, kWidth / 2, kWidth * 7 / 10, kHeight / 4, kHeight / 2 - 10), 0);
  EXPECT_EQ(drawn_pixels(img, kWidth / 2, kWidth * 7 / 10, kHeight / 2 + 10, kHeight * 3 / 4), 0);
  // background: the top-left quarter below the title and the time line, the bottom-left region
  EXPECT_EQ(drawn_pixels(img, 0, kWidth * 7 / 20, kHeight / 5, kHeight / 2 - 10), 0)
      << "top-left quarter is not background";
  EXPECT_EQ(drawn_pixels(img, 0, kWidth * 7 / 20, kHeight * 3 / 5, kHeight), 0) << "bottom-left is not background";
  // the title is drawn (top-left corner)
  EXPECT_GT(drawn_pixels(img, 0, kWidth / 2, 0, kHeight / 10), 0) << "no title";

  // the last frame (t = 0.5 s) shows the beam too, bent but still right of the hub
  const Image last = read_png(out + "/frames/frame_00002.png");
  ASSERT_EQ(last.width, kWidth);
  EXPECT_GT(drawn_pixels(last, kWidth / 2, kWidth * 7 / 10, kHeight / 4, kHeight * 3 / 4), 0);

  // plots
  const Json* plots = outputs->get("plots");
  ASSERT_TRUE(plots && plots->kind == Json::Kind::array);
  std::vector<std::string> listed;
  for (const Json& p : plots->array) listed.push_back(p.string);
  for (const char* p : {"hub_angle", "hub_rate", "tip_transverse", "tip_axial", "energy"}) {
    const std::string rel = std::string("plots/") + p + ".png";
    EXPECT_TRUE(fs::is_regular_file(out + "/" + rel)) << rel;
    EXPECT_NE(std::find(listed.begin(), listed.end(), rel), listed.end()) << rel << " not in summary.json";
  }
  for (const std::string& rel : listed) {
    ASSERT_TRUE(fs::is_regular_file(out + "/" + rel)) << rel;
    const Image plot = read_png(out + "/" + rel);
    EXPECT_GT(plot.width, 0) << rel << " is not a PNG";
    EXPECT_GT(drawn_pixels(plot, 0, plot.width, 0, plot.height), 0) << rel << " is blank";
  }
}

// Item 3 and 4 of issue 34: the frames of `run` share one colour range (a magnitude's from 0) and
// a camera that holds the whole motion, and replay draws the same stored frames identically.
// The double pendulum on coarse shells, with the scene's hand-set view replaced by the fit
// (view_radius = 0): by t = 1.2 s the shells swing out of a view fitted to their initial position
// (the camera before issue 34), on the left.
TEST(CliFrames, RunFramesShareOneRangeAndHoldTheFallingBodyAsReplayDraws) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  const ProcResult r = run_flexframe(
      {"run", "double_pendulum_shells", "--out", out, "--quiet", "--no-plots", "--set", "solver.end=1.5", "--set",
       "output.view_radius=0", "--set", "output.view_center=[]", "--set", "part[0].n1=8", "--set", "part[0].n2=8",
       "--set", "part[1].n1=8", "--set", "part[1].n2=8", "--frame-every", "10", "--width", std::to_string(kWidth),
       "--height", std::to_string(kHeight)},
      dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  std::string err;
  const std::optional<Json> s = read_summary(out, &err);
  ASSERT_TRUE(s) << err;
  const Json* render = s->get("render");
  ASSERT_TRUE(render && render->get("color_range")) << "summary.json has no render.color_range";
  const Json& range = *render->get("color_range");
  ASSERT_EQ(range.array.size(), 2u);
  // |u| is a magnitude: its range starts at 0 (at t = 0 it is all zero; never -1..1), and the
  // shells swing over metres in 1.5 s, so the one range reaches past 1 m
  EXPECT_EQ(range.array[0].number, 0.0);
  EXPECT_GT(range.array[1].number, 1.0);

  const std::vector<std::string> frames = pngs_in(out + "/frames");
  ASSERT_EQ(frames.size(), 16u);  // 151 stored frames (t = 0, 0.01, ..., 1.5), every 10th
  for (const std::string& path : frames) expect_body_in_view(path, false);  // the body in view in every frame

  // replay draws the stored frames with the same range and camera: the same pictures
  const ProcResult rp = run_flexframe(
      {"replay", out, "--out", dir + "/replay", "--no-plots", "--frame-every", "10", "--size",
       std::to_string(kWidth) + "x" + std::to_string(kHeight)}, dir + "/replay");
  ASSERT_EQ(rp.exit_code, 0) << rp.describe();
  ASSERT_EQ(pngs_in(dir + "/replay/frames").size(), frames.size());
  for (const std::string& path : frames) expect_same_picture(path, dir + "/replay/frames/" + fs::path(path).filename().string());
}

// The frames kept for drawing after the solve have a memory budget (--frame-memory): beyond it the
// kept ones are drawn at once and the rest as they come, in the kept frames' colour range and
// view, so a run of a huge mesh does not hold every frame in memory. Every frame is still drawn,
// and the run says so (stderr, summary.json).
TEST(CliFrames, FramesBeyondTheirMemoryBudgetAreDrawnAsTheyComeAndSaySo) {
  const std::string dir = fresh_test_dir();
  auto run = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"run", "double_pendulum_shells", "--out", dir + "/" + name, "--no-plots",
                                     "--set", "solver.end=0.3", "--set", "part[0].n1=8", "--set", "part[0].n2=8",
                                     "--set", "part[1].n1=8", "--set", "part[1].n2=8", "--frame-every", "3",
                                     "--width", "160", "--height", "120"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_flexframe(args, dir + "/" + name + "_log");
  };
  const ProcResult whole = run("whole", {});
  ASSERT_EQ(whole.exit_code, 0) << whole.describe();
  const ProcResult tight = run("tight", {"--frame-memory", "0.05"});  // a few frames of 2 x 81 points
  ASSERT_EQ(tight.exit_code, 0) << tight.describe();
  EXPECT_EQ(pngs_in(dir + "/tight/frames").size(), pngs_in(dir + "/whole/frames").size());
  EXPECT_NE(tight.err.find("beyond --frame-memory"), std::string::npos) << tight.err;
  EXPECT_EQ(whole.err.find("beyond --frame-memory"), std::string::npos) << whole.err;
  std::string err;
  const std::optional<Json> s = read_summary(dir + "/tight", &err);
  ASSERT_TRUE(s) << err;
  const Json* note = s->get("render") ? s->get("render")->get("frame_memory_note") : nullptr;
  ASSERT_TRUE(note);
  EXPECT_NE(note->string.find("drawn as they came"), std::string::npos) << note->string;
  // the kept frames' range: from 0 (a magnitude), narrower than the whole run's
  const Json& tight_range = *s->get("render")->get("color_range");
  const std::optional<Json> w = read_summary(dir + "/whole", &err);
  ASSERT_TRUE(w) << err;
  const Json& whole_range = *w->get("render")->get("color_range");
  EXPECT_EQ(tight_range.array[0].number, 0.0);
  EXPECT_LE(tight_range.array[1].number, whole_range.array[1].number);
}
// The same with the view chosen on the command line (--camera iso): run's automatic camera is
// fitted to the whole motion as replay's is (it used to be fitted to the initial body only, and
// the swinging shells left the picture), and replay with the same --camera draws the same frames.
TEST(CliFrames, RunWithACameraOptionHoldsTheMotionAsReplayDraws) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  const ProcResult r = run_flexframe(
      {"run", "double_pendulum_shells", "--out", out, "--quiet", "--no-plots", "--camera", "iso", "--set",
       "solver.end=1.5", "--set", "part[0].n1=8", "--set", "part[0].n2=8", "--set", "part[1].n1=8", "--set",
       "part[1].n2=8", "--frame-every", "30", "--width", std::to_string(kWidth), "--height", std::to_string(kHeight)},
      dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const std::vector<std::string> frames = pngs_in(out + "/frames");
  ASSERT_EQ(frames.size(), 6u);  // 151 stored frames, every 30th
  for (const std::string& path : frames) expect_body_in_view(path, true);
  const ProcResult rp = run_flexframe({"replay", out, "--out", dir + "/replay", "--no-plots", "--camera", "iso",
                                       "--frame-every", "30", "--size",
                                       std::to_string(kWidth) + "x" + std::to_string(kHeight)},
                                      dir + "/replay");
  ASSERT_EQ(rp.exit_code, 0) << rp.describe();
  ASSERT_EQ(pngs_in(dir + "/replay/frames").size(), frames.size());
  for (const std::string& path : frames) expect_same_picture(path, dir + "/replay/frames/" + fs::path(path).filename().string());
}

}  // namespace
}  // namespace ff::cli::test
