// `flexframe compare` (issue 34, item 6): the max |Delta| it prints per probe is the largest
// difference of the two runs over their common time range (recomputed here from both results.h5
// at their shared frame times); a probe that one run lacks is named in a warning together with
// that run, and still plotted for the other; coinciding runs get labels and looks of their own.

#include <gtest/gtest.h>

#include <cmath>
#include <regex>

#include "app/io/results.h"
#include "app/plots.h"
#include "cli_support.h"

namespace ff::cli::test {
namespace {

// the bundled strip with twice the tip force and one probe more (tip_x), under a name of its own
std::string heavier_scene(const std::string& dir) {
  std::string text = read_text(scene_path("cantilever_step_load"));
  const std::string load = "total = [0.0, 0.0, 0.5]", name = "name = \"cantilever_step_load\"";
  EXPECT_NE(text.find(load), std::string::npos);
  EXPECT_NE(text.find(name), std::string::npos);
  text.replace(text.find(load), load.size(), "total = [0.0, 0.0, 1.0]");
  text.replace(text.find(name), name.size(), "name = \"cantilever_heavier\"");
  text += "\n[[probe]]\nname = \"tip_x\"\nlabel = \"tip axial displacement\"\nselect = \"nearest\"\n"
          "point = [1.0, 0.05, 0.0]\ndirection = [1.0, 0.0, 0.0]\n";
  const std::string path = dir + "/cantilever_heavier.toml";
  write_text(path, text);
  return path;
}

TEST(CliCompare, MaxDeltaOverTheCommonRangeAndAWarningForAMissingProbe) {
  const std::string dir = fresh_test_dir();
  const std::string a = dir + "/light", b = dir + "/heavy", out = dir + "/cmp";
  ProcResult r = run_flexframe({"run", "cantilever_step_load", "--set", "solver.end=0.6", "--no-frames", "--no-plots",
                                "--quiet", "--out", a},
                               dir + "/run_light");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  r = run_flexframe({"run", heavier_scene(dir), "--set", "solver.end=0.4", "--no-frames", "--no-plots", "--quiet",
                     "--out", b},
                    dir + "/run_heavy");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  r = run_flexframe({"compare", a, b, "--out", out}, dir + "/compare");
  ASSERT_EQ(r.exit_code, 0) << r.describe();

  // the expected value: both runs store frames at the same times (same dt and output_every)
  std::string err;
  const auto ra = io::ResultReader::open(a + "/results.h5", &err);
  ASSERT_TRUE(ra) << err;
  const auto rb = io::ResultReader::open(b + "/results.h5", &err);
  ASSERT_TRUE(rb) << err;
  const std::vector<double> ta = ra->times(), tb = rb->times();
  const std::vector<double> wa = ra->probe_series("tip_w"), wb = rb->probe_series("tip_w");
  ASSERT_LT(tb.size(), ta.size());
  double expected = 0.0;
  for (std::size_t i = 0; i < tb.size(); ++i) {
    ASSERT_NEAR(ta[i], tb[i], 1e-12);
    expected = std::max(expected, std::abs(wa[i] - wb[i]));
  }
  ASSERT_GT(expected, 0.0);

  std::smatch m;
  const std::regex line(R"(tip_w: max \|Delta\| = ([0-9.eE+-]+) m \(cantilever_step_load vs cantilever_heavier, )"
                        R"(x in \[0, ([0-9.eE+-]+)\]\))");
  ASSERT_TRUE(std::regex_search(r.out, m, line)) << r.out;
  EXPECT_NEAR(std::stod(m[1].str()), expected, 1e-5 * expected);
  EXPECT_NEAR(std::stod(m[2].str()), tb.back(), 1e-9);

  EXPECT_NE(r.err.find("warning: probe 'tip_x' is not in run 'cantilever_step_load'"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("probe 'tip_w' is not"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_regular_file(out + "/plots/tip_x.png")) << "the probe of one run is still plotted";
  const auto png = ff::render::test::read_png(out + "/plots/tip_w.png");
  EXPECT_GT(png.width, 100);
}

// two runs of one scene with identical curves: labelled by their folders (not twice the scene's
// name), max |Delta| 0, and the first run's colour still visible under the second's dashes
TEST(CliCompare, IdenticalRunsOfOneSceneStayDistinguishable) {
  const std::string dir = fresh_test_dir();
  const std::string a = dir + "/first", b = dir + "/second", out = dir + "/cmp";
  for (const std::string& o : {a, b}) {
    const ProcResult r = run_flexframe({"run", "cantilever_step_load", "--set", "solver.end=0.3", "--no-frames",
                                        "--no-plots", "--quiet", "--out", o},
                                       o + "_run");
    ASSERT_EQ(r.exit_code, 0) << r.describe();
  }
  const ProcResult r = run_flexframe({"compare", a, b, "--out", out}, dir + "/compare");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.out.find("tip_w: max |Delta| = 0 m (" + a + " vs " + b), std::string::npos) << r.out;
  EXPECT_EQ(r.err.find("warning: probe"), std::string::npos) << r.err;
  const auto png = ff::render::test::read_png(out + "/plots/tip_w.png");
  int first = 0, second = 0;  // the palette's first two colours (render/plot.cpp)
  for (const auto& p : png.rgb) {
    first += std::abs(p[0] - 31) < 30 && std::abs(p[1] - 119) < 30 && std::abs(p[2] - 180) < 30;
    second += std::abs(p[0] - 227) < 30 && std::abs(p[1] - 107) < 30 && std::abs(p[2] - 14) < 30;
  }
  EXPECT_GT(first, 200) << "the first run is hidden under the second";
  EXPECT_GT(second, 200);
}

// each run's metrics with their error bars (results.h5's `error_bars`), and a verdict per pair:
// the clamped plate at 8 x 8 and 16 x 16 differ by less than their two bars together (both are
// estimates of one converged answer); the 16 x 16 plate under twice the pressure differs by far
// more; runs without bars say so instead of a verdict
TEST(CliCompare, MetricsAreComparedAgainstTheirErrorBars) {
  const std::string dir = fresh_test_dir();
  const std::string coarse = dir + "/p8", fine = dir + "/p16", heavy = dir + "/p16_heavy", plain = dir + "/plain";
  auto run = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {"run", "clamped_plate_pressure", "--no-frames", "--no-plots", "--quiet", "--out", out};
    args.insert(args.end(), extra.begin(), extra.end());
    const ProcResult r = run_flexframe(args, out + "_run");
    ASSERT_EQ(r.exit_code, 0) << r.describe();
  };
  run(coarse, {"--error-bar", "two"});
  run(fine, {"--error-bar", "two", "--set", "part[0].n1=16", "part[0].n2=16"});
  run(heavy, {"--error-bar", "two", "--set", "part[0].n1=16", "part[0].n2=16", "load[0].pressure=2000"});
  run(plain, {"--error-bar", "off"});
  const ProcResult r = run_flexframe({"compare", coarse, fine, heavy, "--out", dir + "/cmp"}, dir + "/compare");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const std::size_t at = r.out.find(fine + ": 6.58");
  ASSERT_NE(at, std::string::npos) << r.out;
  const std::string fine_line = r.out.substr(at, r.out.find('\n', at) - at);
  EXPECT_NE(fine_line.find(" ± "), std::string::npos) << fine_line;
  EXPECT_NE(fine_line.find("within the two bars together"), std::string::npos) << fine_line;
  EXPECT_NE(r.out.find(heavy + ": 0.0001"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("differs by more than the two bars together"), std::string::npos) << r.out;
  const ProcResult none = run_flexframe({"compare", coarse, plain, "--out", dir + "/cmp_plain"}, dir + "/compare_plain");
  ASSERT_EQ(none.exit_code, 0) << none.describe();
  EXPECT_NE(none.out.find("no verdict: " + plain + " has no bar"), std::string::npos) << none.out;
}

// the error band along a run's curve from a coarser twin (richardson_bands): run y = x, twin
// y = x + 0.3 at ratio 2 give E = 0.1 and the band y +- 0.3, only where the twin has samples; a
// path whose x goes back gets none
TEST(CompareDelta, RichardsonBandsFromATwin) {
  app::LabelledRun run, twin;
  run.info.probes = {{"w", "m", "w"}};
  twin.info.probes = run.info.probes;
  for (int i = 0; i <= 10; ++i) {
    run.history.time.push_back(0.1 * i);
    run.history.probes.resize(1);
    run.history.probes[0].push_back(0.1 * i);
  }
  for (int i = 0; i <= 4; ++i) {  // the twin to x = 0.8 only, on a grid of its own
    twin.history.time.push_back(0.2 * i);
    twin.history.probes.resize(1);
    twin.history.probes[0].push_back(0.2 * i + 0.3);
  }
  const std::vector<app::ProbeBand> bands = app::richardson_bands(run, twin, 2.0, "band");
  ASSERT_EQ(bands.size(), 1u);
  const app::ProbeBand& b = bands[0];
  EXPECT_EQ(b.probe, "w");
  ASSERT_EQ(b.x.size(), 9u) << "x = 0 .. 0.8, where the twin has samples";
  for (std::size_t i = 0; i < b.x.size(); ++i) {
    EXPECT_NEAR(b.lo[i], b.x[i] - 0.3, 1e-12);
    EXPECT_NEAR(b.hi[i], b.x[i] + 0.3, 1e-12);
  }
  EXPECT_TRUE(app::richardson_bands(run, twin, 1.0, "band").empty()) << "no coarser level, no band";
  run.history.time[5] = 0.1;  // the x goes back
  EXPECT_TRUE(app::richardson_bands(run, twin, 2.0, "band").empty());
}

// the difference itself, on grids that do not line up: run b sampled at other times, over a
// shorter range; y = x and y = 2x differ most (by the end of the common range) at x = 1.5
TEST(CompareDelta, InterpolatesOverTheCommonRangeOnly) {
  const std::vector<double> xa = {0.0, 1.0, 2.0, 3.0}, ya = {0.0, 1.0, 2.0, 3.0};
  const std::vector<double> xb = {0.5, 1.5}, yb = {1.0, 3.0};
  double lo = NAN, hi = NAN;
  EXPECT_DOUBLE_EQ(app::max_abs_difference(xa, ya, xb, yb, &lo, &hi), 1.5);
  EXPECT_DOUBLE_EQ(lo, 0.5);
  EXPECT_DOUBLE_EQ(hi, 1.5);
  EXPECT_DOUBLE_EQ(app::max_abs_difference(xb, yb, xa, ya), 1.5);  // symmetric
  // a load that goes back (an x that decreases) has no single y per x; disjoint ranges have none
  EXPECT_TRUE(std::isnan(app::max_abs_difference({0.0, 1.0, 0.5}, {0.0, 1.0, 2.0}, xa, ya)));
  EXPECT_TRUE(std::isnan(app::max_abs_difference({5.0, 6.0}, {0.0, 1.0}, xa, ya)));
}

}  // namespace
}  // namespace ff::cli::test
