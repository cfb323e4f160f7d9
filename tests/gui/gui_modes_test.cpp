// The window with an eigen-analysis' modes (issue 36): the Modes list's `mode N` action animates
// mode N in the view, looping, and `mode off` returns to the run's frames. No scene builds a modal
// model on this branch yet, so the window is given the closed-form plate model
// (tests/support/plate_modes.h) through GuiOptions::simulation_for_test: this test runs itself
// again under `xvfb-run -a` as GuiModesChild.Window, which opens the window.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>

#include "app/gui/gui_app.h"
#include "tests/cli/cli_support.h"
#include "tests/support/plate_modes.h"

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
  write_text(dir + "/modes.txt",
             "run\nwait-end\n"
             "mode 2\nwait 0.3\nexport " + dir + "/mode2_a.png\n"
             "wait 0.3\nexport " + dir + "/mode2_b.png\n"
             "mode off\nexport " + dir + "/frames.png\nquit\n");
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  const std::string command = "FF_GUI_MODES_DIR='" + dir + "' timeout 60 xvfb-run -a -s '-screen 0 1280x800x24' '" + self +
                              "' --gtest_filter=GuiModesChild.Window > '" + dir + "/child.txt' 2>&1";
  const int status = std::system(command.c_str());
  const std::string log = read_text(dir + "/child.txt");
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << log;
  EXPECT_NE(log.find("mode 2: 166.6 Hz"), std::string::npos) << log;
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
  opt.new_problem = "static";
  opt.actions_file = std::string(dir) + "/modes.txt";
  opt.width = 1280;
  opt.height = 800;
  opt.quit_after = 40;
  opt.simulation_for_test = [] { return std::make_unique<ff::test::PlateModesSimulation>(true); };
  const std::atomic<bool> stop{false};
  EXPECT_EQ(app::gui::run_gui(opt, stop), 0);
}

}  // namespace
}  // namespace ff::cli::test
