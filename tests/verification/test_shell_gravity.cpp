// Gravity in a static analysis (issue 31: loads that work in every analysis): the effect gravity
// weighs every part, rho h g per unit area of its reference mid-surface, as the consistent nodal
// forces of a dead surface load. Checked against (1) the same structure under an explicit
// [[load]] of type surface with that per_area (the same forces: equal to round-off), and (2) a
// clamped strip's self-weight tip deflection, w = q L^4 / (8 E I) with q = rho h g b (Euler-
// Bernoulli cantilever under a uniform load, e.g. Timoshenko & Gere, Mechanics of Materials,
// Appendix G): with nu = 0 and 40 elements along, measured 1.0001 of it.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "core/scene/scene.h"

namespace {

const char* kStrip = R"([[material]]
youngs_modulus = 70e9
poisson_ratio = 0.0
thickness = 0.01
density = 2700.0

[[part]]
name = "strip"
generator = "rectangular_plate"
length = 1.0
width = 0.1
n1 = 40
n2 = 2

[[bc]]
type = "clamped"
select = "patch_edge"
patch = "strip"
edge = "x_min"

[[probe]]
name = "tip_w"
select = "nearest"
point = [1.0, 0.05, 0.0]
direction = [0.0, 0.0, 1.0]

[[metric]]
name = "tip_w"
kind = "final"
probe = "tip_w"

[solver]
method = "linear"

[output]
frames = false
plots = false
)";

double tip_w(const std::string& name, const std::string& text) {
  const std::string dir = std::string(FF_BINARY_DIR) + "/test_out/shell_gravity";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/" + name + ".toml";
  std::ofstream(path) << text;
  ff::scene::LoadedScene s = ff::scene::load_scene(path, {});
  std::atomic<bool> stop{false};
  const ff::RunOutcome o = s.simulation->run([](ff::Frame&&) {}, stop);
  EXPECT_EQ(o.status, ff::RunStatus::completed) << o.reason;
  for (const auto& [k, v] : s.simulation->metrics())
    if (k == "tip_w") return v;
  return NAN;
}

TEST(ShellGravity, StaticSelfWeightIsTheSurfaceLoadOfDensityThicknessAndG) {
  const std::string head = "[scene]\nname = \"strip\"\nmodel = \"shell\"\nanalysis = \"static\"\n";
  const double by_gravity = tip_w("gravity", head + "effects = [\"elastic\", \"hr\", \"ans\", \"gravity\"]\n" +
                                                 "[gravity]\ng = [0.0, 0.0, -9.81]\n" + kStrip);
  // the same weight written as a load: 2700 x 0.01 x 9.81 = 264.87 N/m^2 downwards
  const double by_load = tip_w("surface", head + "effects = [\"elastic\", \"hr\", \"ans\"]\n" +
                                              "[[load]]\ntype = \"surface\"\nselect = \"all\"\nper_area = [0.0, 0.0, -264.87]\n" +
                                              kStrip);
  EXPECT_NEAR(by_gravity / by_load, 1.0, 1e-12) << by_gravity << " against " << by_load;
  const double E = 70e9, b = 0.1, h = 0.01, L = 1.0, q = 2700.0 * h * 9.81 * b, I = b * h * h * h / 12.0;
  const double beam = -q * std::pow(L, 4) / (8.0 * E * I);
  std::printf("self-weight tip deflection %.6g m, beam theory %.6g m (ratio %.4f)\n", by_gravity, beam, by_gravity / beam);
  EXPECT_NEAR(by_gravity / beam, 1.0, 0.005);
}

TEST(ShellGravity, GravityWithoutADensityIsRefusedAtTheMaterial) {
  std::string strip = kStrip;
  strip.erase(strip.find("density = 2700.0\n"), std::string("density = 2700.0\n").size());
  const std::string dir = std::string(FF_BINARY_DIR) + "/test_out/shell_gravity";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/no_density.toml";
  std::ofstream(path) << "[scene]\nname = \"strip\"\nmodel = \"shell\"\nanalysis = \"static\"\n"
                         "effects = [\"elastic\", \"gravity\"]\n" + strip;
  try {
    ff::scene::load_scene(path, {});
    ADD_FAILURE() << "gravity without a density was accepted";
  } catch (const ff::scene::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("material.density"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("material[0]"), std::string::npos) << e.what();
  }
}

}  // namespace
