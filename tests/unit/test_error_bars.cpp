// Richardson extrapolation and the GCI (core/model/error_bars.md (R1)-(R6)) on manufactured
// sequences f(h) = f0 + C h^p (+ D h^(p+1)), whose limit and order are known exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "core/model/error_bars.h"

namespace {

double sequence(double h, double p, double higher = 0.0) { return 1.5 + 0.8 * std::pow(h, p) + higher * std::pow(h, p + 1); }

TEST(ErrorBars, RichardsonIsExactOnAPurePowerLaw) {
  // (R1) without the higher-order term: (R3) gives the run's error exactly, (R2) the limit
  for (const double p : {1.0, 2.0, 3.0})
    for (const double r : {2.0, 1.875, 1.3}) {
      const double h = 0.1, fine = sequence(h, p), coarse = sequence(r * h, p);
      const ff::SourceError e = ff::richardson("mesh", fine, coarse, r, p);
      EXPECT_NEAR(e.estimate, fine - 1.5, 1e-12 * std::abs(fine)) << "p " << p << " r " << r;
      EXPECT_NEAR(e.bar, 3.0 * std::abs(fine - 1.5), 1e-12) << "(R4) with F_s = 3";
    }
}

TEST(ErrorBars, TheEstimateCarriesTheSignOfTheRunsError) {
  // a sequence converging from below (a stiff coarse mesh: deflections too small) has f1 - f0 < 0
  const double fine = 1.0 - 0.01, coarse = 1.0 - 0.04;  // p = 2, r = 2
  const ff::SourceError e = ff::richardson("mesh", fine, coarse, 2.0, 2.0);
  EXPECT_NEAR(e.estimate, -0.01, 1e-15);
  ff::MetricError m;
  m.value = fine;
  m.sources = {e};
  EXPECT_NEAR(m.extrapolated(), 1.0, 1e-15);
  EXPECT_NEAR(m.relative_bar(), 0.03 / 0.99, 1e-15);
}

// (R9): the integrator's local error is a magnitude: it widens the bar as it stands (F_s = 1) and
// leaves the extrapolated value alone; a negative or non-finite magnitude is refused
TEST(ErrorBars, ALocalTimeErrorWidensTheBarButMovesNoValue) {
  const ff::SourceError t = ff::local_time_source(2.0, 0.03);
  EXPECT_EQ(t.source, "time");
  EXPECT_EQ(t.method, "local");
  EXPECT_EQ(t.bar, 0.03);
  EXPECT_EQ(t.estimate, 0.0);
  EXPECT_EQ(t.safety, 1.0);
  ff::MetricError m;
  m.value = 2.0;
  m.sources = {t, ff::richardson("mesh", 2.0, 2.3, 2.0, 2.0)};  // E_mesh = 0.1, GCI 0.3
  EXPECT_NEAR(m.bar(), 0.33, 1e-12);
  EXPECT_NEAR(m.extrapolated(), 2.0 - 0.1, 1e-12);
  EXPECT_THROW(ff::local_time_source(1.0, -1e-9), std::invalid_argument);
  EXPECT_THROW(ff::local_time_source(1.0, std::nan("")), std::invalid_argument);
}

TEST(ErrorBars, SourcesAddUp) {
  // (R7): estimates and bars of the mesh and the time step are summed
  ff::MetricError m;
  m.value = 2.0;
  m.sources = {ff::richardson("mesh", 2.0, 2.3, 2.0, 2.0), ff::richardson("time", 2.0, 1.94, 2.0, 2.0)};
  EXPECT_NEAR(m.estimate(), 0.1 - 0.02, 1e-14);
  EXPECT_NEAR(m.bar(), 0.3 + 0.06, 1e-14);
  EXPECT_TRUE(m.has_bar());
  m.flags.push_back("the mesh twin's path differs in kind");
  EXPECT_FALSE(m.has_bar());
}

TEST(ErrorBars, ObservedOrderOfThreeLevels) {
  // (R6): the order of a pure power law comes back, for equal and for unequal ratios
  for (const double p : {1.0, 2.0, 2.5}) {
    const double h1 = 0.05;
    for (const auto& [r21, r32] : {std::pair{2.0, 2.0}, std::pair{1.6, 2.2}}) {
      const double f1 = sequence(h1, p), f2 = sequence(r21 * h1, p), f3 = sequence(r32 * r21 * h1, p);
      const std::optional<double> q = ff::observed_order(f1, f2, f3, r21, r32);
      ASSERT_TRUE(q.has_value()) << p;
      EXPECT_NEAR(*q, p, 1e-8) << "p " << p << " r21 " << r21 << " r32 " << r32;
    }
  }
  // a higher-order term pulls the observed order off the formal one on coarse levels
  const double h = 0.4;
  const std::optional<double> q = ff::observed_order(sequence(h, 2, 5), sequence(2 * h, 2, 5), sequence(4 * h, 2, 5), 2, 2);
  ASSERT_TRUE(q.has_value());
  EXPECT_GT(std::abs(*q - 2.0), 0.3);
}

TEST(ErrorBars, OscillatoryOrFlatLevelsHaveNoOrder) {
  EXPECT_FALSE(ff::observed_order(1.0, 1.1, 1.05, 2, 2).has_value()) << "differences of opposite sign";
  EXPECT_FALSE(ff::observed_order(1.0, 1.0, 1.2, 2, 2).has_value()) << "a zero difference";
}

TEST(ErrorBars, RefusesRatiosAndOrdersThatMeanNothing) {
  EXPECT_THROW(ff::richardson("mesh", 1, 2, 1.0, 2), std::invalid_argument);
  EXPECT_THROW(ff::richardson("mesh", 1, 2, 2.0, 0.0), std::invalid_argument);
  EXPECT_THROW(ff::richardson("mesh", NAN, 2, 2.0, 2.0), std::invalid_argument);
}

}  // namespace

namespace {

TEST(ErrorBarLevels, TwoLevelsUseTheFormalOrderAndFactorThree) {
  const ff::LevelEstimate e = ff::estimate_from_levels("mesh", {1.01, 1.04}, {2.0}, 2.0);
  ASSERT_TRUE(e.error.has_value()) << e.flag;
  EXPECT_NEAR(e.error->estimate, 0.01, 1e-14);
  EXPECT_EQ(e.error->safety, 3.0);
  EXPECT_FALSE(e.error->order_observed);
}

TEST(ErrorBarLevels, ThreeLevelsInTheAsymptoticRangeUseTheObservedOrder) {
  // f = 1.5 + 0.8 h^1.5: observed 1.5 lies within [1, 4] of the formal 2, so it replaces it, with
  // F_s = 1.25 (Celik et al. 2008), and the estimate is exact
  const double h = 0.05;
  const std::vector<double> f = {sequence(h, 1.5), sequence(2 * h, 1.5), sequence(4 * h, 1.5)};
  const ff::LevelEstimate e = ff::estimate_from_levels("mesh", f, {2.0, 2.0}, 2.0);
  ASSERT_TRUE(e.error.has_value()) << e.flag;
  EXPECT_TRUE(e.error->order_observed);
  EXPECT_NEAR(e.error->order, 1.5, 1e-8);
  EXPECT_EQ(e.error->safety, 1.25);
  EXPECT_NEAR(e.error->estimate, f[0] - 1.5, 1e-10);
}

TEST(ErrorBarLevels, AnObservedOrderAboveTheFormalOneIsNotUsed) {
  // (R6a): f = 1.5 + 0.8 h^3 observes 3 (within [1, 4] of the formal 2); the extrapolation keeps
  // p = 2 with F_s = 1.25, so the estimate is (f2 - f1) / 3, larger than the true error (f1 - 1.5)
  // by (2^3 - 1) / 3: the cautious side
  const double h = 0.05;
  const std::vector<double> f = {sequence(h, 3.0), sequence(2 * h, 3.0), sequence(4 * h, 3.0)};
  const ff::LevelEstimate e = ff::estimate_from_levels("mesh", f, {2.0, 2.0}, 2.0);
  ASSERT_TRUE(e.error.has_value()) << e.flag;
  EXPECT_FALSE(e.error->order_observed);
  EXPECT_NEAR(e.error->observed_order, 3.0, 1e-8);
  EXPECT_EQ(e.error->order, 2.0);
  EXPECT_EQ(e.error->safety, 1.25);
  EXPECT_NEAR(e.error->estimate, (f[0] - 1.5) * 7.0 / 3.0, 1e-10);
}

TEST(ErrorBarLevels, ThreeLevelsOutsideTheAsymptoticRangeAreFlagged) {
  // differences that do not shrink (observed order ~0: the main job's final height at dt = 2e-3,
  // 1e-3, 5e-4, docs/validation/error-bars.md) and differences that change sign get no number
  const ff::LevelEstimate flat = ff::estimate_from_levels("time", {0.49551, 0.49674, 0.49800}, {2.0, 2.0}, 2.0);
  EXPECT_FALSE(flat.error.has_value());
  EXPECT_NE(flat.flag.find("observed time order"), std::string::npos) << flat.flag;
  const ff::LevelEstimate sign = ff::estimate_from_levels("mesh", {1.0, 1.1, 1.05}, {2.0, 2.0}, 2.0);
  EXPECT_FALSE(sign.error.has_value());
  EXPECT_NE(sign.flag.find("do not converge monotonically"), std::string::npos) << sign.flag;
  // a metric that does not depend on the discretization has no error from it
  const ff::LevelEstimate same = ff::estimate_from_levels("time", {0.0, 0.0, 0.0}, {2.0, 2.0}, 2.0);
  ASSERT_TRUE(same.error.has_value()) << same.flag;
  EXPECT_EQ(same.error->bar, 0.0);
}

}  // namespace
