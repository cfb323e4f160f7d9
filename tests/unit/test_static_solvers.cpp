// Load-control Newton and arc-length (Crisfield, Lam–Morley) on small problems with closed-form
// equilibrium paths: a cubic with two limit points, the von Mises two-bar truss (snap-through),
// the same truss behind a soft spring (snap-back), and a hardening spring that makes a full load
// step fail (cut-back). Every converged point is compared with the analytic path.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include "core/solve/static_arclength.h"
#include "core/solve/static_newton.h"

namespace ff {
namespace {

// ---------------------------------------------------------------------------------------------
// vector-space problems r(q, λ) = f_int(q) − λ f_ref
class VectorProblem : public StaticProblem {
 public:
  explicit VectorProblem(int n) : q(Eigen::VectorXd::Zero(n)), saved_(q) {}
  int size() const override { return static_cast<int>(q.size()); }
  void evaluate(double lambda, Eigen::VectorXd& r, Eigen::SparseMatrix<double>* k, Eigen::VectorXd* f) override {
    ++evaluations;
    r = internal_force(q) - lambda * load();
    if (k) {
      ++tangent_evaluations;
      *k = stiffness(q).sparseView(0.0, 0.0);
      k->makeCompressed();
    }
    if (f) *f = load();
  }
  void update(const Eigen::VectorXd& d) override { q += d; }
  void save_state() override { saved_ = q; }
  void restore_state() override {
    q = saved_;
    ++restores;
  }
  virtual Eigen::VectorXd internal_force(const Eigen::VectorXd& x) const = 0;
  virtual Eigen::MatrixXd stiffness(const Eigen::VectorXd& x) const = 0;
  virtual Eigen::VectorXd load() const = 0;

  Eigen::VectorXd q;
  int evaluations = 0, tangent_evaluations = 0, restores = 0;

 private:
  Eigen::VectorXd saved_;
};

// Lam & Morley's first example: f(x) = x³ − 57/8 x² + 51/4 x = 5λ, limit points at
// f'(x) = 3x² − 57/4 x + 51/4 = 0.
class Cubic : public VectorProblem {
 public:
  Cubic() : VectorProblem(1) {}
  static double f(double x) { return x * x * x - 57.0 / 8.0 * x * x + 51.0 / 4.0 * x; }
  static double lambda_of(double x) { return f(x) / 5.0; }
  static double limit(int which) {  // x of the first (0) and second (1) limit point
    const double b = 57.0 / 4.0, d = std::sqrt(b * b - 4.0 * 3.0 * 51.0 / 4.0);
    return (b + (which == 0 ? -d : d)) / 6.0;
  }
  Eigen::VectorXd internal_force(const Eigen::VectorXd& x) const override { return Eigen::VectorXd::Constant(1, f(x[0])); }
  Eigen::MatrixXd stiffness(const Eigen::VectorXd& x) const override {
    return Eigen::MatrixXd::Constant(1, 1, 3.0 * x[0] * x[0] - 57.0 / 4.0 * x[0] + 51.0 / 4.0);
  }
  Eigen::VectorXd load() const override { return Eigen::VectorXd::Constant(1, 5.0); }
};

// Shallow von Mises truss: bars from (∓a, 0) to the apex (u, h − w), axial stiffness EA,
// Green strain ε = (ℓ² − L0²)/(2 L0²), energy Σ ½ EA L0 ε²; downward load λP at the apex.
// Symmetric path (u = 0): λ P = EA z (h² − z²)/L0³, z = h − w, limit points at z = ±h/√3.
struct Truss {
  double a = 1.0, h = 0.1, ea = 1e4;
  double l0() const { return std::sqrt(a * a + h * h); }
  double force(double w) const {  // vertical internal force on the symmetric path
    const double z = h - w, l = l0();
    return ea * z * (h * h - z * z) / (l * l * l);
  }
  double stiffness(double w) const {  // d force / dw
    const double z = h - w, l = l0();
    return -ea * (h * h - 3.0 * z * z) / (l * l * l);
  }
  double w_limit(int which) const { return h * (1.0 + (which == 0 ? -1.0 : 1.0) / std::sqrt(3.0)); }
  double peak() const { return force(w_limit(0)); }  // the first limit load
};

class VonMises : public VectorProblem {
 public:
  VonMises() : VectorProblem(2) {}  // q = (u, w)
  Truss t;
  double p = Truss().peak();  // reference load: λ = 1 at the first limit point
  Eigen::VectorXd internal_force(const Eigen::VectorXd& x) const override {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(2);
    const double l0 = t.l0(), z = t.h - x[1];
    for (double xi : {-t.a, t.a}) {
      const double dx = x[0] - xi, eps = (dx * dx + z * z - l0 * l0) / (2 * l0 * l0);
      f += t.ea * l0 * eps * Eigen::Vector2d(dx, -z) / (l0 * l0);
    }
    return f;
  }
  Eigen::MatrixXd stiffness(const Eigen::VectorXd& x) const override {
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(2, 2);
    const double l0 = t.l0(), z = t.h - x[1];
    for (double xi : {-t.a, t.a}) {
      const double dx = x[0] - xi, eps = (dx * dx + z * z - l0 * l0) / (2 * l0 * l0);
      const Eigen::Vector2d g = Eigen::Vector2d(dx, -z) / (l0 * l0);
      k += t.ea * l0 * (g * g.transpose() + eps * Eigen::Matrix2d::Identity() / (l0 * l0));
    }
    return k;
  }
  Eigen::VectorXd load() const override { return Eigen::Vector2d(0.0, p); }
};

// The truss apex (w) loaded through a soft spring k (load point v): k(v − w) = λP = F_truss(w).
// Snap-back when k < max(−dF/dw) = EA h²/L0³: v(w) = w + F(w)/k turns back.
class SnapBack : public VectorProblem {
 public:
  SnapBack() : VectorProblem(2) {}  // q = (w, v)
  Truss t;
  double k = 30.0;
  double p = Truss().peak();
  double v_of(double w) const { return w + t.force(w) / k; }
  Eigen::VectorXd internal_force(const Eigen::VectorXd& x) const override {
    const double s = k * (x[1] - x[0]);
    return Eigen::Vector2d(t.force(x[0]) - s, s);
  }
  Eigen::MatrixXd stiffness(const Eigen::VectorXd& x) const override {
    Eigen::Matrix2d m;
    m << t.stiffness(x[0]) + k, -k, -k, k;
    return m;
  }
  Eigen::VectorXd load() const override { return Eigen::Vector2d(0.0, p); }
};

// Hardening spring f = −ln(1 − q), defined for q < 1: Newton from q = 0 with a large load step
// jumps to q > 1 (non-finite residual) and must cut back. Exact: q = 1 − e^{−λ}.
class LogSpring : public VectorProblem {
 public:
  LogSpring() : VectorProblem(1) {}
  Eigen::VectorXd internal_force(const Eigen::VectorXd& x) const override {
    return Eigen::VectorXd::Constant(1, x[0] < 1.0 ? -std::log(1.0 - x[0]) : std::numeric_limits<double>::quiet_NaN());
  }
  Eigen::MatrixXd stiffness(const Eigen::VectorXd& x) const override {
    return Eigen::MatrixXd::Constant(1, 1, 1.0 / (1.0 - x[0]));
  }
  Eigen::VectorXd load() const override { return Eigen::VectorXd::Constant(1, 1.0); }
};

struct Point {
  StaticStepInfo info;
  Eigen::VectorXd q;
};

template <class Settings>
void record_into(Settings& s, VectorProblem& p, std::vector<Point>& path) {
  s.on_step = [&p, &path](const StaticStepInfo& info) { path.push_back({info, p.q}); };
}

StaticConvergence tight() {
  StaticConvergence c;
  c.residual_tolerance = 1e-12;
  c.increment_tolerance = 1e-10;
  return c;
}

// ---------------------------------------------------------------------------------------------
TEST(LoadControl, CubicReachesFullLoadOnTheStableBranch) {
  Cubic p;
  LoadControlSettings s;
  s.convergence = tight();
  std::vector<Point> path;
  record_into(s, p, path);
  const StaticResult r = solve_load_control(p, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_EQ(r.stop, StaticStop::lambda_reached);
  EXPECT_DOUBLE_EQ(r.lambda, 1.0);
  // the root of f(x) = 5 below the first limit point, by bisection
  double lo = 0.0, hi = Cubic::limit(0);
  for (int i = 0; i < 200; ++i) (Cubic::f(0.5 * (lo + hi)) < 5.0 ? lo : hi) = 0.5 * (lo + hi);
  EXPECT_NEAR(p.q[0], lo, 1e-12);
  ASSERT_FALSE(path.empty());
  for (const Point& pt : path) {
    EXPECT_LT(pt.q[0], Cubic::limit(0));
    EXPECT_NEAR(Cubic::lambda_of(pt.q[0]), pt.info.lambda, 1e-12);
    EXPECT_LE(pt.info.iterations, 6);  // quadratic convergence
    EXPECT_TRUE(pt.info.tangent_refactored);
  }
  EXPECT_DOUBLE_EQ(path.back().info.lambda, 1.0);
  EXPECT_EQ(r.steps, static_cast<int>(path.size()));
}

// the converged points of load control on the cubic with settings s (completed, or a test failure)
std::vector<Point> cubic_path(LoadControlSettings s) {
  Cubic p;
  std::vector<Point> path;
  record_into(s, p, path);
  EXPECT_EQ(solve_load_control(p, s).status, StaticStatus::completed);
  return path;
}

TEST(LoadControl, StepsGrowAfterEasyStepsAndStayBounded) {
  LoadControlSettings s;
  s.initial_step = 0.01;
  s.max_step = 0.08;
  s.lambda_end = 0.9;
  const std::vector<Point> path = cubic_path(s);
  ASSERT_GE(path.size(), 3u);
  EXPECT_NEAR(path[0].info.dlambda, 0.01, 1e-15);
  EXPECT_NEAR(path[1].info.dlambda, 0.015, 1e-15);
  double largest = 0.0;
  for (const Point& pt : path) largest = std::max(largest, pt.info.dlambda);
  EXPECT_DOUBLE_EQ(largest, 0.08);
}

// static_solvers.md §3: a step that needed no more corrections than the one before grows even when
// it is not "easy" (the path is not getting harder); one that needed more keeps its size
TEST(LoadControl, StepsGrowWhileThePathIsNotGettingHarder) {
  LoadControlSettings s;
  s.initial_step = 0.01;
  s.max_step = 0.5;
  s.lambda_end = 0.9;
  s.easy_iterations = 0;  // only the comparison with the step before can grow a step
  s.convergence = tight();
  const std::vector<Point> path = cubic_path(s);
  ASSERT_GE(path.size(), 4u);
  int grown = 0, kept = 0;
  for (std::size_t i = 1; i + 2 < path.size(); ++i) {  // the last step may be shortened to λ_end
    const StaticStepInfo &before = path[i - 1].info, &step = path[i].info, &next = path[i + 1].info;
    ASSERT_EQ(step.attempts, 1);
    if (step.iterations <= before.iterations) {
      EXPECT_NEAR(next.dlambda, std::min(1.5 * step.dlambda, s.max_step), 1e-15) << "step " << i;
      ++grown;
    } else {
      EXPECT_NEAR(next.dlambda, step.dlambda, 1e-15) << "step " << i;
      ++kept;
    }
  }
  EXPECT_GT(grown, 0);
  EXPECT_GT(kept, 0);  // towards the limit point the cubic gets harder
}

// the loads a run reports at (a scene's at_load metrics) are converged states of the path
TEST(LoadControl, StepsLandOnStationsAndKeepTheirSize) {
  LoadControlSettings s;
  s.initial_step = s.max_step = 0.1;
  s.lambda_end = 0.9;
  s.stations = {0.37, 0.61, 2.0, -1.0};  // the last two are off the path
  s.convergence = tight();
  const std::vector<Point> path = cubic_path(s);
  std::vector<double> lambdas;
  for (const Point& pt : path) {
    lambdas.push_back(pt.info.lambda);
    EXPECT_NEAR(Cubic::lambda_of(pt.q[0]), pt.info.lambda, 1e-12);
  }
  EXPECT_NE(std::find(lambdas.begin(), lambdas.end(), 0.37), lambdas.end());
  EXPECT_NE(std::find(lambdas.begin(), lambdas.end(), 0.61), lambdas.end());
  // 0.1, 0.2, 0.3, 0.37, 0.47, 0.57, 0.61, 0.71, 0.81, 0.9: the step after a station is full size
  ASSERT_EQ(path.size(), 10u);
  EXPECT_NEAR(path[4].info.dlambda, 0.1, 1e-15);
  EXPECT_NEAR(path[7].info.dlambda, 0.1, 1e-15);
}

TEST(LoadControl, TooLargeStepIsCutBackAndRecovers) {
  LogSpring p;
  LoadControlSettings s;
  s.lambda_end = 3.0;
  s.initial_step = s.max_step = 3.0;  // the whole load at once: Newton jumps to q = 3, ln(−2)
  s.convergence = tight();
  std::vector<Point> path;
  record_into(s, p, path);
  const StaticResult r = solve_load_control(p, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_GE(r.cutbacks, 1);
  EXPECT_GE(p.restores, r.cutbacks);
  ASSERT_FALSE(path.empty());
  EXPECT_GT(path.front().info.attempts, 1);
  EXPECT_LT(path.front().info.dlambda, 3.0);
  for (const Point& pt : path) { EXPECT_NEAR(pt.q[0], 1.0 - std::exp(-pt.info.lambda), 1e-12); }
  EXPECT_DOUBLE_EQ(r.lambda, 3.0);
}

TEST(LoadControl, FailsGracefullyAtTheLimitPointOfASnapBack) {
  SnapBack p;
  LoadControlSettings s;
  s.lambda_end = 1.5;  // beyond the limit load λ = 1
  s.initial_step = 0.1;
  s.min_step = 1e-5;
  std::vector<Point> path;
  record_into(s, p, path);
  const StaticResult r = solve_load_control(p, s);
  EXPECT_EQ(r.status, StaticStatus::diverged);
  EXPECT_EQ(r.stop, StaticStop::step_too_small);
  EXPECT_NE(r.reason.find("limit point"), std::string::npos) << r.reason;
  // stopped just below the limit load, on the pre-buckling branch, state = last converged step
  EXPECT_LE(r.lambda, 1.0);
  EXPECT_GT(r.lambda, 0.99);
  ASSERT_FALSE(path.empty());
  EXPECT_DOUBLE_EQ(path.back().info.lambda, r.lambda);
  EXPECT_LT(p.q[0], p.t.w_limit(0));
  EXPECT_NEAR(p.q[1], p.v_of(p.q[0]), 1e-9);
}

TEST(LoadControl, DoesNotJumpOverTheLimitPointOfTheCubic) {
  // beyond λ = 1.354 the only equilibria lie past the second limit point (x > 3.55): Newton can
  // converge there from near the first limit point, and must refuse to
  Cubic p;
  LoadControlSettings s;
  s.lambda_end = 2.0;
  const StaticResult r = solve_load_control(p, s);
  EXPECT_EQ(r.status, StaticStatus::diverged) << r.reason;
  EXPECT_EQ(r.stop, StaticStop::step_too_small);
  EXPECT_LT(p.q[0], Cubic::limit(0));
  EXPECT_NEAR(r.lambda, Cubic::lambda_of(Cubic::limit(0)), 1e-4);
  EXPECT_NEAR(Cubic::lambda_of(p.q[0]), r.lambda, 1e-8);
  // with both guards off the same run snaps through to the far branch: the guards are what stops it
  Cubic q;
  s.hold_determinant_sign = false;
  s.max_increment_ratio = 0.0;
  const StaticResult jumped = solve_load_control(q, s);
  EXPECT_EQ(jumped.status, StaticStatus::completed);
  EXPECT_GT(q.q[0], Cubic::limit(1));
}

TEST(LoadControl, StopFlagInterruptsAtTheLastConvergedStep) {
  Cubic p;
  std::atomic<bool> stop{false};
  LoadControlSettings s;
  s.stop = &stop;
  s.initial_step = s.max_step = 0.1;
  int seen = 0;
  s.on_step = [&](const StaticStepInfo&) {
    if (++seen == 3) stop = true;
  };
  const StaticResult r = solve_load_control(p, s);
  EXPECT_EQ(r.status, StaticStatus::interrupted);
  EXPECT_EQ(r.steps, 3);
  EXPECT_NEAR(r.lambda, 0.3, 1e-14);
  EXPECT_NEAR(Cubic::lambda_of(p.q[0]), 0.3, 1e-8);
}

TEST(LoadControl, InvalidSettingsAreReported) {
  Cubic p;
  LoadControlSettings s;
  s.min_step = 0.5;  // > initial_step
  const StaticResult r = solve_load_control(p, s);
  EXPECT_EQ(r.status, StaticStatus::diverged);
  EXPECT_EQ(r.stop, StaticStop::invalid_settings);
  EXPECT_EQ(p.evaluations, 0);
}

// Eq. (4''): under full Newton the first correction of a load step takes the factorization of
// the correction that converged the step before, so only the first step factorizes at its start;
// the path is still the analytic one to the tolerance
TEST(LoadControl, FullNewtonStartsEachStepOnTheFactorizationThatConvergedTheLast) {
  Cubic p;
  LoadControlSettings s;
  s.convergence = tight();
  s.lambda_end = 0.9;
  s.initial_step = 0.1;
  std::vector<Point> path;
  record_into(s, p, path);
  const StaticResult r = solve_load_control(p, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  ASSERT_GT(r.steps, 3);
  EXPECT_EQ(r.cutbacks, 0);
  EXPECT_EQ(r.factorizations, r.iterations - (r.steps - 1));
  EXPECT_EQ(p.tangent_evaluations, r.factorizations);  // eq. (4''')
  for (const Point& pt : path) { EXPECT_NEAR(Cubic::lambda_of(pt.q[0]), pt.info.lambda, 1e-12); }
}

TEST(LoadControl, ModifiedNewtonReusesTheFactorization) {
  VonMises full_p, mod_p;
  LoadControlSettings s;
  s.lambda_end = 0.8;
  s.convergence = tight();
  const StaticResult full = solve_load_control(full_p, s);
  s.convergence.tangent = TangentPolicy::modified;
  s.convergence.refactor_iterations = 50;  // refactor on poor contraction only
  std::vector<Point> path;
  record_into(s, mod_p, path);
  const StaticResult mod = solve_load_control(mod_p, s);
  ASSERT_EQ(full.status, StaticStatus::completed);
  ASSERT_EQ(mod.status, StaticStatus::completed) << mod.reason;
  EXPECT_NEAR(mod_p.q[1], full_p.q[1], 1e-10);
  EXPECT_LT(mod.factorizations, full.factorizations);
  EXPECT_LT(mod.factorizations, mod.iterations);
  bool reused = false;
  for (const Point& pt : path) reused |= !pt.info.tangent_refactored;
  EXPECT_TRUE(reused);
}

// ---------------------------------------------------------------------------------------------
class ArcLengthMethods : public ::testing::TestWithParam<ArcLengthMethod> {};

TEST_P(ArcLengthMethods, CubicPassesBothLimitPointsOnTheExactCurve) {
  Cubic p;
  ArcLengthSettings s;
  s.method = GetParam();
  s.convergence = tight();
  s.lambda_max = 1e9;
  s.monitor_dof = 0;
  s.displacement_limit = 5.0;  // beyond the second limit point x ≈ 3.55
  s.initial_load_increment = 0.1;
  s.max_arc_length_ratio = 2.0;
  std::vector<Point> path;
  record_into(s, p, path);
  const StaticResult r = solve_arc_length(p, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_EQ(r.stop, StaticStop::displacement_limit);
  EXPECT_EQ(r.limit_points, 2);
  double x_prev = 0.0, lmax = -1e9, lmin = 1e9, dx_max = 0.0;
  for (const Point& pt : path) {
    const double x = pt.q[0];
    EXPECT_NEAR(pt.info.lambda, Cubic::lambda_of(x), 1e-11) << "x = " << x;
    EXPECT_GT(x, x_prev);  // the path is monotone in x: no back-tracking at the limit points
    EXPECT_NEAR(pt.info.monitored, x, 1e-14);
    dx_max = std::max(dx_max, x - x_prev);
    x_prev = x;
    if (x < Cubic::limit(1)) lmax = std::max(lmax, pt.info.lambda);
    if (x > Cubic::limit(0)) lmin = std::min(lmin, pt.info.lambda);
  }
  EXPECT_GE(p.q[0], 5.0);
  // the sampled extrema approach the limit loads to within ½|λ''|(Δx/2)² (|λ''| ≤ 1.5 there)
  const double bound = 0.75 * 0.25 * dx_max * dx_max;
  EXPECT_LT(dx_max, 0.12);
  EXPECT_NEAR(lmax, Cubic::lambda_of(Cubic::limit(0)), bound);
  EXPECT_NEAR(lmin, Cubic::lambda_of(Cubic::limit(1)), bound);
}

// Under full Newton every factorization is of a new state: one per correction, one after a
// rejected attempt and the first at the origin. A converged state takes the factorization of the
// correction that converged it (eq. 4'') for the end-tangent check of eq. (22') and the next
// predictor: refactorizing the same K for the predictor cost the 32×32 pinched-cylinder octant 84
// of its 546 factorizations, and a factorization of the converged state 84 of the remaining 462.
TEST_P(ArcLengthMethods, FullNewtonFactorizesEachStateOnce) {
  Cubic p;
  ArcLengthSettings s;
  s.method = GetParam();
  s.convergence = tight();
  ASSERT_EQ(s.convergence.tangent, TangentPolicy::every_iteration);
  s.lambda_max = 1e9;
  s.monitor_dof = 0;
  s.displacement_limit = 5.0;
  s.initial_load_increment = 0.1;
  s.max_arc_length_ratio = 2.0;
  const StaticResult r = solve_arc_length(p, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  ASSERT_GT(r.steps, 10);
  EXPECT_LE(r.factorizations, 1 + r.iterations + r.cutbacks);
  // eq. (4'''): every tangent assembled is factorized; the converged states' are never assembled
  EXPECT_EQ(p.tangent_evaluations, r.factorizations);
}

TEST_P(ArcLengthMethods, VonMisesTrussSnapsThroughAndReturnsToPositiveLoad) {
  VonMises p;
  ArcLengthSettings s;
  s.method = GetParam();
  s.convergence = tight();
  s.lambda_max = 10.0;
  s.monitor_dof = 1;
  s.displacement_limit = 2.5 * p.t.h;
  s.initial_load_increment = 0.1;
  s.max_arc_length_ratio = 2.0;
  std::vector<Point> path;
  record_into(s, p, path);
  const StaticResult r = solve_arc_length(p, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_EQ(r.stop, StaticStop::displacement_limit);
  EXPECT_EQ(r.limit_points, 2);
  double lmax = -1e9, lmin = 1e9, w_prev = 0.0, dw_max = 0.0;
  for (const Point& pt : path) {
    const double w = pt.q[1];
    EXPECT_NEAR(pt.info.lambda, p.t.force(w) / p.p, 1e-9) << "w = " << w;
    EXPECT_LT(std::abs(pt.q[0]), 1e-12);  // symmetric: the apex never moves sideways
    EXPECT_GT(w, w_prev);
    dw_max = std::max(dw_max, w - w_prev);
    w_prev = w;
    if (w < p.t.w_limit(1)) lmax = std::max(lmax, pt.info.lambda);
    lmin = std::min(lmin, pt.info.lambda);
  }
  // analytic limit loads ±1 (λ normalised by the first one), sampled within ½|λ''|(Δw/2)²,
  // |λ''| = 6 EA z/(L0³ P) = 900 at z = ±h/√3
  const double bound = 0.5 * 900.0 * 0.25 * dw_max * dw_max;
  EXPECT_LT(bound, 0.01);
  EXPECT_NEAR(lmax, 1.0, bound);
  EXPECT_NEAR(lmin, -1.0, bound);
  EXPECT_GT(r.lambda, 0.0);
  EXPECT_GT(p.q[1], 2.0 * p.t.h);
}

TEST_P(ArcLengthMethods, SnapBackFollowsTheParametricCurve) {
  SnapBack p;
  ArcLengthSettings s;
  s.method = GetParam();
  s.convergence = tight();
  s.lambda_max = 10.0;
  s.monitor_dof = 0;
  s.displacement_limit = 2.5 * p.t.h;
  s.initial_load_increment = 0.05;
  std::vector<Point> path;
  record_into(s, p, path);
  const StaticResult r = solve_arc_length(p, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_EQ(r.stop, StaticStop::displacement_limit);
  int v_decreasing = 0;
  double v_prev = 0.0, w_prev = -1.0;
  for (const Point& pt : path) {
    const double w = pt.q[0], v = pt.q[1];
    EXPECT_NEAR(pt.info.lambda, p.t.force(w) / p.p, 1e-9) << "w = " << w;
    EXPECT_NEAR(v, p.v_of(w), 1e-9) << "w = " << w;
    EXPECT_GT(w, w_prev);
    if (v < v_prev) ++v_decreasing;
    v_prev = v;
    w_prev = w;
  }
  // the load point moved backwards for a stretch: the snap-back was traversed, not jumped
  EXPECT_GE(v_decreasing, 3);
  EXPECT_EQ(r.limit_points, 2);
  EXPECT_GT(r.lambda, 0.0);
}

TEST_P(ArcLengthMethods, TooLongFirstArcIsCutBackAndLandsOnLambdaMax) {
  LogSpring p;
  ArcLengthSettings s;
  s.method = GetParam();
  s.convergence = tight();
  s.initial_load_increment = 3.0;  // predictor to q = 3: ln(−2)
  s.lambda_max = 3.0;
  std::vector<Point> path;
  record_into(s, p, path);
  const StaticResult r = solve_arc_length(p, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_EQ(r.stop, StaticStop::lambda_reached);
  EXPECT_GE(r.cutbacks, 1);
  ASSERT_FALSE(path.empty());
  EXPECT_GT(path.front().info.attempts, 1);
  for (const Point& pt : path) { EXPECT_NEAR(pt.q[0], 1.0 - std::exp(-pt.info.lambda), 1e-12); }
  EXPECT_DOUBLE_EQ(r.lambda, 3.0);
  EXPECT_NEAR(p.q[0], 1.0 - std::exp(-3.0), 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Methods, ArcLengthMethods,
                         ::testing::Values(ArcLengthMethod::crisfield, ArcLengthMethod::lam_morley),
                         [](const auto& info) {
                           return info.param == ArcLengthMethod::crisfield ? "Crisfield" : "LamMorley";
                         });

TEST(ArcLength, SphericalConstraintKeepsTheArcLength) {
  VonMises p;
  ArcLengthSettings s;
  s.psi = 0.01;  // ψ||f|| = 0.038: the load term is comparable with ||Δq|| (~0.04 per unit λ)
  s.convergence = tight();
  s.arc_length = 0.005;
  s.max_arc_length_ratio = 1.0;  // fixed Δl
  s.min_arc_length_ratio = 1.0;
  s.max_steps = 40;
  s.lambda_max = 10.0;
  std::vector<Point> path;
  record_into(s, p, path);
  Eigen::VectorXd q_prev = p.q;
  double l_prev = 0.0;
  const StaticResult r = solve_arc_length(p, s);
  // the step budget ends the run before λ_max: incomplete, not completed
  ASSERT_EQ(r.status, StaticStatus::incomplete) << r.reason;
  EXPECT_EQ(r.stop, StaticStop::max_steps);
  EXPECT_NE(r.reason.find("step 40"), std::string::npos) << r.reason;
  const double fnorm2 = p.load().squaredNorm();
  for (const Point& pt : path) {
    // eq. (10) at convergence: ||Δq||² + ψ²Δλ²||f||² = Δl² (vector space: Δq = q − q_prev)
    const double dl2 = (pt.q - q_prev).squaredNorm() + 1e-4 * std::pow(pt.info.lambda - l_prev, 2) * fnorm2;
    EXPECT_NEAR(std::sqrt(dl2), 0.005, 1e-12);
    EXPECT_NEAR(pt.info.lambda, p.t.force(pt.q[1]) / p.p, 1e-9);
    q_prev = pt.q;
    l_prev = pt.info.lambda;
  }
  EXPECT_GE(r.limit_points, 1);
}

TEST(ArcLength, ModifiedNewtonCorrectorPassesTheLimitPoints) {
  // Crisfield (1981) paired the constraint with modified Newton: factorizations only on stagnation
  SnapBack p;
  ArcLengthSettings s;
  s.convergence = tight();
  s.convergence.tangent = TangentPolicy::modified;
  s.convergence.max_iterations = 40;
  s.desired_iterations = 8;
  s.lambda_max = 10.0;
  s.monitor_dof = 0;
  s.displacement_limit = 2.5 * p.t.h;
  s.initial_load_increment = 0.05;
  std::vector<Point> path;
  record_into(s, p, path);
  const StaticResult r = solve_arc_length(p, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_EQ(r.limit_points, 2);
  EXPECT_LT(r.factorizations, r.iterations / 2);
  for (const Point& pt : path) {
    EXPECT_NEAR(pt.info.lambda, p.t.force(pt.q[0]) / p.p, 1e-9);
    EXPECT_NEAR(pt.q[1], p.v_of(pt.q[0]), 1e-9);
  }
}

// eqs. (13), (13'): Δl grows by max_growth while the step needs at most N_d corrections and its
// predictor turned less than target_turn / max_growth; more corrections shrink it by sqrt(N_d/N),
// a larger turn by target_turn / turn (never below a quarter; no growth after a cut-back)
TEST(ArcLength, ArcLengthAdaptsToIterationsAndTurn) {
  VonMises p;
  ArcLengthSettings s;
  s.desired_iterations = 3;
  s.max_growth = 1.5;
  s.max_steps = 12;
  s.lambda_max = 10.0;
  std::vector<Point> path;
  record_into(s, p, path);
  ASSERT_EQ(solve_arc_length(p, s).status, StaticStatus::incomplete);
  ASSERT_EQ(path.size(), 12u);
  int grew = 0, shrank = 0;
  for (size_t i = 1; i < path.size(); ++i) {
    const StaticStepInfo& a = path[i - 1].info;
    ASSERT_EQ(a.attempts, 1);
    double factor = 1.5;
    if (a.iterations > 3) factor = std::sqrt(3.0 / a.iterations);
    if (a.turn > 0.0) factor = std::min(factor, s.target_turn / a.turn);
    factor = std::max(factor, 0.25);
    const double expected = a.arc_length * factor;
    EXPECT_NEAR(path[i].info.arc_length, expected, 1e-12 * expected) << "step " << i;
    grew += path[i].info.arc_length > a.arc_length;
    shrank += path[i].info.arc_length < a.arc_length;
  }
  EXPECT_GT(grew, 0);
  EXPECT_GT(shrank, 0);  // the truss path turns at its limit points
}

TEST(ArcLength, StopFlagAndStepBudget) {
  Cubic p;
  std::atomic<bool> stop{false};
  ArcLengthSettings s;
  s.stop = &stop;
  s.lambda_max = 1e9;
  int seen = 0;
  s.on_step = [&](const StaticStepInfo&) {
    if (++seen == 2) stop = true;
  };
  const StaticResult r = solve_arc_length(p, s);
  EXPECT_EQ(r.status, StaticStatus::interrupted);
  EXPECT_EQ(r.steps, 2);
  EXPECT_NEAR(Cubic::lambda_of(p.q[0]), r.lambda, 1e-8);
}

// ---------------------------------------------------------------------------------------------
// What the path did is in the result (issue 30, items 7 and 8): returns to the unloaded state and
// loops as events and in the reason, a bound on λ, a stop at the first limit point, and every
// attempt, accepted or not, in the record.

// the von Mises truss at λ = 1 per its first limit load: up to 1, down through 0 to −1, back up
ArcLengthSettings truss_path(ArcLengthMethod method, const VonMises& p) {
  ArcLengthSettings s;
  s.method = method;
  s.convergence = tight();
  s.lambda_max = 10.0;
  s.monitor_dof = 1;
  s.displacement_limit = 2.5 * p.t.h;
  s.initial_load_increment = 0.1;
  s.max_arc_length_ratio = 2.0;
  return s;
}

const StaticEvent* find_event(const StaticResult& r, StaticEvent::Kind kind) {
  for (const StaticEvent& e : r.events)
    if (e.kind == kind) return &e;
  return nullptr;
}

TEST_P(ArcLengthMethods, ReturnToTheUnloadedStateAndBackAreEventsAndInTheReason) {
  VonMises p;
  ArcLengthSettings s = truss_path(GetParam(), p);
  std::vector<Point> path;
  record_into(s, p, path);
  const StaticResult r = solve_arc_length(p, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  const StaticEvent* down = find_event(r, StaticEvent::Kind::unloaded);
  const StaticEvent* back = find_event(r, StaticEvent::Kind::loop);
  ASSERT_TRUE(down && back);
  ASSERT_LT(down->step, back->step);
  // at the step where λ crossed zero, each way
  EXPECT_GT(path[down->step - 2].info.lambda, 0.0);
  EXPECT_LE(path[down->step - 1].info.lambda, 0.0);
  EXPECT_LT(path[back->step - 2].info.lambda, 0.0);
  EXPECT_GE(path[back->step - 1].info.lambda, 0.0);
  EXPECT_NE(back->detail.find("out to λ = -0.99"), std::string::npos) << back->detail;  // the truss's minimum −1, sampled
  // a completed run says it too: the notes, and the reason's tail
  EXPECT_NE(r.notes.find("returned to the unloaded state at step " + std::to_string(down->step)), std::string::npos)
      << r.notes;
  EXPECT_NE(r.notes.find("(a loop)"), std::string::npos) << r.notes;
  EXPECT_NE(r.reason.find(r.notes), std::string::npos) << r.reason;
}

TEST(ArcLength, APathWithoutAReturnToZeroLoadHasNoNotes) {
  Cubic p;  // λ rises, falls to a minimum above zero, rises again
  ArcLengthSettings s;
  s.convergence = tight();
  s.lambda_max = 3.0;
  const StaticResult r = solve_arc_length(p, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_EQ(find_event(r, StaticEvent::Kind::unloaded), nullptr);
  EXPECT_TRUE(r.notes.empty()) << r.notes;
}

TEST_P(ArcLengthMethods, LeavingTheLoadFactorRangeEndsIncompleteNamingTheBoundAndTheStep) {
  VonMises p;
  ArcLengthSettings s = truss_path(GetParam(), p);
  s.lambda_min = -0.5;
  s.lambda_min_name = "solver.min_load_factor";
  std::vector<Point> path;
  record_into(s, p, path);
  const StaticResult r = solve_arc_length(p, s);
  EXPECT_EQ(r.status, StaticStatus::incomplete) << r.reason;
  EXPECT_EQ(r.stop, StaticStop::load_factor_bound);
  ASSERT_FALSE(path.empty());
  EXPECT_LT(r.lambda, -0.5);
  EXPECT_EQ(r.lambda, path.back().info.lambda);
  for (std::size_t k = 0; k + 1 < path.size(); ++k) { EXPECT_GE(path[k].info.lambda, -0.5); }  // stops at the first
  EXPECT_NE(r.reason.find("solver.min_load_factor = -0.5"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("at step " + std::to_string(r.steps)), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("returned to the unloaded state"), std::string::npos) << r.reason;
}

TEST_P(ArcLengthMethods, StopsAtTheFirstLimitPointWhenAsked) {
  VonMises p;
  ArcLengthSettings s = truss_path(GetParam(), p);
  s.stop_at_first_limit_point = true;
  const StaticResult r = solve_arc_length(p, s);
  EXPECT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_EQ(r.stop, StaticStop::limit_point);
  EXPECT_EQ(r.limit_points, 1);
  EXPECT_GT(r.lambda, 0.5);  // just past the maximum λ = 1, nowhere near the second
  EXPECT_NE(r.reason.find("first limit point"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("maximum of λ"), std::string::npos) << r.reason;
}

TEST(ArcLength, ABoundAboveTheStartIsInvalid) {
  VonMises p;
  ArcLengthSettings s = truss_path(ArcLengthMethod::crisfield, p);
  s.lambda_min = 0.5;
  const StaticResult r = solve_arc_length(p, s);
  EXPECT_EQ(r.stop, StaticStop::invalid_settings);
}

// corrections of the accepted steps plus those of the rejected attempts make up r.iterations
template <class Path>
int corrections_in_the_record(Path& path, int& accepted, int& rejected_rows) {
  int sum = 0;
  accepted = rejected_rows = 0;
  auto take = [&] {
    for (const StaticAttempt& a : path.rejected()) {
      sum += a.iterations;
      ++rejected_rows;
      EXPECT_FALSE(a.why.empty());
    }
  };
  while (!path.finished()) {
    const bool stepped = path.advance();
    take();  // rejected() holds this call's attempts only
    if (!stepped) break;
    sum += path.last_step().iterations;
    accepted += path.last_step().iterations;
  }
  return sum;
}

TEST_P(ArcLengthMethods, EveryCorrectionIsInTheRecordWithCutBacksAndTheLanding) {
  LogSpring p;
  ArcLengthSettings s;
  s.method = GetParam();
  s.convergence = tight();
  s.initial_load_increment = 3.0;  // the first arc fails (ln of a negative number) and is halved
  s.lambda_max = 3.0;
  ArcLengthPath path(p, s);
  ASSERT_TRUE(path.start());
  int accepted = 0, rows = 0;
  const int sum = corrections_in_the_record(path, accepted, rows);
  const StaticResult& r = path.result();
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_GE(r.cutbacks, 1);
  EXPECT_GE(rows, r.cutbacks + 1);  // the cut-backs and the arc step the landing on λ_max replaced
  EXPECT_LT(accepted, r.iterations);  // the accepted steps alone miss corrections
  EXPECT_EQ(sum, r.iterations);
  // the first step needed cut-backs: an event says so
  const StaticEvent* first = find_event(r, StaticEvent::Kind::first_step_cut_back);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->step, 1);
  EXPECT_NE(first->detail.find("cut-back"), std::string::npos) << first->detail;
}

TEST(LoadControl, EveryCorrectionIsInTheRecordAndAFirstStepCutBackIsAnEvent) {
  LogSpring p;
  LoadControlSettings s;
  s.lambda_end = 3.0;
  s.initial_step = s.max_step = 3.0;  // Newton jumps to q = 3, ln(−2): cut back
  s.convergence = tight();
  LoadControlPath path(p, s);
  int accepted = 0, rows = 0;
  const int sum = corrections_in_the_record(path, accepted, rows);
  const StaticResult& r = path.result();
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_GE(r.cutbacks, 1);
  EXPECT_EQ(rows, r.cutbacks);
  EXPECT_LT(accepted, r.iterations);
  EXPECT_EQ(sum, r.iterations);
  const StaticEvent* first = find_event(r, StaticEvent::Kind::first_step_cut_back);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->step, 1);
  // halved once per cut-back: 1/2^(attempts − 1) of the initial step, at the λ it reached
  const int cuts = r.cutbacks;  // all of them on the first step: the later steps grow from it
  EXPECT_NE(first->detail.find(std::to_string(cuts) + " cut-backs, at " + significant(std::ldexp(1.0, -cuts)) + " of the initial step"),
            std::string::npos)
      << first->detail;
  EXPECT_DOUBLE_EQ(first->lambda, 3.0 * std::ldexp(1.0, -cuts));
}

TEST(LoadControl, ADivergedRunRecordsTheAttemptsItEndedOn) {
  SnapBack p;  // load control cannot pass the limit point at λ = 1
  LoadControlSettings s;
  s.lambda_end = 1.5;
  s.convergence = tight();
  LoadControlPath path(p, s);
  int accepted = 0, rows = 0;
  const int sum = corrections_in_the_record(path, accepted, rows);
  const StaticResult& r = path.result();
  ASSERT_EQ(r.status, StaticStatus::diverged) << r.reason;
  EXPECT_GT(rows, 0);
  EXPECT_EQ(sum, r.iterations);
}

TEST(LoadControl, TheEndKeyIsNamedInTheReason) {
  Cubic p;
  LoadControlSettings s;
  s.lambda_end = 0.5;
  s.lambda_end_name = "solver.end";
  s.max_steps = 1;
  s.initial_step = 0.1;
  const StaticResult r = solve_load_control(p, s);
  EXPECT_EQ(r.status, StaticStatus::incomplete);
  EXPECT_NE(r.reason.find("before solver.end = 0.5"), std::string::npos) << r.reason;
}

}  // namespace
}  // namespace ff
