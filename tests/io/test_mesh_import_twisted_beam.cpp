// MacNeal & Harder's twisted beam ("A proposed standard set of problems to test finite element
// accuracy", Finite Elements in Analysis and Design 1 (1985) 3-20): a strip 12 long and 1.1 wide,
// twisted by 90 degrees from root to tip, h = 0.32, E = 29e6, nu = 0.22, clamped at the root, a
// unit force at the tip in the tip's plane (along its width) or normal to it: tip deflection along
// the force 5.424e-3 and 1.754e-3. Its 12 x 2 mesh of warped quads is written as an OBJ file and
// read with generator = "file", as a user would bring a mesh of their own. Measured: 0.9969 and
// 0.9862 of the references (warped elements, no locking: the references allow 5 %).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "app/io/mesh_import.h"
#include "tests/verification/generator_scene_run.h"

namespace {

void write_twisted_strip(const std::string& path) {
  const double length = 12.0, width = 1.1;
  const int nx = 12, ny = 2;
  std::ofstream f(path);
  for (int i = 0; i <= nx; ++i) {
    const double x = length * i / nx, twist = 0.5 * std::numbers::pi * i / nx;
    for (int j = 0; j <= ny; ++j) {
      const double s = -0.5 * width + width * j / ny;
      f << "v " << x << " " << s * std::cos(twist) << " " << s * std::sin(twist) << "\n";
    }
  }
  auto id = [&](int i, int j) { return i * (ny + 1) + j + 1; };  // OBJ counts from 1
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j) f << "f " << id(i, j) << " " << id(i + 1, j) << " " << id(i + 1, j + 1) << " " << id(i, j + 1) << "\n";
}

}  // namespace

TEST(TwistedBeam, TipDeflectionsMatchMacNealHarder) {
  const std::string dir = std::string(FF_BINARY_DIR) + "/test_out";
  std::filesystem::create_directories(dir);
  write_twisted_strip(dir + "/twisted_beam.obj");
  const std::string rest =
      "[[bc]]\ntype = \"clamped\"\nselect = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n"
      "[[load]]\ntype = \"force\"\ntotal = [0.0, 0.0, 1.0]\nselect = \"plane\"\npoint = [12.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n"
      "[[probe]]\nname = \"uy\"\ndirection = [0.0, 1.0, 0.0]\nselect = \"nearest\"\npoint = [12.0, 0.0, 0.0]\n"
      "[[probe]]\nname = \"uz\"\ndirection = [0.0, 0.0, 1.0]\nselect = \"nearest\"\npoint = [12.0, 0.0, 0.0]\n";
  const std::string text = ff::verification::linear_scene(
      "twisted_beam", "[\"elastic\", \"hr\", \"ans\"]", "generator = \"file\"\nfile = \"twisted_beam.obj\"\n",
      "youngs_modulus = 29.0e6\npoisson_ratio = 0.22\nthickness = 0.32", rest);
  // at the tip the width lies along z: a force along z is in the tip's plane, along y normal to it
  const auto in_plane = ff::verification::run_scene_text("twisted_beam_in_plane", text, {}, ff::io::scene_context());
  const auto out_of_plane = ff::verification::run_scene_text("twisted_beam_out_of_plane", text,
                                                             {"load[0].total=[0.0, 1.0, 0.0]"}, ff::io::scene_context());
  const double r_in = in_plane.at("uz") / 5.424e-3, r_out = out_of_plane.at("uy") / 1.754e-3;
  std::printf("twisted beam: in-plane %.4f, out-of-plane %.4f of the references\n", r_in, r_out);
  EXPECT_NEAR(r_in, 1.0, 0.05);
  EXPECT_NEAR(r_out, 1.0, 0.05);
}
