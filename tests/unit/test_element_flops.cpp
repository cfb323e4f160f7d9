// The flop count of the CB element (core/shell/cb_shell.md, "Flop count"): the counting scalar
// counts what it should, and the counted run of the element computes the solver's force and
// tangent, so the count is the count of the kernel the solver runs.
#include <gtest/gtest.h>

#include "core/shell/cb_shell.h"
#include "core/shell/counted_scalar.h"
#include "app/bench/sample_elements.h"

namespace {

using namespace ff::shell;
using Counted = CountedDouble;

TEST(CountedScalar, CountsTextbookOperationCounts) {
  // a 3x3 matrix times a 3-vector: 9 multiplies and 6 adds
  Eigen::Matrix<Counted, 3, 3> A;
  Eigen::Matrix<Counted, 3, 1> x, y;
  for (int i = 0; i < 3; ++i) {
    x[i] = 1.0 + i;
    for (int j = 0; j < 3; ++j) A(i, j) = 0.5 * (i + 1) - j;
  }
  counted_flops = 0;
  y.noalias() = A.lazyProduct(x);
  EXPECT_EQ(counted_flops, 15);
  EXPECT_DOUBLE_EQ(y[0].value, 0.5 * 1 - 0.0 * 1 + (0.5 - 1) * 2 + (0.5 - 2) * 3);
  // a dot product of 5-vectors: 5 multiplies, 4 adds; a square root is one flop
  Eigen::Matrix<Counted, 5, 1> a = Eigen::Matrix<Counted, 5, 1>::Constant(2.0);
  counted_flops = 0;
  const Counted d = a.dot(a);
  EXPECT_EQ(counted_flops, 9);
  counted_flops = 0;
  EXPECT_DOUBLE_EQ(sqrt(d).value, std::sqrt(20.0));
  EXPECT_EQ(counted_flops, 1);
  // negation and comparison are free
  counted_flops = 0;
  EXPECT_TRUE(-d < d);
  EXPECT_EQ(counted_flops, 0);
}

double relative_difference(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// For every effect set (5 DoF without drilling, 6 with): the counted run reproduces the double
// kernel's force and tangent (to round-off: the double build may fuse multiply-adds), and the
// tangent adds work to the force.
TEST(ElementFlops, CountedRunIsTheSolverKernelForEveryEffectSet) {
  const ElementPoses ref = samples::curved();
  const ElementPoses cur = samples::deformed(ref, 5);
  for (int mask = 0; mask < 8; ++mask) {
    ShellOptions o;
    o.hr = mask & 1;
    o.ans = mask & 2;
    o.drilling = mask & 4;
    o.drilling_factor = 0.1;
    const CbShellElement el(ref, isotropic_section(2.0e5, 0.3, 0.05), o);
    Vec24 f;
    Mat24 K;
    el.evaluate(cur, f, &K);
    const ElementFlops n = count_element_flops(el, cur);
    SCOPED_TRACE("hr " + std::to_string(o.hr) + " ans " + std::to_string(o.ans) + " drilling " +
                 std::to_string(o.drilling));
    EXPECT_LT(relative_difference(n.counted_force, f), 1e-13);
    EXPECT_LT(relative_difference(n.counted_tangent, K), 1e-13);
    EXPECT_GT(n.force, 1000);
    EXPECT_GT(n.force_tangent, 3 * n.force);
  }
}

// The count follows the effects: drilling adds its points, hr replaces the membrane rows.
TEST(ElementFlops, DrillingAddsWork) {
  const ElementPoses ref = samples::curved();
  const ElementPoses cur = samples::deformed(ref, 5);
  ShellOptions five, six;
  six.drilling = true;
  const ElementFlops n5 = count_element_flops(CbShellElement(ref, isotropic_section(2.0e5, 0.3, 0.05), five), cur);
  const ElementFlops n6 = count_element_flops(CbShellElement(ref, isotropic_section(2.0e5, 0.3, 0.05), six), cur);
  EXPECT_GT(n6.force, n5.force);
  EXPECT_GT(n6.force_tangent, n5.force_tangent);
}

}  // namespace
