// `flexframe gui` as a person (or CI) runs it: under `xvfb-run -a`, driven by an actions file
// through run / pause / set / step / probe, then a screenshot read back pixel by pixel (the body
// is in the viewport, the image is not one flat colour), the saved scene and the exported frame.
// Without a display the GUI exits at once with exit code 2 and names the headless verbs; a bad
// actions line is reported as FILE:LINE with exit code 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

#include "tests/cli/cli_support.h"

namespace ff::cli::test {
namespace {

/// Runs `program args...` (searched in PATH) with output to log files; like Child for flexframe.
ProcResult run_program(const std::vector<std::string>& argv_in, const std::string& log_prefix, double timeout_s) {
  const std::string out_file = log_prefix + ".stdout.txt", err_file = log_prefix + ".stderr.txt";
  std::vector<std::string> all = argv_in;
  std::vector<char*> argv;
  for (std::string& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const auto t0 = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    const int o = open(out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (o < 0 || e < 0) _exit(126);
    dup2(o, STDOUT_FILENO);
    dup2(e, STDERR_FILENO);
    setpgid(0, 0);  // its own group: a timeout kills xvfb-run, Xvfb and flexframe together
    execvp(argv[0], argv.data());
    _exit(127);
  }
  ProcResult r;
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() > timeout_s) {
      r.timed_out = true;
      kill(-pid, SIGKILL);
      waitpid(pid, &status, 0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) r.signal = WTERMSIG(status);
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.out = read_text(out_file);
  r.err = read_text(err_file);
  return r;
}

bool have_xvfb_run() { return std::system("command -v xvfb-run > /dev/null 2>&1") == 0; }

/// flexframe gui ARGS under a fresh virtual display.
ProcResult run_gui_under_xvfb(const std::vector<std::string>& args, const std::string& log_prefix) {
  std::vector<std::string> argv = {"xvfb-run", "-a", "-s", "-screen 0 1280x800x24", flexframe_exe(), "gui"};
  argv.insert(argv.end(), args.begin(), args.end());
  return run_program(argv, log_prefix, 60.0);
}

// the viewport: left of the 390 px side panel, above the 250 px plots and the 30 px status line
struct Region {
  int x0, y0, x1, y1;
};
constexpr std::array<std::uint8_t, 3> kViewportBackground = {247, 247, 250};  // 0.97, 0.97, 0.98

int differs(const std::array<std::uint8_t, 3>& a, const std::array<std::uint8_t, 3>& b) {
  return std::abs(a[0] - b[0]) + std::abs(a[1] - b[1]) + std::abs(a[2] - b[2]);
}

/// Checks a GUI screenshot: the viewport shows something besides its background (the body), it
/// has the background too (not covered by a panel), and the whole window is not one colour.
void expect_body_in_viewport(const Image& img, int width, int height) {
  ASSERT_EQ(img.width, width);
  ASSERT_EQ(img.height, height);
  const Region vp{0, 0, width - 390, height - 250 - 30};
  long long body = 0, background = 0, total = 0;
  for (int y = vp.y0 + 60; y < vp.y1; ++y) {     // below the title and time text
    for (int x = vp.x0; x < vp.x1 - 150; ++x) {  // left of the colour bar
      const auto& p = img.at(x, y);
      ++total;
      if (differs(p, kViewportBackground) <= 6)
        ++background;
      else if (differs(p, kViewportBackground) > 60)
        ++body;
    }
  }
  EXPECT_GT(background, total / 3) << "the viewport background is missing";
  EXPECT_GT(body, 200) << "no body drawn in the viewport (" << body << " pixels differ from the background)";
  std::set<std::array<std::uint8_t, 3>> colours;
  for (int y = 0; y < img.height && colours.size() < 50; y += 7)
    for (int x = 0; x < img.width && colours.size() < 50; x += 7) colours.insert(img.at(x, y));
  EXPECT_GT(colours.size(), 10u) << "the window is (nearly) one colour";
}

TEST(GuiCli, ScriptedSessionUnderXvfb) {
  if (!have_xvfb_run()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup installs it)";
  const std::string dir = fresh_test_dir();
  const std::string actions = dir + "/session.txt";
  write_text(actions,
             "# drive the GUI like a person would\n"
             "step 3\n"
             "run\n"
             "wait 0.2\n"
             "pause\n"
             "set solver.dt 0.02\n"
             "set torque.amplitude 7\n"
             "step 40\n"
             "probe 5\n"
             "step 5\n"
             "screenshot " + dir + "/shot.png\n"
             "export " + dir + "/frame.png\n"
             "save " + dir + "/edited.toml\n"
             "quit\n");
  const ProcResult r = run_gui_under_xvfb({"hub_beam_fem_tau1", "--actions", actions, "--width", "1280",
                                           "--height", "800", "--quit-after", "40"}, dir + "/gui");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_LT(r.wall_s, 20.0 * slowdown()) << r.describe();
  EXPECT_NE(r.out.find("session.txt:14: quit"), std::string::npos) << r.describe();
  expect_body_in_viewport(read_png(dir + "/shot.png"), 1280, 800);

  // the exported frame is the viewport alone
  const Image frame = read_png(dir + "/frame.png");
  EXPECT_EQ(frame.width, 1280 - 390);
  EXPECT_EQ(frame.height, 800 - 250 - 30);

  // the saved scene holds the edits and is valid
  const std::string saved = read_text(dir + "/edited.toml");
  EXPECT_NE(saved.find("dt = 0.02"), std::string::npos) << saved;
  EXPECT_NE(saved.find("amplitude = 7"), std::string::npos) << saved;
  const ProcResult check = run_flexframe({"check", dir + "/edited.toml"}, dir + "/check");
  EXPECT_EQ(check.exit_code, 0) << check.describe();
}

/// The value after "metric NAME = " in the window's output; NaN when absent.
double printed_metric(const std::string& out, const std::string& name) {
  const std::string tag = "metric " + name + " = ";
  const auto at = out.find(tag);
  return at == std::string::npos ? std::nan("") : std::strtod(out.c_str() + at + tag.size(), nullptr);
}

// Issue 34's acceptance: from a new problem, with actions and clicks only, a cantilever with a tip
// force is set up (a support on a patch edge picked from the list, the load moved to the other
// edge, the probe on a picked node, a metric, a material preset), run, probed by a click and
// saved; the saved file passes `check`, and its headless run gives the window's metric to the
// last digit.
TEST(GuiCli, CantileverSetUpFromNothingRerunsHeadlessToTheSameMetric) {
  if (!have_xvfb_run()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup installs it)";
  const std::string dir = fresh_test_dir();
  const std::string actions = dir + "/set_up.txt";
  write_text(actions,
             "new static\n"
             "set part[0].width 0.1\n"
             "set part[0].n1 16\n"
             "set part[0].n2 2\n"
             "add bc type=clamped select=patch_edge edge=x_min\n"
             // one edit: a load switched to patch_edge alone would sit on the clamp's edge (u=0),
             // where it does no work, and be refused (issue 48)
             "use-edge load[0] plate x_max\n"
             "set load[0].total [0.0, 0.0, 1000.0]\n"
             "set probe[0].name tip_w\n"
             "pick 33\n"  // the middle node of the free end (17 x 3 nodes, row by row)
             "use-pick probe[0]\n"
             "add metric\n"
             "preset material[0] aluminium\n"
             "run\n"
             "wait-end\n"
             "metrics\n"
             "view top\n"        // from the top the strip lies right of the view's centre (its clamped
             "click 420 250\n"   // corner is the origin, the fit's centre), whatever its deflection
             "save " + dir + "/my_cantilever.toml\n"
             "screenshot " + dir + "/shot.png\n"
             "quit\n");
  const ProcResult r = run_gui_under_xvfb({"--new", "static", "--actions", actions, "--width", "1280", "--height",
                                           "800", "--quit-after", "50"}, dir + "/gui");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const double window_tip = printed_metric(r.out, "tip_w_final");
  ASSERT_TRUE(std::isfinite(window_tip)) << r.describe();
  EXPECT_GT(window_tip, 0.3) << "a 1 kN tip force bends a 1 m aluminium strip 10 mm thick by tens of cm";
  EXPECT_NE(r.out.find("clicked node "), std::string::npos) << r.describe();
  expect_body_in_viewport(read_png(dir + "/shot.png"), 1280, 800);

  const std::string saved = read_text(dir + "/my_cantilever.toml");
  EXPECT_NE(saved.find("name = \"my_cantilever\""), std::string::npos) << saved;  // its own output folder
  EXPECT_NE(saved.find("select = \"nodes\""), std::string::npos) << saved;
  EXPECT_NE(saved.find("youngs_modulus = 7e+10"), std::string::npos) << saved;  // the aluminium preset
  const ProcResult check = run_flexframe({"check", dir + "/my_cantilever.toml"}, dir + "/check");
  EXPECT_EQ(check.exit_code, 0) << check.describe();
  const ProcResult run = run_flexframe({"run", dir + "/my_cantilever.toml", "--out", dir + "/out", "--no-frames"}, dir + "/run");
  ASSERT_EQ(run.exit_code, 0) << run.describe();
  const std::string summary = read_text(dir + "/out/summary.json");
  const auto at = summary.find("\"tip_w_final\": ");
  ASSERT_NE(at, std::string::npos) << summary;
  EXPECT_EQ(std::strtod(summary.c_str() + at + 15, nullptr), window_tip) << "the saved scene reproduces the window's run";
}

/// Compares region `r` of `actual` with the stored picture `reference`: pixels whose colour
/// differs by more than 60 (sum over R, G, B) may be at most 2 % of the region's content (the
/// pixels that are not the region's background, the colour of its top-left corner, in either
/// picture), and the mean difference over the region at most 3, so anti-aliasing and round-off
/// in the rasteriser pass and a changed layout, colour or body does not. FF_UPDATE_GUI_REFERENCES=1 stores `actual` as the reference.
void expect_like_reference(const std::string& actual, const std::string& reference, Region r) {
  if (std::getenv("FF_UPDATE_GUI_REFERENCES")) {
    std::filesystem::create_directories(std::filesystem::path(reference).parent_path());
    std::filesystem::copy_file(actual, reference, std::filesystem::copy_options::overwrite_existing);
    GTEST_SKIP() << "stored " << reference;
  }
  const Image a = read_png(actual), b = read_png(reference);
  ASSERT_GT(b.width, 0) << "no stored picture " << reference << " (FF_UPDATE_GUI_REFERENCES=1 stores one)";
  ASSERT_EQ(a.width, b.width) << actual;
  ASSERT_EQ(a.height, b.height) << actual;
  long long off = 0, total = 0, content = 0;
  double sum = 0;
  const auto background = b.at(r.x0, r.y0);
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) {
      const int d = differs(a.at(x, y), b.at(x, y));
      sum += d, ++total;
      if (d > 60) ++off;
      if (differs(a.at(x, y), background) > 6 || differs(b.at(x, y), background) > 6) ++content;
    }
  ASSERT_GT(content, 0) << reference << " is blank";
  EXPECT_LE(off, content / 50) << actual << " differs from " << reference << " in " << off << " of its " << content
                               << " content pixels";
  EXPECT_LE(sum / static_cast<double>(total), 3.0) << actual << " against " << reference;
}

// The window's pictures against stored ones (tests/gui/reference/): the 3D view of the guide's
// cantilever after its run, with its selections shown and a probe, and the set-up panel listing
// its entries. A change that moves the body, its colours, the highlights or the panel's layout
// shows here; the status line (rates, times) is left out.
TEST(GuiCli, PicturesOfTheSetUpCantileverMatchTheStoredOnes) {
  if (!have_xvfb_run()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup installs it)";
  const std::string dir = fresh_test_dir();
  const std::string actions = dir + "/pictures.txt";
  std::string script = read_text(std::string(FF_SOURCE_DIR) + "/docs/guide/gui_cantilever.actions");
  script = script.substr(0, script.find("save "));  // the set-up and the run
  write_text(actions, script + "show all\nprobe 50\nexport " + dir + "/view.png\nscreenshot " + dir +
                          "/window.png\nquit\n");
  const ProcResult r = run_gui_under_xvfb({"--new", "static", "--actions", actions, "--width", "1280", "--height",
                                           "800", "--quit-after", "50"}, dir + "/gui");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const std::string stored = std::string(FF_SOURCE_DIR) + "/tests/gui/reference/";
  expect_like_reference(dir + "/view.png", stored + "cantilever_view.png", Region{0, 0, 1280 - 390, 800 - 250 - 30});
  expect_like_reference(dir + "/window.png", stored + "cantilever_window.png", Region{1280 - 390, 0, 1280, 600});
}

/// Height over width of the box holding the pixels that are not the view's background.
double body_aspect(const Image& img) {
  int x0 = img.width, x1 = -1, y0 = img.height, y1 = -1;
  for (int y = 75; y < img.height - 80; ++y)      // below the title and its lines, above the triad
    for (int x = 120; x < img.width - 150; ++x)   // right of the triad, left of the colour bar
      if (differs(img.at(x, y), kViewportBackground) > 60)
        x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  return x1 < x0 ? 0.0 : static_cast<double>(y1 - y0 + 1) / (x1 - x0 + 1);
}

// The view buttons, scripted: a flat square plate is a square from the top and a thin line from
// the front; `view scene` returns to the scene's own view (clamped_plate_pressure: iso).
TEST(GuiCli, ViewActionsTurnTheCameraAsTheButtons) {
  if (!have_xvfb_run()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup installs it)";
  const std::string dir = fresh_test_dir();
  const std::string actions = dir + "/views.txt";
  write_text(actions, "set output.color_field none\nexport " + dir + "/scene.png\nview top\nexport " + dir +
                          "/top.png\nview front\nexport " + dir + "/front.png\nview scene\nexport " + dir +
                          "/back.png\nquit\n");
  const ProcResult r = run_gui_under_xvfb({"clamped_plate_pressure", "--actions", actions, "--width", "1280", "--height",
                                           "800", "--quit-after", "40"}, dir + "/gui");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const double top = body_aspect(read_png(dir + "/top.png")), front = body_aspect(read_png(dir + "/front.png"));
  EXPECT_NEAR(top, 1.0, 0.1) << "a square plate seen from the top";
  EXPECT_LT(front, 0.1) << "the plate seen edge-on from the front";
  const double scene = body_aspect(read_png(dir + "/scene.png")), back = body_aspect(read_png(dir + "/back.png"));
  EXPECT_GT(scene, 0.2) << "iso: neither a square nor a line";
  EXPECT_LT(scene, 0.8);
  EXPECT_NEAR(back, scene, 1e-9) << "view scene returns to the scene's view";
}

TEST(GuiCli, ShellSceneScreenshotAfterQuitAfter) {
  if (!have_xvfb_run()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup installs it)";
  const std::string dir = fresh_test_dir();
  // a coarse double pendulum, a few steps: surfaces in the viewport
  const ProcResult r = run_gui_under_xvfb(
      {"double_pendulum_shells", "--set", "part[0].n1=6", "--set", "part[0].n2=6", "--set", "part[1].n1=6",
       "--set", "part[1].n2=6", "--run", "--screenshot", dir + "/shot.png", "--quit-after", "4", "--width",
       "1280", "--height", "800"},
      dir + "/gui");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  expect_body_in_viewport(read_png(dir + "/shot.png"), 1280, 800);
}

/// The "probe node N at (x, y, z), |x - X| = d..." lines of a GUI's stdout, in order: (N, rest of the line).
std::vector<std::pair<int, std::string>> probe_readouts(const std::string& out) {
  std::vector<std::pair<int, std::string>> found;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("probe node ", 0) == 0) found.emplace_back(std::stoi(line.substr(11)), line.substr(line.find(" at ")));
  return found;
}

// `probe NODE` prints the window's node readout once the probe took effect: the node's state at
// once, while paused and after the run ended, under its own number (it used to show (0, 0, 0)
// until the next step, and after the run the previous node's values under the new name).
TEST(GuiCli, ProbeReadsTheNodesCurrentState) {
  if (!have_xvfb_run()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup installs it)";
  const std::string dir = fresh_test_dir();
  const std::string actions = dir + "/probe.txt";
  write_text(actions, "step 3\nprobe 5\nrun\nwait 3\nprobe 9\nprobe 5\nquit\n");
  const ProcResult r = run_gui_under_xvfb({"hub_beam_fem_tau1", "--set", "solver.end=0.5", "--actions", actions,
                                           "--width", "1280", "--height", "800", "--quit-after", "40"},
                                          dir + "/gui");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const auto readouts = probe_readouts(r.out);
  ASSERT_EQ(readouts.size(), 3u) << r.describe();
  EXPECT_EQ(readouts[0].first, 5);
  EXPECT_EQ(readouts[1].first, 9);
  EXPECT_EQ(readouts[2].first, 5);
  EXPECT_EQ(readouts[0].second.find("at (0, 0, 0)"), std::string::npos) << r.out;
  EXPECT_EQ(readouts[0].second.find("|x - X| = 0,"), std::string::npos) << r.out;
  EXPECT_NE(readouts[1].second, readouts[2].second) << "nodes 9 and 5 read the same after the run: " << r.out;
  EXPECT_NE(readouts[0].second, readouts[2].second) << "node 5 did not move from step 3 to the end: " << r.out;
}

/// The N of every "redraws N" line of a GUI's stdout, in order.
std::vector<long long> redraw_counts(const std::string& out) {
  std::vector<long long> counts;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);)
    if (line.rfind("redraws ", 0) == 0) counts.push_back(std::stoll(line.substr(8)));
  return counts;
}

// Idle costs nothing: a finished window with no input draws (nearly) no frames. It used to
// redraw 30 times a second (about 90 frames in these 3 s) and use a third of a core.
TEST(GuiCli, IdleFinishedWindowDoesNotRedraw) {
  if (!have_xvfb_run()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup installs it)";
  const std::string dir = fresh_test_dir();
  const std::string actions = dir + "/idle.txt";
  write_text(actions, "run\nwait 2\nredraws\nwait 3\nredraws\nscreenshot " + dir + "/shot.png\nquit\n");
  const ProcResult r = run_gui_under_xvfb({"hub_beam_fem_tau1", "--set", "solver.end=0.5", "--actions", actions,
                                           "--width", "1280", "--height", "800", "--quit-after", "40"},
                                          dir + "/gui");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const std::vector<long long> counts = redraw_counts(r.out);
  ASSERT_EQ(counts.size(), 2u) << r.describe();
  EXPECT_GT(counts[0], 0) << "the window never drew";
  EXPECT_LE(counts[1] - counts[0], 5) << "an idle window went on redrawing: " << r.describe();
  // and it still shows the finished run when asked for a picture
  expect_body_in_viewport(read_png(dir + "/shot.png"), 1280, 800);
}

// Issue 34: the probed node is marked in the viewport (a green dot none of the field colours
// comes near, gui_app.cpp kProbeMarkerColor), and the viewport carries the orientation triad in
// its bottom-left corner (x red, y green, z blue). Before any probe there is no marker.
TEST(GuiCli, ProbedNodeIsMarkedAndTheViewportHasATriad) {
  if (!have_xvfb_run()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup installs it)";
  const std::string dir = fresh_test_dir();
  const std::string actions = dir + "/probe.txt";
  write_text(actions, "step 1\nexport " + dir + "/before.png\nprobe 40\nstep 1\nexport " + dir +
                          "/after.png\nquit\n");
  const ProcResult r = run_gui_under_xvfb({"clamped_plate_pressure", "--actions", actions, "--width", "1280",
                                           "--height", "800", "--quit-after", "40"},
                                          dir + "/gui");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const Image before = read_png(dir + "/before.png"), after = read_png(dir + "/after.png");
  ASSERT_EQ(after.width, 1280 - 390);
  auto marker_green = [](const std::array<std::uint8_t, 3>& p) {
    return std::abs(p[0] - 26) <= 1 && std::abs(p[1] - 230) <= 1 && std::abs(p[2] - 77) <= 1;
  };
  long long green_before = 0, green_after = 0;
  for (const auto& p : before.rgb) green_before += marker_green(p);
  for (const auto& p : after.rgb) green_after += marker_green(p);
  EXPECT_EQ(green_before, 0) << "a probe marker before any probe";
  EXPECT_GT(green_after, 50) << "the probed node is not marked";
  EXPECT_LT(green_after, 400) << "the probe marker is one dot of 14 px";
  // the triad: its three colours in the bottom-left square (16 % of the height), none above it
  const int side = static_cast<int>(std::lround(0.16 * after.height)) + 12;
  int red = 0, green = 0, blue = 0, coloured_above = 0;
  for (int y = 0; y < after.height; ++y)
    for (int x = 0; x < side; ++x) {
      const auto& p = after.at(x, y);
      const bool r_ = p[0] > p[1] + 60 && p[0] > p[2] + 60, g_ = p[1] > p[0] + 40 && p[1] > p[2] + 40,
                 b_ = p[2] > p[0] + 60 && p[2] > p[1] + 40;
      if (y >= after.height - side)
        red += r_, green += g_, blue += b_;
      else if (y > after.height / 4)  // below the title and status text
        coloured_above += r_ || g_ || b_;
    }
  EXPECT_GT(red, 20);
  EXPECT_GT(green, 20);
  EXPECT_GT(blue, 5);  // z points at the eye in this top view: the arrow tip only
  EXPECT_EQ(coloured_above, 0);
}

TEST(GuiCli, NoDisplayExitsWithTheHeadlessVerbs) {
  const std::string dir = fresh_test_dir();
  const char* saved = std::getenv("DISPLAY");
  const std::string display = saved ? saved : "";
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  const ProcResult r = run_flexframe({"gui", "hub_beam_fem_tau1"}, dir + "/gui", "", 20.0);
  if (!display.empty()) setenv("DISPLAY", display.c_str(), 1);
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_LT(r.wall_s, 5.0) << r.describe();
  EXPECT_NE(r.err.find("needs a display"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find("flexframe run"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find("flexframe replay"), std::string::npos) << r.describe();
}

// `mode N` on a run that computed no modes (a static analysis) fails the script with why, at its line
TEST(GuiCli, ModeOfARunWithoutModesIsRefused) {
  if (!have_xvfb_run()) GTEST_SKIP() << "xvfb-run is not installed (scripts/setup installs it)";
  const std::string dir = fresh_test_dir();
  const std::string actions = dir + "/modes.txt";
  write_text(actions, "run\nwait-end\nmode 1\nquit\n");
  const ProcResult r = run_gui_under_xvfb({"clamped_plate_pressure", "--actions", actions, "--width", "800",
                                           "--height", "600", "--quit-after", "40"},
                                          dir + "/gui");
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find(actions + ":3: mode 1: the run computed no modes"), std::string::npos) << r.describe();
}

TEST(GuiCli, BadActionsLineNamesFileAndLine) {
  const std::string dir = fresh_test_dir();
  const std::string actions = dir + "/bad.txt";
  write_text(actions, "run\nwait 0.1\nstep many\nquit\n");
  const ProcResult r = run_flexframe({"gui", "hub_beam_fem_tau1", "--actions", actions}, dir + "/gui", "", 20.0);
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find(actions + ":3: 'step' takes a whole number of steps"), std::string::npos) << r.describe();

  // a key the scene does not have is caught before any window opens, at its line
  write_text(actions, "run\nset solver.dtt 0.01\n");
  const ProcResult k = run_flexframe({"gui", "hub_beam_fem_tau1", "--actions", actions}, dir + "/gui2", "", 20.0);
  EXPECT_EQ(k.exit_code, 2) << k.describe();
  EXPECT_NE(k.err.find(actions + ":2: set solver.dtt 0.01"), std::string::npos) << k.describe();
}

}  // namespace
}  // namespace ff::cli::test
