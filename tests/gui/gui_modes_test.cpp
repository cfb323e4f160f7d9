// The window with an eigen-analysis' modes (issue 36): the Modes list's `mode N` action animates
// mode N in the view, looping, and `mode off` returns to the run's frames. The window runs the
// bundled modal_cantilever_strip scene; mode 2's frequency it prints is the one a headless run of
// the same scene writes to summary.json. This test runs itself again under `xvfb-run -a` as
// GuiModesChild.Window, which opens the window.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>

#include "app/gui/gui_app.h"
#include "tests/cli/cli_support.h"
#include <nlohmann/json.hpp>

namespace ff::cli::test {
namespace {

std::size_t differing_pixels(const ff::render::test::Image& a, const ff::render::test::Image& b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < std::min(a.rgb.size(), b.rgb.size()); ++i) n += a.rgb[i] != b.rgb[i];
  return n;
}

TEST(GuiModes, ModeAnimatesInTheView) {
  if (std::system("command -v xvfb-run > /dev/null 2>&1") != 0) GTEST_SKIP() << "xvfb-run is not installed";
  const std::string dir = fresh_test_dir();
  // 0.3 s apart in a release build; an instrumented window draws far fewer frames per second
  const std::string wait = "wait " + std::to_string(0.3 * slowdown()) + "\n";
  write_text(dir + "/modes.txt",
             "run\nwait-end\n"
             "mode 2\n" + wait + "export " + dir + "/mode2_a.png\n" +
             wait + "export " + dir + "/mode2_b.png\n"
             "mode off\nexport " + dir + "/frames.png\nquit\n");
  // mode 2's frequency from a headless run of the scene the window runs
  const ProcResult headless = run_flexframe({"run", "modal_cantilever_strip", "--no-frames", "--no-plots", "--quiet",
                                             "--animate-modes", "0", "--out", dir + "/headless"},
                                            dir + "/headless", "", 120.0);
  ASSERT_EQ(headless.exit_code, 0) << headless.describe();
  const auto summary = nlohmann::json::parse(read_text(dir + "/headless/summary.json"));
  const double mode2_hz = summary.at("modes").at("modes").at(1).at("value").get<double>();
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  const std::string command = "FF_GUI_MODES_DIR='" + dir + "' timeout " + std::to_string(static_cast<int>(60 * slowdown())) + " xvfb-run -a -s '-screen 0 1280x800x24' '" + self +
                              "' --gtest_filter=GuiModesChild.Window > '" + dir + "/child.txt' 2>&1";
  const int status = std::system(command.c_str());
  const std::string log = read_text(dir + "/child.txt");
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << log;
  const auto at = log.find("mode 2: ");
  ASSERT_NE(at, std::string::npos) << log;
  EXPECT_NEAR(std::strtod(log.c_str() + at + 8, nullptr), mode2_hz, 1e-3 * mode2_hz) << log;
  const auto a = ff::render::test::read_png(dir + "/mode2_a.png"), b = ff::render::test::read_png(dir + "/mode2_b.png"),
             frames = ff::render::test::read_png(dir + "/frames.png");
  ASSERT_GT(a.width, 0) << log;
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.width, frames.width);
  EXPECT_GT(differing_pixels(a, b), 1000u) << "the animation moves on: another phase 0.3 s later";
  EXPECT_GT(differing_pixels(a, frames), 1000u) << "`mode off` shows the run's frame again";
}

// the window itself, run by GuiModes.ModeAnimatesInTheView under a virtual display
TEST(GuiModesChild, Window) {
  const char* dir = std::getenv("FF_GUI_MODES_DIR");
  if (!dir) GTEST_SKIP() << "the window of GuiModes.ModeAnimatesInTheView, which runs it under xvfb-run";
  app::gui::GuiOptions opt;
  opt.scene_path = std::string(FF_ASSET_DIR) + "/scenes/modal_cantilever_strip.toml";
  opt.actions_file = std::string(dir) + "/modes.txt";
  opt.width = 1280;
  opt.height = 800;
  opt.quit_after = 40;
  const std::atomic<bool> stop{false};
  EXPECT_EQ(app::gui::run_gui(opt, stop), 0);
}

}  // namespace
}  // namespace ff::cli::test
