// Supports and loads in the axes users think in, checked end to end through scene files against
// cantilever beam theory (Timoshenko & Gere, Mechanics of Materials: tip deflection of a cantilever
// under an end force P, w = P L^3 / (3 E I); nu = 0, so plate and beam moduli agree):
//  - a line load q along the free edge (type = "line") is the end force P = q b;
//  - a prescribed tip displacement (type = "displacement", displacement control) needs the
//    reaction P = 3 E I w / L^3, read by a reaction probe at the clamped edge;
//  - the same clamp written in cylindrical axes about an axis through the clamped edge gives the
//    same answer as the global one.
// Two meshes each: the error against beam theory shrinks with refinement (the CB element's
// transverse shear adds a relative w_shear/w_bend = 3 E h^2 / (12 kappa G L^2) ~ 5e-5 here).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/model/simulation.h"
#include "core/scene/scene.h"

namespace {

constexpr double kE = 1.0e7, kL = 10.0, kB = 1.0, kH = 0.1;
constexpr double kI = kB * kH * kH * kH / 12.0;

std::string strip_scene(int n_length, const std::string& supports, const std::string& loads, const std::string& probes) {
  return "[scene]\nname = \"strip\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = [\"elastic\", \"hr\", \"ans\"]\n"
         "[[part]]\ngenerator = \"rectangular_plate\"\nn1 = " + std::to_string(n_length) + "\nn2 = 2\nlength = " +
         std::to_string(kL) + "\nwidth = " + std::to_string(kB) + "\n"
         "[[material]]\nyoungs_modulus = " + std::to_string(kE) + "\npoisson_ratio = 0.0\nthickness = " + std::to_string(kH) +
         "\n" + supports + loads + probes +
         "[solver]\nmethod = \"load_control\"\ninitial_step = 1.0\nmax_step = 1.0\n[output]\nframes = false\nplots = false\n";
}

const char* kClamp = "[[bc]]\ntype = \"clamped\"\nselect = \"patch_edge\"\npatch = \"plate\"\nedge = \"u=0\"\n";
const char* kTipProbe =
    "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, 1.0]\nselect = \"nearest\"\npoint = [10.0, 0.5, 0.0]\n";

ff::Metrics run_text(const std::string& text, double* tip, double* reaction = nullptr) {
  const std::string path = std::string(FF_BINARY_DIR) + "/test_out/strip_" + std::to_string(std::hash<std::string>{}(text)) + ".toml";
  std::filesystem::create_directories(std::string(FF_BINARY_DIR) + "/test_out");
  std::ofstream(path) << text;
  ff::scene::LoadedScene s = ff::scene::load_scene(path, {});
  std::atomic<bool> stop{false};
  std::vector<ff::Frame> frames;
  const ff::RunOutcome out = s.simulation->run([&](ff::Frame&& f) { frames.push_back(std::move(f)); }, stop);
  EXPECT_EQ(out.status, ff::RunStatus::completed) << out.reason;
  const ff::RunInfo& info = s.simulation->info();
  for (std::size_t k = 0; k < info.probes.size(); ++k) {
    if (info.probes[k].name == "w") *tip = frames.back().probes[k];
    if (reaction && info.probes[k].name == "reaction") *reaction = frames.back().probes[k];
  }
  return s.simulation->metrics();
}

}  // namespace

TEST(ShellSupportsLoads, LineLoadOnTheFreeEdgeIsTheEndForce) {
  const double q = 1e-3;  // per unit length along the edge: P = q b, small (linear range: w/L ~ 4e-4)
  const double w_beam = q * kB * kL * kL * kL / (3.0 * kE * kI);
  const std::string load =
      "[[load]]\ntype = \"line\"\nper_length = [0.0, 0.0, " + std::to_string(q) + "]\nselect = \"patch_edge\"\npatch = \"plate\"\nedge = \"u=1\"\n";
  double err[2];
  const int meshes[2] = {8, 32};
  for (int k = 0; k < 2; ++k) {
    double w = 0.0;
    run_text(strip_scene(meshes[k], kClamp, load, kTipProbe), &w);
    err[k] = std::abs(w / w_beam - 1.0);
    std::printf("  %d elements: w / w_beam - 1 = %+.3e\n", meshes[k], w / w_beam - 1.0);
  }
  EXPECT_LT(err[1], 2e-3) << "w/w_beam - 1 = " << err[1];
  EXPECT_LT(err[1], err[0]);
}

TEST(ShellSupportsLoads, PrescribedTipDisplacementNeedsTheBeamReaction) {
  const double w_tip = 4e-3;  // prescribed, lambda = 1
  const double p_beam = 3.0 * kE * kI * w_tip / (kL * kL * kL);
  const std::string supports = std::string(kClamp) +
                               "[[bc]]\ntype = \"displacement\"\nfix = [\"uz\"]\ndisplacement = [0.0, 0.0, " +
                               std::to_string(w_tip) + "]\nselect = \"patch_edge\"\npatch = \"plate\"\nedge = \"u=1\"\n";
  // the support force at the clamped edge, summed: it balances the force at the driven edge
  const std::string probes = std::string(kTipProbe) +
                             "[[probe]]\nname = \"reaction\"\nquantity = \"reaction\"\ndirection = [0.0, 0.0, 1.0]\n"
                             "select = \"patch_edge\"\npatch = \"plate\"\nedge = \"u=0\"\n";
  double err[2];
  const int meshes[2] = {8, 32};
  for (int k = 0; k < 2; ++k) {
    double w = 0.0, reaction = 0.0;
    run_text(strip_scene(meshes[k], supports, "", probes), &w, &reaction);
    EXPECT_NEAR(w, w_tip, 1e-12);
    // the clamp holds the strip down with -P (the driven edge pushes it up with +P)
    err[k] = std::abs(-reaction / p_beam - 1.0);
    std::printf("  %d elements: P / P_beam - 1 = %+.3e\n", meshes[k], -reaction / p_beam - 1.0);
  }
  EXPECT_LT(err[1], 2e-3) << "P/P_beam - 1 = " << err[1];
  EXPECT_LT(err[1], err[0]);
}

TEST(ShellSupportsLoads, ClampInCylindricalAxesEqualsTheGlobalClamp) {
  const std::string load =
      "[[load]]\ntype = \"line\"\nper_length = [0.0, 0.0, 1e-3]\nselect = \"patch_edge\"\npatch = \"plate\"\nedge = \"u=1\"\n";
  // axis along z through (-1, 0.5, 0): at the clamped edge x = 0 the radial, tangential and axial
  // directions are oblique to x and y, so the node bases are not the global ones
  const std::string cylindrical =
      "[[bc]]\ntype = \"fix\"\nframe = \"cylindrical\"\naxis = [0.0, 0.0, 1.0]\naxis_point = [-1.0, 0.5, 0.0]\n"
      "fix = [\"ur\", \"ut\", \"ua\", \"rr\", \"rt\", \"ra\"]\nselect = \"patch_edge\"\npatch = \"plate\"\nedge = \"u=0\"\n";
  double w_global = 0.0, w_cyl = 0.0;
  run_text(strip_scene(16, kClamp, load, kTipProbe), &w_global);
  run_text(strip_scene(16, cylindrical, load, kTipProbe), &w_cyl);
  EXPECT_GT(std::abs(w_global), 1e-4);
  EXPECT_NEAR(w_cyl, w_global, 1e-9 * std::abs(w_global));
}
