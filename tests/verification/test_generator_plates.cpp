// Generators "rectangular_plate" (placed by mesh.origin) and "folded_plate" against closed-form
// answers, each on two meshes (small loads: linear range).
// - Simply supported 1 x 2 plate under uniform pressure q: the Navier double series of a
//   Reissner-Mindlin plate with hard simple supports (w = 0, M_n = 0, no rotation along the edge):
//   w = sum_{m,n odd} 16 q / (pi^2 m n) sin(m pi x / a) sin(n pi y / b) (1 / (D k^4) + 1 / (kappa G h
//   k^2)), k^2 = (m pi / a)^2 + (n pi / b)^2 (Timoshenko & Woinowsky-Krieger, Theory of Plates and
//   Shells, 2nd ed. 1959, §30 (Navier solution) for the Kirchhoff part, whose centre value 0.01013 q a^4 / D
//   is Table 8 at b/a = 2; Reddy, Theory and Analysis of Elastic Plates and Shells, 2nd ed. 2007,
//   §10.2 for the shear part). Bilinear quads converge at second order: the error must fall by at
//   least 2.5 per halving and be below 1e-2 on the fine mesh. Measured: -1.32e-2 (8 x 16), -3.26e-3
//   (16 x 32); the series gives 0.01013 q a^4 / D for its Kirchhoff part, as Table 8.
// - Folded plate: a cantilever leg (length a along x, clamped at its end) folded up by 90 degrees
//   into a second leg (length b), pushed at the free end by a force P along x. With nu = 0 each leg
//   bends as a beam of EI = E w h^3 / 12, and the unit-load method (Timoshenko & Gere, Mechanics of
//   Materials, deflections of frames: delta = int M m / (E I) ds) gives the end displacement
//   delta = P b^3 / (3 E I) + P b^2 a / (E I). Axial and shear strains add O(h^2 / L^2) ~ 1e-4.
//   The error must fall with refinement and be below 1e-2. Measured: -2.22e-3 (8 + 4 elements along
//   the legs), -5.47e-4 (16 + 8).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "tests/verification/generator_scene_run.h"

TEST(GeneratorPlates, SimplySupportedRectangleAtAnOriginMatchesNavier) {
  const double a = 1.0, b = 2.0, h = 0.01, E = 1e7, nu = 0.3, q = 1e-4, kappa = 5.0 / 6.0;
  const double D = E * h * h * h / (12 * (1 - nu * nu)), G = E / (2 * (1 + nu)), pi = std::numbers::pi;
  double w_exact = 0.0;  // at the centre: sin(m pi / 2) sin(n pi / 2) = (-1)^((m+n)/2 - 1)
  for (int m = 1; m < 400; m += 2)
    for (int n = 1; n < 400; n += 2) {
      const double k2 = std::pow(m * pi / a, 2) + std::pow(n * pi / b, 2);
      const double sign = ((m + n) / 2 - 1) % 2 == 0 ? 1.0 : -1.0;
      w_exact += sign * 16 * q / (pi * pi * m * n) * (1 / (D * k2 * k2) + 1 / (kappa * G * h * k2));
    }
  std::printf("Navier: w_centre = %.8e = %.5f q a^4 / D (Table 8, Kirchhoff: 0.01013)\n", w_exact, w_exact * D / (q * a * a * a * a));
  double err[2];
  const int n[2] = {8, 16};
  for (int k = 0; k < 2; ++k) {
    // x in [2, 3], y in [-1, 1], z = 0.5: centre (2.5, 0, 0.5)
    const std::string mesh = "generator = \"rectangular_plate\"\nlength = 1.0\nwidth = 2.0\norigin = [2.0, -1.0, 0.5]\nn1 = " +
                             std::to_string(n[k]) + "\nn2 = " + std::to_string(2 * n[k]) + "\n";
    std::string rest;
    for (const char* e : {"x_min", "x_max"})
      rest += std::string("[[bc]]\ntype = \"fix\"\nfix = [\"ux\", \"uy\", \"uz\", \"rx\"]\nselect = \"patch_edge\"\npatch = "
                          "\"plate\"\nedge = \"") + e + "\"\n";
    for (const char* e : {"y_min", "y_max"})
      rest += std::string("[[bc]]\ntype = \"fix\"\nfix = [\"ux\", \"uy\", \"uz\", \"ry\"]\nselect = \"patch_edge\"\npatch = "
                          "\"plate\"\nedge = \"") + e + "\"\n";
    rest += "[[load]]\ntype = \"pressure\"\npressure = 1e-4\nselect = \"all\"\n"
            "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, 1.0]\nselect = \"nearest\"\npoint = [2.5, 0.0, 0.5]\n";
    const auto probes = ff::verification::run_scene_text(
        "generator_plate_" + std::to_string(n[k]),
        ff::verification::linear_scene("plate", "[\"elastic\", \"hr\", \"ans\"]", mesh,
                                       "youngs_modulus = 1e7\npoisson_ratio = 0.3\nthickness = 0.01", rest));
    err[k] = std::abs(probes.at("w") / w_exact - 1.0);
    std::printf("plate %d x %d: w = %.8e, rel. error %+.3e\n", n[k], 2 * n[k], probes.at("w"), probes.at("w") / w_exact - 1.0);
  }
  EXPECT_LT(err[1], 1e-2);
  EXPECT_GT(err[0] / err[1], 2.5);
}

TEST(GeneratorPlates, FoldedCantileverEndDisplacementMatchesFrameTheory) {
  const double a = 1.0, b = 0.5, w = 0.1, h = 0.01, E = 1e7, P = 1e-5;
  const double EI = E * w * h * h * h / 12;
  const double delta_exact = P * b * b * b / (3 * EI) + P * b * b * a / EI;
  double err[2];
  const int n1[2] = {8, 16};
  for (int k = 0; k < 2; ++k) {
    const std::string mesh = "generator = \"folded_plate\"\nlength = 1.0\nlength2 = 0.5\nwidth = 0.1\nfold_angle = 90.0\nn1 = " +
                             std::to_string(n1[k]) + "\nn3 = " + std::to_string(n1[k] / 2) + "\nn2 = " + std::to_string(k + 1) + "\n";
    const std::string rest =
        "[[bc]]\ntype = \"clamped\"\nselect = \"patch_edge\"\npatch = \"leg1\"\nedge = \"end\"\n"
        "[[load]]\ntype = \"force\"\ntotal = [1e-5, 0.0, 0.0]\nselect = \"patch_edge\"\npatch = \"leg2\"\nedge = \"end\"\n"
        "[[probe]]\nname = \"delta\"\ndirection = [1.0, 0.0, 0.0]\nselect = \"nearest\"\npoint = [1.0, 0.0, 0.5]\n";
    const auto probes = ff::verification::run_scene_text(
        "generator_folded_" + std::to_string(n1[k]),
        ff::verification::linear_scene("folded", "[\"elastic\", \"hr\", \"ans\"]", mesh,
                                       "youngs_modulus = 1e7\npoisson_ratio = 0.0\nthickness = 0.01", rest));
    err[k] = std::abs(probes.at("delta") / delta_exact - 1.0);
    std::printf("folded plate %d + %d elements: delta = %.8e (frame theory %.8e), rel. error %+.3e\n", n1[k], n1[k] / 2,
                probes.at("delta"), delta_exact, probes.at("delta") / delta_exact - 1.0);
  }
  EXPECT_LT(err[1], 1e-2);
  EXPECT_LT(err[1], err[0]);
}
