// Generator "spherical_cap" closed at the pole (the pole-free core + ring mesh), a hemisphere under
// internal pressure, against the membrane solution of a thin sphere:
//   w = p R^2 (1 - nu) / (2 E h)   (Timoshenko & Woinowsky-Krieger, Theory of Plates and Shells,
//   2nd ed. 1959, §105: N_phi = N_theta = p R / 2, eps = w / R = N (1 - nu) / (E h)).
// The equator z = 0 is a symmetry plane (the hemisphere is half of a pressurised sphere, which is
// in a pure membrane state); the pole cannot move across the axis (ux = uy = 0) and the equator
// point (R, 0, 0) not along y: by symmetry neither moves so anyway, and the rigid motions go.
// Load small (w / R = 3.5e-6). Faceting errors are O(h^2) in the element size; bending adds
// O(h^2 / R^2). The error at the pole (inside the core patch) and at the equator (ring) must fall
// by at least 3 from the coarse (32 elements around, 8 across the ring) to the fine mesh (64, 16),
// and be below 1e-2 there. Measured: pole +4.5e-3 -> +1.1e-3, equator -1.8e-3 -> -2.2e-4. (A
// 16 x 4 mesh is not yet in the asymptotic range: +9.2e-2 at the pole, whose core quads are then
// 2 per half-side.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/verification/generator_scene_run.h"

TEST(GeneratorSphericalCap, ClosedHemisphereUnderInternalPressureGivesTheMembraneSolution) {
  const double R = 1.0, h = 0.01, E = 1e7, nu = 0.3, p = 1.0;
  const double w_exact = p * R * R * (1 - nu) / (2 * E * h);
  double err_pole[2], err_equator[2];
  const int rim[2] = {32, 64}, ring[2] = {8, 16};
  for (int k = 0; k < 2; ++k) {
    const std::string mesh = "generator = \"spherical_cap\"\nradius = 1.0\npolar_end = 90.0\nn1 = " + std::to_string(ring[k]) +
                             "\nn2 = " + std::to_string(rim[k]) + "\n";
    const std::string rest =
        "[[bc]]\ntype = \"symmetry\"\nselect = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n"
        "[[bc]]\ntype = \"fix\"\nfix = [\"ux\", \"uy\"]\nselect = \"nearest\"\npoint = [0.0, 0.0, 1.0]\n"
        "[[bc]]\ntype = \"fix\"\nfix = [\"uy\"]\nselect = \"nearest\"\npoint = [1.0, 0.0, 0.0]\n"
        "[[load]]\ntype = \"pressure\"\npressure = " + std::to_string(p) + "\nselect = \"all\"\n"
        "[[probe]]\nname = \"pole\"\ndirection = [0.0, 0.0, 1.0]\nselect = \"nearest\"\npoint = [0.0, 0.0, 1.0]\n"
        "[[probe]]\nname = \"equator\"\ndirection = [0.0, 1.0, 0.0]\nselect = \"nearest\"\npoint = [0.0, 1.0, 0.0]\n";
    const auto probes = ff::verification::run_scene_text(
        "generator_cap_" + std::to_string(rim[k]),
        ff::verification::linear_scene("cap", "[\"elastic\", \"hr\", \"ans\"]", mesh,
                                       "youngs_modulus = 1e7\npoisson_ratio = 0.3\nthickness = 0.01", rest));
    err_pole[k] = std::abs(probes.at("pole") / w_exact - 1.0);
    err_equator[k] = std::abs(probes.at("equator") / w_exact - 1.0);
    std::printf("hemisphere %2d x %d: w_pole / w - 1 = %+.3e, w_equator / w - 1 = %+.3e\n", rim[k], ring[k],
                probes.at("pole") / w_exact - 1.0, probes.at("equator") / w_exact - 1.0);
  }
  EXPECT_LT(err_pole[1], 1e-2);
  EXPECT_LT(err_equator[1], 1e-2);
  EXPECT_GT(err_pole[0] / err_pole[1], 3.0);
  EXPECT_GT(err_equator[0] / err_equator[1], 3.0);
}
