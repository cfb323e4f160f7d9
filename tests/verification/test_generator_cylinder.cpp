// Generator "cylinder" (core/scene/mesh_generator_keys.h), closed 360 degrees (merged seam), under
// internal pressure with free ends, against the membrane hoop solution of a thin cylinder:
//   w = p R^2 / (E h)   (Timoshenko & Woinowsky-Krieger, Theory of Plates and Shells, 2nd ed. 1959,
//   §114, the symmetrically loaded cylindrical shell: N_theta = p R, N_x = 0 with free ends, so
//   eps_theta = w / R = p R / (E h)).
// Supports that restrain nothing of that state: the bottom edge holds only the tangential and
// axial directions (cylindrical axes), which removes the six rigid-body motions. The load is small
// (w / R = 1e-5: linear range). The faceted mesh is a polygon of n1 sides whose error in the hoop
// stiffness is O((pi / n1)^2); the bending part of the shell adds O(h^2 / R^2) ~ 1e-5. So: the
// error must fall by about 4 from 16 to 32 sides (at least 3), and be below 1e-2 on the fine one.
// Measured: -1.66e-2 (16 sides), -4.12e-3 (32).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "tests/verification/generator_scene_run.h"

TEST(GeneratorCylinder, ClosedCylinderUnderInternalPressureGivesTheHoopSolution) {
  const double R = 1.0, L = 2.0, h = 0.01, E = 1e7, p = 1.0;
  const double w_exact = p * R * R / (E * h);
  double err[2];
  const int sides[2] = {16, 32};
  for (int k = 0; k < 2; ++k) {
    const std::string mesh = "generator = \"cylinder\"\nradius = " + std::to_string(R) + "\nlength = " + std::to_string(L) +
                             "\nn1 = " + std::to_string(sides[k]) + "\nn2 = 2\n";
    const std::string rest =
        "[[bc]]\ntype = \"fix\"\nframe = \"cylindrical\"\naxis = [0.0, 0.0, 1.0]\naxis_point = [0.0, 0.0, 0.0]\n"
        "fix = [\"ut\", \"ua\"]\nselect = \"patch_edge\"\npatch = \"cylinder\"\nedge = \"bottom\"\n"
        "[[load]]\ntype = \"pressure\"\npressure = " + std::to_string(p) + "\nselect = \"all\"\n"
        "[[probe]]\nname = \"w\"\ndirection = [1.0, 0.0, 0.0]\nselect = \"nearest\"\npoint = [1.0, 0.0, 1.0]\n";
    const auto probes = ff::verification::run_scene_text(
        "generator_cylinder_" + std::to_string(sides[k]), ff::verification::linear_scene("cyl", "[\"elastic\", \"hr\", \"ans\"]", mesh,
                                                              "youngs_modulus = 1e7\npoisson_ratio = 0.3\nthickness = 0.01", rest));
    const double w = probes.at("w");
    err[k] = std::abs(w / w_exact - 1.0);
    std::printf("cylinder %2d sides: w = %.8e, w / (p R^2 / E h) - 1 = %+.3e\n", sides[k], w, w / w_exact - 1.0);
  }
  EXPECT_LT(err[1], 1e-2);
  EXPECT_GT(err[0] / err[1], 3.0) << "not converging at second order";
}

// The Scordelis-Lo roof (MacNeal & Harder, "A proposed standard set of problems to test finite
// element accuracy", Finite Elements in Analysis and Design 1 (1985) 3-20, problem 3): a
// cylindrical panel R = 25, span 50, 80 degrees wide, h = 0.25, E = 4.32e8, nu = 0, under its
// self-weight 90 per unit area (a `surface` load, straight down), held by rigid diaphragms at the
// curved ends (no motion in their plane), free along the straight edges. The vertical deflection
// at the middle of a free edge: 0.3024, the value element studies normalize with (Belytschko et
// al., CMAME 51 (1985) 221-258; MacNeal & Harder quote 0.3086 from deep-shell theory). Written
// as a user would from the manual: the quarter with two symmetry planes, the `cylinder` generator
// about y with azimuth 0 at the crown. Small load factor (linear range). Measured: 0.30445 (8 x 8,
// +0.68 %), 0.30176 (16 x 16, -0.21 %), 0.30135 (32 x 32).
TEST(GeneratorCylinder, ScordelisLoRoofUnderSelfWeightMatchesTheBenchmark) {
  const double reference = 0.3024, lambda = 1e-3;
  double err[2];
  const int n[2] = {8, 16};
  for (int k = 0; k < 2; ++k) {
    const std::string mesh = "generator = \"cylinder\"\nradius = 25.0\nlength = 25.0\naxis = [0.0, 1.0, 0.0]\n"
                             "reference = [0.0, 0.0, 1.0]\nstart_angle = 0.0\nend_angle = 40.0\nn1 = " +
                             std::to_string(n[k]) + "\nn2 = " + std::to_string(n[k]) + "\n";
    const std::string rest =
        "[[bc]]\ntype = \"fix\"\nfix = [\"ux\", \"uz\"]\nselect = \"plane\"\npoint = [0.0, 25.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\n"
        "[[bc]]\ntype = \"symmetry\"\nselect = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\n"
        "[[bc]]\ntype = \"symmetry\"\nselect = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n"
        "[[load]]\ntype = \"surface\"\nper_area = [0.0, 0.0, -90.0]\nselect = \"all\"\n"
        "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, -1.0]\nselect = \"nearest\"\npoint = [16.0696902, 0.0, 19.1511110]\n";
    const auto probes = ff::verification::run_scene_text(
        "scordelis_lo_" + std::to_string(n[k]),
        ff::verification::linear_scene("scordelis_lo", "[\"elastic\", \"hr\", \"ans\"]", mesh,
                                       "youngs_modulus = 4.32e8\npoisson_ratio = 0.0\nthickness = 0.25", rest),
        {"solver.end=" + std::to_string(lambda), "solver.initial_step=" + std::to_string(lambda),
         "solver.max_step=" + std::to_string(lambda)});
    const double w = probes.at("w") / lambda;
    err[k] = w / reference - 1.0;
    std::printf("Scordelis-Lo roof %d x %d: w = %.5f, rel. error %+.3e\n", n[k], n[k], w, err[k]);
  }
  EXPECT_LT(std::abs(err[0]), 2e-2);
  EXPECT_LT(std::abs(err[1]), 5e-3);
  EXPECT_LT(std::abs(err[1]), std::abs(err[0]));
}

// The pinched cylinder with rigid end diaphragms (Belytschko et al., CMAME 51 (1985) 221-258;
// MacNeal & Harder 1985): R = 300, L = 600, h = 3, E = 3e6, nu = 0.3, two opposite radial forces
// P = 1 at the middle; the deflection under a force is 1.8248e-5 (the series solution those papers
// quote). One octant with three symmetry planes, the diaphragm holding the radial and tangential
// motion (cylindrical axes), P/4 at the corner, 6 DoF per node (drilling). Bilinear shells converge
// slowly here (a point load on a thin shell): measured 0.9377 (16 x 16) and 0.9913 (32 x 32) of
// the reference.
TEST(GeneratorCylinder, PinchedCylinderDeflectionConvergesToTheSeriesSolution) {
  const double reference = 1.8248e-5;
  double ratio[2];
  const int n[2] = {16, 32};
  for (int k = 0; k < 2; ++k) {
    const std::string mesh = "generator = \"cylinder\"\nradius = 300.0\nlength = 300.0\nstart_angle = 0.0\n"
                             "end_angle = 90.0\nn1 = " + std::to_string(n[k]) + "\nn2 = " + std::to_string(n[k]) + "\n";
    std::string rest;
    for (const char* normal : {"[0.0, 1.0, 0.0]", "[1.0, 0.0, 0.0]", "[0.0, 0.0, 1.0]"})
      rest += std::string("[[bc]]\ntype = \"symmetry\"\nselect = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = ") + normal + "\n";
    rest += "[[bc]]\ntype = \"fix\"\nframe = \"cylindrical\"\naxis = [0.0, 0.0, 1.0]\naxis_point = [0.0, 0.0, 0.0]\n"
            "fix = [\"ur\", \"ut\"]\nselect = \"plane\"\npoint = [0.0, 0.0, 300.0]\nnormal = [0.0, 0.0, 1.0]\n"
            "[[load]]\ntype = \"force\"\ntotal = [-0.25, 0.0, 0.0]\nselect = \"nearest\"\npoint = [300.0, 0.0, 0.0]\n"
            "[[probe]]\nname = \"w\"\ndirection = [-1.0, 0.0, 0.0]\nselect = \"nearest\"\npoint = [300.0, 0.0, 0.0]\n";
    const auto probes = ff::verification::run_scene_text(
        "pinched_cylinder_" + std::to_string(n[k]),
        ff::verification::linear_scene("pinched_cylinder", "[\"elastic\", \"hr\", \"ans\", \"drilling\"]", mesh,
                                       "youngs_modulus = 3.0e6\npoisson_ratio = 0.3\nthickness = 3.0", rest));
    ratio[k] = probes.at("w") / reference;
    std::printf("pinched cylinder %d x %d: w = %.6e = %.4f of the reference\n", n[k], n[k], probes.at("w"), ratio[k]);
  }
  EXPECT_GT(ratio[0], 0.90);
  EXPECT_LT(std::abs(ratio[1] - 1.0), 0.02);
  EXPECT_LT(std::abs(ratio[1] - 1.0), 0.25 * std::abs(ratio[0] - 1.0));
}
