// Shape functions of the hub-beam (core/hubbeam/hub_beam.md §6-§7): IGMLS/IMLS Kronecker
// property, polynomial reproduction, derivatives against central differences.
#include <gtest/gtest.h>

#include <cmath>

#include "core/hubbeam/beam_basis.h"
#include "core/solve/gauss.h"

using namespace ff::hubbeam;

namespace {
constexpr double kL = 1.8;

std::unique_ptr<BeamBasis> efg(double scale = 2.5, int nodes = 10) {
  EfgOptions o;
  o.nodes = nodes;
  o.scale = scale;
  return make_efg_basis(kL, o);
}
}  // namespace

TEST(Gauss, IntegratesPolynomialsExactly) {
  for (int n = 1; n <= 8; ++n) {
    const ff::GaussRule r = ff::gauss_legendre(n);
    for (int deg = 0; deg <= 2 * n - 1; ++deg) {
      double s = 0;
      for (int i = 0; i < n; ++i) s += r.weights[i] * std::pow(r.points[i], deg);
      const double exact = deg % 2 ? 0.0 : 2.0 / (deg + 1);
      EXPECT_NEAR(s, exact, 1e-14) << "n=" << n << " deg=" << deg;
    }
  }
}

TEST(CubicSplineWeight, IsC2AndCompact) {
  double w, dw, ddw, w2, dw2, ddw2;
  cubic_spline_weight(0.0, w, dw, ddw);
  EXPECT_NEAR(w, 2.0 / 3.0, 1e-15);
  EXPECT_NEAR(dw, 0.0, 1e-15);
  for (double r0 : {0.5, 1.0}) {
    cubic_spline_weight(r0 - 1e-12, w, dw, ddw);
    cubic_spline_weight(r0 + 1e-12, w2, dw2, ddw2);
    EXPECT_NEAR(w, w2, 1e-10);
    EXPECT_NEAR(dw, dw2, 1e-10);
    EXPECT_NEAR(ddw, ddw2, 1e-9);
  }
  cubic_spline_weight(1.2, w, dw, ddw);
  EXPECT_EQ(w, 0.0);
}

// the defining property of the interpolating transform, eq. (22)-(23)
TEST(Igmls, KroneckerPropertyOnValuesAndSlopes) {
  for (double scale : {1.5, 2.0, 2.5, 3.0, 4.0}) {
    auto b = efg(scale);
    const int n = b->node_count();
    ShapeRows s = b->make_rows();
    for (int j = 0; j < n; ++j) {
      b->evaluate(b->nodes()[j], s);
      for (int i = 0; i < 2 * n; ++i) {
        EXPECT_NEAR(s.n2[i], i == j ? 1.0 : 0.0, 1e-9) << "scale " << scale << " node " << j;
        EXPECT_NEAR(s.dn2[i], i == n + j ? 1.0 : 0.0, 1e-8) << "scale " << scale << " node " << j;
      }
      for (int i = 0; i < n; ++i) { EXPECT_NEAR(s.n1[i], i == j ? 1.0 : 0.0, 1e-9); }
    }
  }
}

// GMLS with basis [1, x, x^2] reproduces quadratics exactly, values and derivatives
TEST(Igmls, ReproducesQuadratics) {
  auto b = efg();
  const int n = b->node_count();
  auto f = [](double x) { return 0.3 - 1.2 * x + 0.7 * x * x; };
  auto df = [](double x) { return -1.2 + 1.4 * x; };
  Eigen::VectorXd q2(2 * n), q1(n);
  for (int i = 0; i < n; ++i) {
    q2[i] = f(b->nodes()[i]);
    q2[n + i] = df(b->nodes()[i]);
    q1[i] = 0.5 - 2.0 * b->nodes()[i];  // linear field for the (degree-1) axial IMLS
  }
  ShapeRows s = b->make_rows();
  for (double x = 0.013; x < kL; x += 0.0917) {
    b->evaluate(x, s);
    EXPECT_NEAR(s.n2.dot(q2), f(x), 1e-9) << x;
    EXPECT_NEAR(s.dn2.dot(q2), df(x), 1e-8) << x;
    EXPECT_NEAR(s.ddn2.dot(q2), 1.4, 1e-6) << x;
    EXPECT_NEAR(s.n1.dot(q1), 0.5 - 2.0 * x, 1e-9) << x;
    EXPECT_NEAR(s.dn1.dot(q1), -2.0, 1e-8) << x;
  }
}

void check_derivatives(const BeamBasis& b) {
  ShapeRows s = b.make_rows(), sp = b.make_rows(), sm = b.make_rows();
  const double h = 1e-5;
  for (double x = 0.031; x < kL - 0.01; x += 0.137) {
    b.evaluate(x, s);
    b.evaluate(x + h, sp);
    b.evaluate(x - h, sm);
    const double scale1 = 1.0 + s.dn2.cwiseAbs().maxCoeff(), scale2 = 1.0 + s.ddn2.cwiseAbs().maxCoeff();
    EXPECT_LT(((sp.n2 - sm.n2) / (2 * h) - s.dn2).cwiseAbs().maxCoeff(), 1e-6 * scale1) << b.name() << " x=" << x;
    EXPECT_LT(((sp.dn2 - sm.dn2) / (2 * h) - s.ddn2).cwiseAbs().maxCoeff(), 1e-5 * scale2) << b.name() << " x=" << x;
    EXPECT_LT(((sp.n1 - sm.n1) / (2 * h) - s.dn1).cwiseAbs().maxCoeff(), 1e-6 * (1 + s.dn1.cwiseAbs().maxCoeff()));
  }
}

TEST(Igmls, DerivativesMatchFiniteDifferences) { check_derivatives(*efg()); }

TEST(Fem, DerivativesMatchFiniteDifferencesAndNodesInterpolate) {
  FemOptions o;
  auto b = make_fem_basis(kL, o);
  check_derivatives(*b);
  ShapeRows s = b->make_rows();
  const int n = b->node_count();
  b->evaluate(kL, s);
  EXPECT_NEAR(s.n2[n - 1], 1.0, 1e-14);
  EXPECT_NEAR(s.dn2[2 * n - 1], 1.0, 1e-12);
}

TEST(Igmls, TooSmallSupportIsReportedNotCrashed) {
  EfgOptions o;
  o.scale = 1.5;
  o.axial_basis_order = 2;  // needs 3 nodes in every support; 1.5 spacings hold only 2 between nodes
  try {
    make_efg_basis(kL, o);
    FAIL() << "expected a singular moment matrix to be reported";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("efg.scale"), std::string::npos) << e.what();
  }
}
