// Lie-group generalized-alpha (core/solve/generalized_alpha.md) on problems with closed-form
// answers: the linear oscillator (second-order accuracy, no dissipation at rho_inf = 1, energy never
// grows for rho_inf < 1) and the index-3 pendulum in Cartesian coordinates (constraint kept at
// solver tolerance, small-amplitude period 2 pi sqrt(L/g)); iteration-matrix policies count NOI/NOU.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/solve/generalized_alpha.h"

using namespace ff;

namespace {

// x'' + w^2 x = 0 on the additive group R (exp = identity map)
class Oscillator : public DynamicProblem {
 public:
  explicit Oscillator(double w, double x0) : w2_(w * w), x_(x0), xn_(x0) {}
  int size() const override { return 1; }
  int constraint_count() const override { return 0; }
  void configure(const Eigen::VectorXd& step) override { x_ = xn_ + step[0]; }
  void commit() override { xn_ = x_; }
  void rollback() override { x_ = xn_; }
  void evaluate(double, const Eigen::VectorXd&, const Eigen::VectorXd& vd, const Eigen::VectorXd&, Eigen::VectorXd& r,
                Eigen::VectorXd& phi, const IterationWeights* w, SparseMatrixD* S, SparseMatrixD* B) override {
    r.resize(1);
    r[0] = vd[0] + w2_ * x_;
    phi.resize(0);
    if (w && S) {
      S->resize(1, 1);
      S->insert(0, 0) = w->mass + w->stiffness * w2_;
      S->makeCompressed();
    }
    if (B) B->resize(0, 1);
  }
  double x() const { return x_; }

 private:
  double w2_, x_, xn_;
};

// a point mass m on a massless rod of length L, in Cartesian (x, y): Φ = ½(x² + y² − L²), gravity −y
class Pendulum : public DynamicProblem {
 public:
  Pendulum(double L, double angle) : L_(L) { q_ = qn_ = Eigen::Vector2d(L * std::sin(angle), -L * std::cos(angle)); }
  int size() const override { return 2; }
  int constraint_count() const override { return 1; }
  void configure(const Eigen::VectorXd& step) override { q_ = qn_ + step; }
  void commit() override { qn_ = q_; }
  void rollback() override { q_ = qn_; }
  void evaluate(double, const Eigen::VectorXd&, const Eigen::VectorXd& vd, const Eigen::VectorXd& lam,
                Eigen::VectorXd& r, Eigen::VectorXd& phi, const IterationWeights* w, SparseMatrixD* S,
                SparseMatrixD* B) override {
    r = vd + lam[0] * q_;
    r[1] += kG;
    phi.resize(1);
    phi[0] = 0.5 * (q_.squaredNorm() - L_ * L_);
    if (w && S) {
      S->resize(2, 2);
      S->setZero();
      S->insert(0, 0) = w->mass + w->stiffness * lam[0];
      S->insert(1, 1) = w->mass + w->stiffness * lam[0];
      S->makeCompressed();
    }
    if (B) {
      B->resize(1, 2);
      B->setZero();
      B->insert(0, 0) = q_[0];
      B->insert(0, 1) = q_[1];
      B->makeCompressed();
    }
  }
  const Eigen::Vector2d& q() const { return q_; }
  double energy(const Eigen::VectorXd& v) const { return 0.5 * v.squaredNorm() + kG * q_[1]; }
  static constexpr double kG = 9.81;

 private:
  double L_;
  Eigen::Vector2d q_, qn_;
};

// x = cos(w t) integrated to T = 1.125 periods (at a whole period x is at an extremum and its error
// is O(h^4)): the global error at T, and the steps' local error estimates (G12) summed in magnitude
struct Oscillation {
  double error = 0.0, summed_local_error = 0.0;
};
Oscillation oscillate(double h, double rho) {
  const double w = 2 * std::numbers::pi, T = 1.125;
  Oscillator p(w, 1.0);
  GeneralizedAlphaSettings s;
  s.rho_inf = rho;
  s.tolerance = 1e-13;
  GeneralizedAlpha ga(p, s);
  EXPECT_EQ(ga.initialize(0.0, Eigen::VectorXd::Zero(1)), "");
  const int steps = static_cast<int>(std::lround(T / h));
  Oscillation out;
  Eigen::VectorXd e;
  for (int i = 0; i < steps; ++i) {
    EXPECT_TRUE(ga.step(h).converged);
    ga.take_local_error(e);
    out.summed_local_error += std::abs(e[0]);
  }
  out.error = std::abs(p.x() - std::cos(w * T));
  return out;
}
double oscillator_error(double h, double rho) { return oscillate(h, rho).error; }

TEST(GeneralizedAlpha, OscillatorIsSecondOrderAccurate) {
  for (double rho : {1.0, 0.9, 0.5}) {
    const double e1 = oscillator_error(1.0 / 80, rho), e2 = oscillator_error(1.0 / 160, rho);
    EXPECT_GT(e1 / e2, 3.5) << "rho_inf " << rho;  // ~4 for second order
    EXPECT_LT(e1 / e2, 4.5) << "rho_inf " << rho;
  }
}

// (G12)-(G13) against the one-step error of the trapezoidal rule (rho_inf = 1, where the initial
// acceleration is the shifted one exactly): from the exact state of x = cos(w t + phi) the step's
// position minus the exact one is the local error, and the estimate h^2/12 (a1 - a0) must match
// it in sign and size as h -> 0. (phi = 0 would be a bad choice: the third derivative of x is 0
// there, the h^3 term vanishes, and the h^4 term, which the estimate halves, is all that is left.)
TEST(GeneralizedAlpha, LocalErrorEstimateMatchesOneStepOfTheTrapezoidalRule) {
  const double w = 2 * std::numbers::pi, phi = std::numbers::pi / 3;
  for (double h : {1e-2, 5e-3}) {
    Oscillator p(w, std::cos(phi));
    GeneralizedAlphaSettings s;
    s.rho_inf = 1.0;
    s.tolerance = 1e-14;
    GeneralizedAlpha ga(p, s);
    ASSERT_EQ(ga.initialize(0.0, Eigen::VectorXd::Constant(1, -w * std::sin(phi))), "");
    Eigen::VectorXd e;
    ga.take_local_error(e);
    EXPECT_EQ(e[0], 0.0) << "initialize() takes no step";
    ASSERT_TRUE(ga.step(h).converged);
    ga.take_local_error(e);
    const double actual = p.x() - std::cos(phi + w * h);
    EXPECT_NEAR(e[0] / actual, 1.0, 0.02) << "h " << h;
    ga.take_local_error(e);
    EXPECT_EQ(e[0], 0.0) << "taken: the sum starts again";
  }
}

// (G14): summed in magnitude over the steps, the local errors of an undamped oscillation give its
// global (phase) error to within the mean of |sin| and the phase of the end point, for every
// rho_inf, and fall by 4 per halving of h like the error itself
TEST(GeneralizedAlpha, SummedLocalErrorsFollowTheGlobalErrorOfAnOscillation) {
  for (double rho : {1.0, 0.9, 0.6}) {
    for (double h : {1.0 / 40, 1.0 / 80}) {
      const Oscillation o = oscillate(h, rho);
      const double estimate = o.summed_local_error, actual = o.error;
      EXPECT_GT(estimate / actual, 1.0 / 3.0) << "rho_inf " << rho << ", h " << h;
      EXPECT_LT(estimate / actual, 3.0) << "rho_inf " << rho << ", h " << h;
    }
    const double ratio = oscillate(1.0 / 80, rho).summed_local_error / oscillate(1.0 / 160, rho).summed_local_error;
    EXPECT_GT(ratio, 3.5) << "rho_inf " << rho;
    EXPECT_LT(ratio, 4.5) << "rho_inf " << rho;
  }
}

TEST(GeneralizedAlpha, EnergyConservedAtRhoOneAndNeverGrowsBelow) {
  const double w = 2 * std::numbers::pi, h = 0.05;  // coarse: 20 steps per period
  for (double rho : {1.0, 0.6, 0.0}) {
    Oscillator p(w, 1.0);
    GeneralizedAlphaSettings s;
    s.rho_inf = rho;
    s.tolerance = 1e-13;
    GeneralizedAlpha ga(p, s);
    ASSERT_EQ(ga.initialize(0.0, Eigen::VectorXd::Zero(1)), "");
    auto energy = [&] { return 0.5 * ga.velocity()[0] * ga.velocity()[0] + 0.5 * w * w * p.x() * p.x(); };
    const double e0 = energy();
    // the physical energy oscillates within a period (what decreases monotonically is the scheme's
    // own norm, Chung & Hulbert 1993); its maximum over each period must not grow
    double period_max = 0.0, last_period_max = 1e300;
    for (int i = 1; i <= 400; ++i) {  // 20 periods of 20 steps
      ASSERT_TRUE(ga.step(h).converged);
      if (rho == 1.0) { EXPECT_NEAR(energy(), e0, 1e-9 * e0); }  // trapezoidal rule: exact for a linear system
      period_max = std::max(period_max, energy());
      if (i % 20 == 0) {
        EXPECT_LE(period_max, last_period_max * (1 + 1e-12)) << "rho_inf " << rho << " period " << i / 20;
        last_period_max = period_max;
        period_max = 0.0;
      }
    }
    if (rho < 1.0) { EXPECT_LT(energy(), 0.999 * e0); }
  }
}

TEST(GeneralizedAlpha, PendulumKeepsItsConstraintAndSmallAmplitudePeriod) {
  const double L = 1.0, angle = 0.05, h = 1e-3;
  Pendulum p(L, angle);
  GeneralizedAlphaSettings s;
  s.rho_inf = 0.8;
  s.tolerance = 1e-12;
  GeneralizedAlpha ga(p, s);
  ASSERT_EQ(ga.initialize(0.0, Eigen::VectorXd::Zero(2)), "");
  // initial multiplier: tension m g cos(angle) / L at rest
  EXPECT_NEAR(ga.multipliers()[0], Pendulum::kG * std::cos(angle) / L, 1e-9);
  const double e0 = p.energy(ga.velocity());
  double previous_x = p.q()[0], crossing = -1;
  int crossings = 0;
  while (ga.time() < 3.0) {
    ASSERT_TRUE(ga.step(h).converged);
    EXPECT_LT(std::abs(p.q().norm() - L), 1e-10);
    const double x = p.q()[0];
    if (previous_x > 0 && x <= 0 && ++crossings == 1) crossing = ga.time() - h * x / (x - previous_x);
    previous_x = x;
  }
  // first downward zero crossing at a quarter period; finite amplitude lengthens it by ~θ²/16
  const double T = 2 * std::numbers::pi * std::sqrt(L / Pendulum::kG) * (1 + angle * angle / 16);
  EXPECT_NEAR(crossing, 0.25 * T, 2e-4 * T);
  EXPECT_LE(p.energy(ga.velocity()), e0 + 1e-9);  // rho_inf < 1 dissipates, never adds
}

TEST(GeneralizedAlpha, PoliciesCountIterationsAndUpdates) {
  const double h = 2e-3;
  struct Run {
    long long noi, nou, fallbacks;
    double x;
  };
  auto run = [&](MatrixPolicy policy, int nni) {
    Pendulum p(1.0, 0.5);  // a swing of 0.5 rad: the matrix changes (the multiplier varies)
    GeneralizedAlphaSettings s;
    s.policy = policy;
    s.nni_threshold = nni;
    s.tolerance = 1e-10;
    GeneralizedAlpha ga(p, s);
    EXPECT_EQ(ga.initialize(0.0, Eigen::VectorXd::Zero(2)), "");
    for (int i = 0; i < 500; ++i) { EXPECT_TRUE(ga.step(h).converged); }
    return Run{ga.total_iterations(), ga.total_updates(), ga.total_fallbacks(), p.q()[0]};
  };
  const Run full = run(MatrixPolicy::full, 0), nni = run(MatrixPolicy::nni, 3), frozen = run(MatrixPolicy::frozen, 0),
            lazy = run(MatrixPolicy::lazy, 0);
  EXPECT_EQ(full.nou, full.noi);            // one update per iteration
  EXPECT_LT(nni.nou, full.nou);
  EXPECT_GE(nni.noi, full.noi);
  // Cartesian coordinates: the constraint gradient turns with the rod, so a frozen matrix stops
  // converging within max_iterations after a while and the step is redone with fresh matrices;
  // every update beyond the initial one belongs to such a fallback
  EXPECT_EQ(nni.fallbacks, 0);
  EXPECT_LE(frozen.nou, 1 + frozen.fallbacks * 30);
  EXPECT_LT(frozen.nou, nni.nou);
  EXPECT_GT(frozen.noi, full.noi);
  // lazy (G10) refreshes the aging matrix before a step fails: no fallbacks, fewer updates than
  // nni, fewer iterations than frozen
  EXPECT_EQ(lazy.fallbacks, 0);
  EXPECT_LT(lazy.nou, nni.nou);
  EXPECT_GT(lazy.nou, 1);
  EXPECT_LT(lazy.noi, frozen.noi);
  // same trajectory up to the Newton tolerance accumulated over 500 steps
  EXPECT_NEAR(nni.x, full.x, 1e-6);
  EXPECT_NEAR(frozen.x, full.x, 1e-6);
  EXPECT_NEAR(lazy.x, full.x, 1e-6);
}

// (G10'): under lazy, a step that kept its matrix and ended on a contraction ‖Δx_k‖/‖Δx_{k−1}‖
// above step_refresh_ratio hands the next step a fresh matrix from its first correction on; with
// the rule off (ratio 1) the next step keeps the aged one unless its own corrections slow down
// (G10). Either way the trajectory is the same to the Newton tolerance.
TEST(GeneralizedAlpha, LazyStartsTheStepAfterASlowContractionWithAFreshMatrix) {
  constexpr double slow = 0.1;
  struct Run {
    int slow_ends = 0, refreshed_after = 0;
    double x = 0.0;
  };
  auto run = [](double step_refresh_ratio) {
    Pendulum p(1.0, 0.5);
    GeneralizedAlphaSettings s;
    s.policy = MatrixPolicy::lazy;
    s.tolerance = 1e-10;
    s.step_refresh_ratio = step_refresh_ratio;
    GeneralizedAlpha ga(p, s);
    EXPECT_EQ(ga.initialize(0.0, Eigen::VectorXd::Zero(2)), "");
    Run r;
    bool ended_slow = false;
    for (int i = 0; i < 500; ++i) {
      const StepReport rep = ga.step(2e-3);
      EXPECT_TRUE(rep.converged);
      if (ended_slow) ++r.slow_ends, r.refreshed_after += rep.matrix_updates > 0;
      const std::vector<double>& c = ga.last_corrections();
      ended_slow = rep.matrix_updates == 0 && c.size() >= 2 && c.back() > slow * c[c.size() - 2];
    }
    r.x = p.q()[0];
    return r;
  };
  const Run on = run(slow), off = run(1.0);
  EXPECT_GT(on.slow_ends, 0);
  EXPECT_EQ(on.refreshed_after, on.slow_ends);
  EXPECT_GT(off.slow_ends, 0);
  EXPECT_LT(off.refreshed_after, off.slow_ends);
  EXPECT_NEAR(on.x, off.x, 1e-6);
}

// (G3'): starting from v̇_{n+1} = v̇_n with x and v moved along (G6) changes where Newton starts,
// not what it converges to. On the linear oscillator one correction solves each step exactly, so
// both predictors give the same trajectory to round-off, and the first correction (the predictor's
// miss) shrinks from O(h² ω² x) to O(h³ ω³ x); on the nonlinear pendulum the trajectories agree to
// the tolerance and the closer start needs fewer corrections.
TEST(GeneralizedAlpha, PreviousAccelerationPredictorStartsCloserAndConvergesToTheSameSteps) {
  struct Run {
    double x, first_correction_sum;
    long long noi;
  };
  auto oscillator = [](AccelerationPredictor predictor) {
    const double w = 2 * std::numbers::pi, h = 1.0 / 80;
    Oscillator p(w, 1.0);
    GeneralizedAlphaSettings s;
    s.tolerance = 1e-13;
    s.predictor = predictor;
    GeneralizedAlpha ga(p, s);
    EXPECT_EQ(ga.initialize(0.0, Eigen::VectorXd::Zero(1)), "");
    double first = 0.0;
    for (int i = 0; i < 90; ++i) {
      EXPECT_TRUE(ga.step(h).converged);
      first += ga.last_corrections().front();
    }
    return Run{p.x(), first, ga.total_iterations()};
  };
  const Run zero = oscillator(AccelerationPredictor::zero), previous = oscillator(AccelerationPredictor::previous);
  EXPECT_NEAR(previous.x, zero.x, 1e-12);
  EXPECT_LT(previous.first_correction_sum, 0.2 * zero.first_correction_sum);  // ω h = 0.08

  auto pendulum = [](AccelerationPredictor predictor) {
    Pendulum p(1.0, 0.5);
    GeneralizedAlphaSettings s;
    s.tolerance = 1e-12;
    s.predictor = predictor;
    GeneralizedAlpha ga(p, s);
    EXPECT_EQ(ga.initialize(0.0, Eigen::VectorXd::Zero(2)), "");
    for (int i = 0; i < 500; ++i) { EXPECT_TRUE(ga.step(2e-3).converged); }
    return Run{p.q()[0], 0.0, ga.total_iterations()};
  };
  const Run pz = pendulum(AccelerationPredictor::zero), pp = pendulum(AccelerationPredictor::previous);
  EXPECT_NEAR(pp.x, pz.x, 1e-9);
  EXPECT_LT(pp.noi, pz.noi);
}

}  // namespace
