// write_plot_png: a two-series chart is written at the requested size and shows both curves.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "render/graphics_context.h"
#include "render/plot.h"
#include "render_test_support.h"

namespace ff::render {
namespace {

class PlotTest : public ::testing::Test {
 protected:
  void SetUp() override {
    unsetenv("DISPLAY");
    std::string err;
    gc_ = GraphicsContext::create(&err);
    ASSERT_NE(gc_, nullptr) << err;
  }
  std::unique_ptr<GraphicsContext> gc_;
};

PlotSpec two_series() {
  PlotSpec spec;
  spec.title = "hub angle";
  spec.x_label = "time [s]";
  spec.y_label = axis_title({"hub_angle", "deg", "hub angle"});
  PlotSeries sim{"simulation", {}, {}, false}, ref{"reference", {}, {}, true};
  for (int i = 0; i <= 200; ++i) {
    const double t = 0.075 * i;
    sim.x.push_back(t);
    sim.y.push_back(180.0 * std::sin(0.4 * t) * std::exp(-0.05 * t));
  }
  for (int i = 0; i <= 15; ++i) {
    const double t = 1.0 * i;
    ref.x.push_back(t);
    ref.y.push_back(180.0 * std::sin(0.4 * t) * std::exp(-0.05 * t) + 3.0);
  }
  spec.series = {sim, ref};
  return spec;
}

// pixels close to an RGB colour (0..1)
int count_near(const test::Image& img, double r, double g, double b, int tol) {
  int n = 0;
  for (const auto& p : img.rgb)
    n += std::abs(p[0] - int(255 * r)) <= tol && std::abs(p[1] - int(255 * g)) <= tol &&
         std::abs(p[2] - int(255 * b)) <= tol;
  return n;
}

TEST_F(PlotTest, TwoSeriesChartIsWrittenAtSizeAndNotBlank) {
  const std::string path = test::out_dir() + "/plot_two_series.png";
  std::filesystem::remove(path);
  std::string err;
  ASSERT_TRUE(write_plot_png(*gc_, two_series(), path, &err)) << err;
  const test::Image img = test::read_png(path);
  ASSERT_EQ(img.width, 900);
  ASSERT_EQ(img.height, 600);
  int ink = 0, white = 0;
  for (const auto& p : img.rgb) {
    ink += test::is_ink(p);
    white += test::is_background(p);
  }
  EXPECT_GT(ink, 2000) << "chart looks blank";
  EXPECT_GT(white, img.width * img.height / 2) << "background is not white";
  // both series drawn in their own colours (first two palette entries)
  EXPECT_GT(count_near(img, 0.122, 0.467, 0.706, 40), 300) << "first series missing";
  EXPECT_GT(count_near(img, 0.890, 0.420, 0.055, 40), 100) << "second series missing";
}

// a band (a run's error bar along its curve) is shaded under the curves in a light shade of its
// series' colour, counts in PlotDrawn, and one whose arrays disagree is refused
TEST_F(PlotTest, ABandIsShadedUnderItsSeries) {
  PlotSpec spec = two_series();
  PlotBand band{"error bar", {}, {}, {}, 0};
  for (std::size_t i = 0; i < spec.series[0].x.size(); ++i) {
    band.x.push_back(spec.series[0].x[i]);
    band.lo.push_back(spec.series[0].y[i] - 20.0);
    band.hi.push_back(spec.series[0].y[i] + 20.0);
  }
  const std::string plain = test::out_dir() + "/plot_without_band.png", shaded = test::out_dir() + "/plot_band.png";
  std::string err;
  PlotDrawn drawn;
  ASSERT_TRUE(write_plot_png(*gc_, spec, plain, &err, &drawn)) << err;
  EXPECT_EQ(drawn.bands, 0u);
  spec.bands = {band};
  ASSERT_TRUE(write_plot_png(*gc_, spec, shaded, &err, &drawn)) << err;
  EXPECT_EQ(drawn.bands, 1u);
  // the first palette colour (0.122, 0.467, 0.706) at a quarter over white
  const auto light = [](double c) { return 0.25 * c + 0.75; };
  const int without = count_near(test::read_png(plain), light(0.122), light(0.467), light(0.706), 12);
  const int with = count_near(test::read_png(shaded), light(0.122), light(0.467), light(0.706), 12);
  EXPECT_GT(with, 5000) << "no light shade under the first series";
  EXPECT_LT(without, with / 10);
  spec.bands[0].hi.pop_back();
  EXPECT_FALSE(write_plot_png(*gc_, spec, shaded, &err));
  EXPECT_NE(err.find("plot band 'error bar'"), std::string::npos) << err;
}

TEST_F(PlotTest, LogAxesAndCustomSize) {
  PlotSpec spec;
  spec.title = "convergence";
  spec.x_label = "iteration";
  spec.y_label = "residual norm";
  spec.log_y = true;
  spec.width = 640;
  spec.height = 480;
  PlotSeries s{"residual", {}, {}, false};
  for (int i = 0; i < 8; ++i) {
    s.x.push_back(i);
    s.y.push_back(std::pow(10.0, -2.0 * i));
  }
  s.x.push_back(8);
  s.y.push_back(0.0);  // not drawable on a log axis: left out
  spec.series = {s};
  const std::string path = test::out_dir() + "/plot_log.png";
  std::string err;
  ASSERT_TRUE(write_plot_png(*gc_, spec, path, &err)) << err;
  const test::Image img = test::read_png(path);
  ASSERT_EQ(img.width, 640);
  ASSERT_EQ(img.height, 480);
  // on the log axis the decay is a diagonal: the curve's colour appears in the upper-left and
  // lower-right quarters (a chart that ignored the log scale draws it along the top edge)
  auto curve_pixels = [&](int c0, int c1, int r0, int r1) {
    int n = 0;
    for (int r = r0; r < r1; ++r)
      for (int c = c0; c < c1; ++c) {
        const auto& p = img.at(c, r);
        n += p[2] > 120 && p[0] < 90 && p[2] - p[0] > 60;
      }
    return n;
  };
  EXPECT_GT(curve_pixels(80, 320, 60, 240), 50) << "no curve in the upper-left quarter";
  EXPECT_GT(curve_pixels(320, 630, 240, 430), 50) << "no curve in the lower-right quarter";
}

// two runs whose curves coincide: the second is dashed with markers, so the first one's colour
// still shows through its gaps (two solid lines drew only the later colour)
TEST_F(PlotTest, CoincidingCurvesStayVisibleThroughDashes) {
  PlotSpec spec = two_series();
  spec.series[1] = spec.series[0];
  spec.series[1].label = "second run";
  spec.series[1].dash = LineDash::dashed;
  spec.series[1].marker = MarkerShape::square;
  const std::string path = test::out_dir() + "/plot_coinciding.png";
  std::string err;
  PlotDrawn drawn;
  ASSERT_TRUE(write_plot_png(*gc_, spec, path, &err, &drawn)) << err;
  EXPECT_EQ(drawn.curves, 2u);
  const test::Image img = test::read_png(path);
  EXPECT_GT(count_near(img, 0.122, 0.467, 0.706, 40), 300) << "first run hidden under the second";
  EXPECT_GT(count_near(img, 0.890, 0.420, 0.055, 40), 300) << "second run missing";
}

// a fixed x range with ticks of our own (a spectrum: room beside the first and last mode number,
// whole numbers as ticks) is the range drawn
TEST_F(PlotTest, FixedXRangeIsTheRangeDrawn) {
  PlotSpec spec;
  spec.title = "spectrum";
  spec.x_label = "mode number";
  spec.y_label = "frequency [Hz]";
  spec.series.push_back({"modes", {1, 2, 3, 4}, {10, 25, 40, 90}, true});
  spec.x_min = 0.5;
  spec.x_max = 4.5;
  spec.x_ticks = {1, 2, 3, 4};
  std::string err;
  PlotDrawn drawn;
  ASSERT_TRUE(write_plot_png(*gc_, spec, test::out_dir() + "/plot_fixed_x.png", &err, &drawn)) << err;
  EXPECT_DOUBLE_EQ(drawn.x_min, 0.5);
  EXPECT_DOUBLE_EQ(drawn.x_max, 4.5);
  spec.x_min = spec.x_max = NAN;  // unset: fitted to the data
  ASSERT_TRUE(write_plot_png(*gc_, spec, test::out_dir() + "/plot_fitted_x.png", &err, &drawn)) << err;
  EXPECT_LE(drawn.x_min, 1.0);
  EXPECT_GT(drawn.x_min, 0.5);
}

// a Pareto-like chart: errors from 1e-3 % to 159 % on a log axis with six legend rows. The
// legend's headroom once ran the axis to 1e6 %; the axis now ends within a decade of the data.
TEST_F(PlotTest, LogAxisWithManySeriesIsSizedToTheData) {
  PlotSpec spec;
  spec.title = "error against wall time";
  spec.x_label = "wall time [s]";
  spec.y_label = "error [%]";
  spec.log_x = spec.log_y = true;
  const double errors[] = {159.0, 20.0, 3.0, 0.4, 0.02, 0.001};
  for (int k = 0; k < 6; ++k) {
    PlotSeries s{"dt=" + std::to_string(k), {0.1 * (k + 1)}, {errors[k]}, true};
    s.point_labels = {"v" + std::to_string(k)};
    spec.series.push_back(s);
  }
  const std::string path = test::out_dir() + "/plot_pareto_range.png";
  std::string err;
  PlotDrawn drawn;
  ASSERT_TRUE(write_plot_png(*gc_, spec, path, &err, &drawn)) << err;
  EXPECT_GE(drawn.y_max, 159.0);
  EXPECT_LT(drawn.y_max, 1590.0) << "y axis runs far above the largest error";
  EXPECT_LE(drawn.y_min, 0.001);
  EXPECT_GT(drawn.y_min, 1e-5);
  EXPECT_FALSE(drawn.legend_inside);
  EXPECT_EQ(drawn.point_labels, 6u);
  EXPECT_EQ(drawn.curves, 6u);
}

TEST_F(PlotTest, UnusableSpecsAreErrors) {
  std::string err;
  PlotSpec empty;
  EXPECT_FALSE(write_plot_png(*gc_, empty, test::out_dir() + "/plot_empty.png", &err));
  PlotSpec mismatch = two_series();
  mismatch.series[1].y.pop_back();
  EXPECT_FALSE(write_plot_png(*gc_, mismatch, test::out_dir() + "/plot_bad.png", &err));
  EXPECT_NE(err.find("reference"), std::string::npos) << err;
  PlotSpec nan_only;
  nan_only.series = {{"nan", {std::nan("")}, {1.0}, false}};
  EXPECT_FALSE(write_plot_png(*gc_, nan_only, test::out_dir() + "/plot_nan.png", &err));
}

}  // namespace
}  // namespace ff::render
