// Patch tests on the distorted 5-element mesh of MacNeal & Harder (1985, FEAD 1:3-20): the
// rectangle 0.24 x 0.12 with interior nodes (0.04, 0.02), (0.18, 0.03), (0.16, 0.08), (0.08, 0.08);
// E = 1e6, nu = 0.25, h = 0.001. The exact field is prescribed on the four boundary nodes and the
// linear problem about the reference state (the assembled tangent at the undeformed mesh, i.e. the
// element's linear stiffness) is solved for the interior nodes, which must reproduce the field:
// - membrane: u = 1e-3 (x + y/2), v = 1e-3 (y + x/2) (constant strain, no rotation);
// - bending (Kirchhoff constant curvature): w = 1e-3 (x^2 + xy + y^2)/2 with the director tilts
//   theta_x = dw/dy, theta_y = -dw/dx (zero transverse shear).
// Both with hr + ans, for 5 DoF and 6 DoF (drilling) per node; tolerance 1e-8 of the field's
// largest interior value (measured 5e-10 membrane: its stiffness is ~1e6 x the bending one at
// h = 0.001; 7e-12 bending). MITC4-type shear tying with bilinear directors reproduces constant
// curvature exactly on a flat distorted mesh, so the bending patch is passed, not approximated.
#include <gtest/gtest.h>

#include <Eigen/SparseLU>

#include "core/shell/shell_model.h"

using namespace ff::shell;

namespace {
constexpr double kA = 1e-3;

ff::mesh::ShellMesh macneal_harder_patch() {
  ff::mesh::ShellMesh m;
  const double p[8][2] = {{0, 0}, {0.24, 0}, {0.24, 0.12}, {0, 0.12},
                          {0.04, 0.02}, {0.18, 0.03}, {0.16, 0.08}, {0.08, 0.08}};
  for (const auto& q : p) {
    m.points.emplace_back(q[0], q[1], 0.0);
    m.normals.push_back(Vec3::UnitZ());
  }
  m.quads = {{0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}, {4, 5, 6, 7}};  // all CCW about +z
  for (const Vec3& n : m.normals) m.frames.push_back(ff::mesh::frame_from_normal(n, Vec3::UnitX()));
  m.fold.assign(m.points.size(), 0);
  return m;
}

ShellModelSpec spec(bool drilling) {
  ShellModelSpec s;
  s.mesh = macneal_harder_patch();
  s.section = isotropic_section(1.0e6, 0.25, 0.001);
  s.options.hr = s.options.ans = true;
  s.options.drilling = drilling;
  return s;
}

// exact nodal values [ux, uy, uz, rx, ry, rz] (rotations as global rotation-vector components,
// which for the flat mesh with e1 = x are also the 5-DoF node's local increments)
using Field = Eigen::Matrix<double, 6, 1>;
Field membrane(const Vec3& X) {
  Field f = Field::Zero();
  f[0] = kA * (X.x() + 0.5 * X.y());
  f[1] = kA * (X.y() + 0.5 * X.x());
  return f;
}
Field bending(const Vec3& X) {
  Field f = Field::Zero();
  f[2] = 0.5 * kA * (X.x() * X.x() + X.x() * X.y() + X.y() * X.y());
  f[3] = kA * (X.y() + 0.5 * X.x());    // theta_x = dw/dy
  f[4] = -kA * (X.x() + 0.5 * X.y());   // theta_y = -dw/dx
  return f;
}
// not a patch-test field (varying curvature): the interior cannot reproduce it -- the control that
// shows the comparison can fail
Field cubic(const Vec3& X) {
  Field f = Field::Zero();
  f[2] = kA * X.x() * X.x() * X.x() / 0.24;
  f[4] = -3 * kA * X.x() * X.x() / 0.24;
  return f;
}

// solve K_ii u_i = -K_ib u_b on the unrestrained model's reference tangent; max relative error of
// the interior nodes against the field
double linear_patch_error(bool drilling, Field (*field)(const Vec3&)) {
  ShellModel model(spec(drilling));
  const int n = model.size(), dofs = drilling ? 6 : 5;
  Eigen::VectorXd r;
  Eigen::SparseMatrix<double> K;
  model.evaluate(0.0, r, &K, nullptr);
  const Eigen::MatrixXd Kd(K);
  std::vector<int> inner, outer;
  Eigen::VectorXd exact(n);
  for (int node = 0; node < 8; ++node) {
    const Field f = field(model.spec().mesh.points[node]);
    for (int s = 0; s < dofs; ++s) {
      const int e = model.equation(node, s);
      exact[e] = f[s];
      (node < 4 ? outer : inner).push_back(e);
    }
  }
  Eigen::MatrixXd Kii(inner.size(), inner.size()), Kib(inner.size(), outer.size());
  Eigen::VectorXd ub(outer.size());
  for (std::size_t a = 0; a < inner.size(); ++a) {
    for (std::size_t b = 0; b < inner.size(); ++b) Kii(a, b) = Kd(inner[a], inner[b]);
    for (std::size_t b = 0; b < outer.size(); ++b) Kib(a, b) = Kd(inner[a], outer[b]);
  }
  for (std::size_t b = 0; b < outer.size(); ++b) ub[b] = exact[outer[b]];
  const Eigen::VectorXd ui = Kii.fullPivLu().solve(-Kib * ub);
  double scale = 0.0, err = 0.0;
  for (std::size_t a = 0; a < inner.size(); ++a) {
    scale = std::max(scale, std::abs(exact[inner[a]]));
    err = std::max(err, std::abs(ui[a] - exact[inner[a]]));
  }
  return err / scale;
}
}  // namespace

class ShellPatch : public ::testing::TestWithParam<bool> {};

TEST_P(ShellPatch, MembranePatchIsExactOnTheDistortedMesh) {
  const double e = linear_patch_error(GetParam(), membrane);
  std::printf("membrane patch, drilling %d: relative error %.3g\n", GetParam(), e);
  EXPECT_LT(e, 1e-8) << "drilling " << GetParam();
}

TEST_P(ShellPatch, BendingPatchIsExactOnTheDistortedMesh) {
  const double e = linear_patch_error(GetParam(), bending);
  std::printf("bending patch, drilling %d: relative error %.3g\n", GetParam(), e);
  EXPECT_LT(e, 1e-8) << "drilling " << GetParam();
  EXPECT_GT(linear_patch_error(GetParam(), cubic), 1e-4);
}

INSTANTIATE_TEST_SUITE_P(FiveAndSixDofs, ShellPatch, ::testing::Bool());
