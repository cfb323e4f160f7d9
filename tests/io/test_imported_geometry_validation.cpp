// What imported geometry costs in accuracy (issue 32; the figures and their explanation are in
// docs/validation/imported-geometry.md): the same plate and the same hemisphere meshed by the
// generator (structured quads), by Gmsh from a CAD surface or .geo script (unstructured quads) and
// as Gmsh triangle meshes split into quads by FlexFrame; the plate with a hole from a .geo against
// a much finer mesh of the same part and against Kirsch's infinite plate.
// Meshes: assets/geometry/*.geo (meshed through the Gmsh library in the run), and the triangle
// meshes tests/io/data/gmsh/{clamped_plate,hemisphere}_tri_*.msh written from those scripts by the
// gmsh program (the commands are in the scripts' headers).
// Every tolerance below is the measured error of the mesh in question with a margin of about a
// quarter; none is there to let a result pass.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "app/io/mesh_import.h"
#include "core/mesh/shell_mesh.h"
#include "core/scene/scene.h"

namespace {

std::string scene_path(const std::string& name) { return std::string(FF_SOURCE_DIR) + "/assets/scenes/" + name + ".toml"; }
std::string msh(const std::string& name) { return std::string(FF_SOURCE_DIR) + "/tests/io/data/gmsh/" + name; }

struct SceneRun {
  std::map<std::string, double> metrics;
  int nodes = 0, quads = 0;
};

// loads a bundled scene with overrides (mesh files through ff::io::scene_context()), runs it, and
// returns its metrics and the size of its mesh
SceneRun run(const std::string& scene, const std::vector<std::string>& overrides) {
  SceneRun r;
  ff::scene::LoadedScene s = ff::scene::load_scene(scene_path(scene), overrides, ff::io::scene_context());
  std::atomic<bool> stop{false};
  const ff::RunOutcome o = s.simulation->run([](ff::Frame&&) {}, stop);
  EXPECT_EQ(o.status, ff::RunStatus::completed) << scene << ": " << o.reason;
  for (const auto& [k, v] : s.simulation->metrics()) r.metrics[k] = v;
  r.nodes = static_cast<int>(s.simulation->info().mesh.point_count());
  r.quads = static_cast<int>(s.simulation->info().mesh.quads.size() / 4);
  return r;
}

double metric(const SceneRun& r, const std::string& name) {
  const auto it = r.metrics.find(name);
  EXPECT_NE(it, r.metrics.end()) << "no metric " << name;
  return it == r.metrics.end() ? NAN : it->second;
}

}  // namespace

// ---- the clamped plate under pressure ----------------------------------------------------------
// Timoshenko & Woinowsky-Krieger, Theory of Plates and Shells (2nd ed., 1959), §44, Table 35:
// w_max = 0.00126 q a^4 / D (b/a = 1, nu = 0.3), 6.552e-5 m for assets/scenes/clamped_plate_pressure.toml.
// The CB shell (Reissner-Mindlin) converges to 0.61 % above it at a/h = 100 (the generator's 64 x 64
// mesh: 6.5920e-5; docs/validation/shell-statics.md), so each mesh's own error is measured against
// the generator's 32 x 32 value (6.5900e-5, 0.03 % from 64 x 64). Measured at about 300 nodes:
// generator 16 x 16 -0.12 %, Gmsh quads (mesh_size 0.0625, 332 nodes) -0.35 %, 116 Gmsh triangles
// split into 348 quads (377 nodes) -0.30 %. Coarser (about 100 nodes): -0.6 % (8 x 8), -2.0 %
// (0.125: 96 nodes), -1.8 % (split, 97 nodes).
TEST(ImportedGeometryAccuracy, ClampedPlateUnstructuredAndSplitTriangleMeshesNearTheStructuredOne) {
  const double w_converged = metric(run("clamped_plate_pressure", {"part[0].n1=32", "part[0].n2=32"}), "w_centre");
  const double table = 0.00126 * 1000.0 / (2.1e11 * 1e-6 / (12 * (1 - 0.09)));
  EXPECT_NEAR(w_converged / table - 1, 0.0061, 0.001) << "the element's converged value moved";

  const SceneRun generated = run("clamped_plate_pressure", {"part[0].n1=16", "part[0].n2=16"});
  const SceneRun gmsh_quads = run("clamped_plate_pressure_geo", {});
  const SceneRun split = run("clamped_plate_pressure_geo", {"part[0].file=" + msh("clamped_plate_tri_0p15.msh"), "part[0].mesh_size=0"});
  const SceneRun split_coarse = run("clamped_plate_pressure_geo", {"part[0].file=" + msh("clamped_plate_tri_0p25.msh"), "part[0].mesh_size=0"});
  struct Row {
    const char* what;
    const SceneRun& r;
    double tolerance;
  };
  for (const Row& row : {Row{"generator 16 x 16", generated, 0.002}, Row{"Gmsh quads 0.0625", gmsh_quads, 0.0044},
                         Row{"split triangles 0.15", split, 0.004}}) {
    const double w = metric(row.r, "w_centre");
    std::printf("clamped plate, %-22s %4d nodes %4d quads: w = %.5e, %+.2f %% of the converged value, %+.2f %% of Table 35\n",
                row.what, row.r.nodes, row.r.quads, w, 100 * (w / w_converged - 1), 100 * (w / table - 1));
    EXPECT_NEAR(w / w_converged, 1.0, row.tolerance) << row.what;
    EXPECT_NEAR(w / table, 1.0, 0.01) << row.what;  // the element's +0.61 % and the mesh's error
  }
  // each of the 116 triangles into three quads
  EXPECT_EQ(split.quads, 3 * 116);
  // the split mesh converges: the coarser one (40 triangles, 137 nodes) is further off (-1.3 %)
  EXPECT_GT(std::abs(metric(split_coarse, "w_centre") / w_converged - 1), std::abs(metric(split, "w_centre") / w_converged - 1));
}

// ---- the hemisphere with an 18 degree hole -----------------------------------------------------
// Sze, Liu & Lo, Finite Elements in Analysis and Design 40 (2004) 1551-1569, §3.4 (ABAQUS S4R;
// assets/reference/sze2004_34_hemisphere_18deg_hole.csv): at F = 400 the outward-loaded point
// moves 4.067 and the inward-loaded one 8.178. Full load path to F = 400 (about 0.3-1.5 s a mesh).
// All meshes run with the drilling effect (6 DoF): the directors of a triangle mesh read from a
// .msh are averaged from its facets, and at a node on a symmetry plane they lean out of the plane
// (the facets lie on one side only: by 0.10 at size 2.6), which a 5-DoF node cannot carry; the
// generator's and the CAD mesh's results change by less than 1e-3 with it.
// Measured at F = 400 (outward / inward):
//   generator 16 x 16 (289 nodes)                          -0.40 / -0.68 %
//   Gmsh quads from the CAD sphere, size 1.0 (245 nodes)   -2.9 / -5.8 %
//   Gmsh quads from the CAD sphere, size 0.7 (435 nodes)   -0.53 / -1.1 %
//   Gmsh triangles split by FlexFrame, 2.6 (221 nodes)     -9.4 / -16.2 %
//   Gmsh triangles split by FlexFrame, 2.0 (347 nodes)     -5.3 / -10.5 %
//   Gmsh triangles split by FlexFrame, 1.4 (653 nodes)     -2.3 / -4.4 %
//   the 2.0 triangles split by Gmsh onto the sphere (347)  -2.1 / -3.7 %
// The split costs through its geometry: FlexFrame puts the new nodes at the straight edges'
// midpoints and the flat triangles' centroids (imported_surface.md S1-S2), so the split mesh keeps
// the facets of the coarse triangles (a sag of L^2 / (8 R) = 0.05 at L = 2, more than the
// thickness 0.04); the same triangles split with the new nodes on the sphere (Gmsh's
// Mesh.SubdivisionAlgorithm = 1 on the CAD surface, the same nodes and quads) lose most of it.
TEST(ImportedGeometryAccuracy, HemisphereFromCadQuadsAndSplitTrianglesAgainstSze) {
  const std::string drilling = "scene.effects=[\"elastic\", \"hr\", \"ans\", \"drilling\"]";
  const auto file = [&](const std::string& name) {
    return std::vector<std::string>{drilling, "part[0].file=" + msh(name), "part[0].mesh_size=0"};
  };
  struct Row {
    const char* what;
    SceneRun r;
    double tolerance;  // on the larger of the two relative errors at F = 400
  };
  std::vector<Row> rows;
  rows.push_back({"generator 16 x 16", run("hemisphere_18deg_h004", {drilling}), 0.009});
  rows.push_back({"Gmsh quads 1.0", run("hemisphere_18deg_cad", {drilling, "part[0].mesh_size=1.0"}), 0.072});
  rows.push_back({"Gmsh quads 0.7", run("hemisphere_18deg_cad", {drilling}), 0.014});
  rows.push_back({"split triangles 2.6", run("hemisphere_18deg_cad", file("hemisphere_tri_2p6.msh")), 0.2});
  rows.push_back({"split triangles 2.0", run("hemisphere_18deg_cad", file("hemisphere_tri_2p0.msh")), 0.13});
  rows.push_back({"split triangles 1.4", run("hemisphere_18deg_cad", file("hemisphere_tri_1p4.msh")), 0.055});
  rows.push_back({"2.0 split onto the sphere", run("hemisphere_18deg_cad", file("hemisphere_tri_2p0_subdivided_on_cad.msh")), 0.046});
  std::vector<double> worst;
  for (const Row& row : rows) {
    const double out = metric(row.r, "disp_outward_point_F400") / 4.067 - 1;
    const double in = metric(row.r, "disp_inward_point_F400") / 8.178 - 1;
    std::printf("hemisphere, %-26s %4d nodes %4d quads: F = 400 outward %+.2f %%, inward %+.2f %%\n", row.what, row.r.nodes,
                row.r.quads, 100 * out, 100 * in);
    worst.push_back(std::max(std::abs(out), std::abs(in)));
    EXPECT_LT(worst.back(), row.tolerance) << row.what;
  }
  // the CAD quads and the split triangles converge; the split onto the sphere (same topology as
  // "split triangles 2.0") is more than twice as close as FlexFrame's flat split
  EXPECT_LT(worst[2], worst[1]);
  EXPECT_LT(worst[4], worst[3]);
  EXPECT_LT(worst[5], worst[4]);
  EXPECT_EQ(rows[6].r.nodes, rows[4].r.nodes);
  EXPECT_LT(2 * worst[6], worst[4]);
}

// ---- the plate with a central hole under uniaxial tension --------------------------------------
// Kirsch (Z. VDI 42 (1898) 797-807): the stresses of an infinite plate with a hole of radius a
// under a remote tension sigma along x (as in Barber, Elasticity, 2nd ed., eqs 8.74-8.76)
//   s_rr = sigma/2 (1 - a^2/r^2) + sigma/2 (1 - 4 a^2/r^2 + 3 a^4/r^4) cos 2t
//   s_tt = sigma/2 (1 + a^2/r^2) - sigma/2 (1 + 3 a^4/r^4) cos 2t
//   s_rt = -sigma/2 (1 + 2 a^2/r^2 - 3 a^4/r^4) sin 2t
// come in plane stress (kappa = (3 - nu)/(1 + nu), mu = E / (2 (1 + nu))) from the displacements
//   u_r = sigma/(4 mu) [r ((kappa - 1)/2 + cos 2t) + a^2/r (1 + (1 + kappa) cos 2t) - a^4/r^3 cos 2t]
//   u_t = -sigma/(4 mu) [r + (kappa - 1) a^2/r + a^4/r^3] sin 2t
// (the strains of this field give the stresses above through Hooke's law exactly; checked
// symbolically, docs/validation/imported-geometry.md). At the hole's edge they are independent of nu:
//   u_r(a, t) = sigma a / E (1 + 2 cos 2t),  u_t(a, t) = -2 sigma a / E sin 2t,
// and on the axes u_x(r, 0) = sigma (2 r^4 + (5 + nu) a^2 r^2 - (1 + nu) a^4) / (2 E r^3),
// u_y(0, r) = sigma ((1 + nu) a^4 - (3 - nu) a^2 r^2 - 2 nu r^4) / (2 E r^3).
// The plate of assets/geometry/plate_with_hole.geo is finite (d/W = 0.1, L/b = 2): Howland's
// finite-width solution (Phil. Trans. R. Soc. A 229 (1930) 49-86) raises the peak stress from 3 to
// about 3.03 of the gross stress there (Heywood's fit K_net = 2 + (1 - d/W)^3, over 1 - d/W), and the fine mesh below moves the hole's edge 1.2 % (u_x)
// and 3.2 % (u_y) more than Kirsch's infinite plate; with the hole halved (d/W = 0.05) these
// fall to 0.2-0.4 % and 0.6 % (measured: the (a/b)^2 of a finite-width correction).
// Mesh error against the fine mesh (size 0.125, hole 0.0125: 16 257 quads; the 16 138 quads of an
// earlier mesh near 0.125 agree with it to 0.05 %): the bundled scene's mesh (1.5, hole 0.2:
// 148 quads) 1.0-7.1 %, size 0.5 with hole 0.05 (1086 quads) 0.3-1.5 %. (Measured again when
// part.mesh_size came to set the size at every point of the geometry, not only cap it: Gmsh's
// grading from the hole outwards changed, and the coarse mesh's worst probe went from 4.4 % to
// 7.1 %; the fine and medium meshes moved by less than 0.2 %.)
namespace {
struct Kirsch {
  double ux_hole_0, uy_hole_90, ux_hole_45, uy_hole_45, ux_axis_2a, uy_axis_2a;
};
Kirsch kirsch(double sigma, double a, double E, double nu) {
  const double s = sigma * a / E, r = 2 * a;
  return {3 * s,
          -s,
          3 * s / std::sqrt(2.0),
          -s / std::sqrt(2.0),
          sigma * (2 * std::pow(r, 4) + (5 + nu) * a * a * r * r - (1 + nu) * std::pow(a, 4)) / (2 * E * r * r * r),
          sigma * ((1 + nu) * std::pow(a, 4) - (3 - nu) * a * a * r * r - 2 * nu * std::pow(r, 4)) / (2 * E * r * r * r)};
}
}  // namespace

TEST(ImportedGeometryAccuracy, PlateWithAHoleFromAGeoScriptAgainstAFineMeshAndKirsch) {
  const Kirsch k = kirsch(1.0e6, 1.0, 2.1e11, 0.3);
  const SceneRun fine = run("plate_with_hole_geo", {"part[0].mesh_size=0.125", "part[0].local_sizes=[0.0125]"});
  const SceneRun medium = run("plate_with_hole_geo", {"part[0].mesh_size=0.5", "part[0].local_sizes=[0.05]"});
  const SceneRun coarse = run("plate_with_hole_geo", {});
  const std::vector<std::pair<std::string, double>> probes = {
      {"ux_hole_0", k.ux_hole_0},   {"uy_hole_90", k.uy_hole_90}, {"ux_hole_45", k.ux_hole_45},
      {"uy_hole_45", k.uy_hole_45}, {"ux_axis_2a", k.ux_axis_2a}, {"uy_axis_2a", k.uy_axis_2a}};
  double medium_worst = 0, coarse_worst = 0;
  for (const auto& [name, kirsch_value] : probes) {
    const double f = metric(fine, name), m = metric(medium, name), c = metric(coarse, name);
    std::printf("plate with a hole, %-10s fine %.5e (Kirsch %+.2f %%), medium %+.2f %%, coarse %+.2f %% of the fine mesh\n",
                name.c_str(), f, 100 * (f / kirsch_value - 1), 100 * (m / f - 1), 100 * (c / f - 1));
    // the finite width: u_x 1.2 %, u_y 3.0-3.2 % beyond Kirsch's infinite plate, never below it
    const bool along_load = name[1] == 'x';
    EXPECT_GT(f / kirsch_value - 1, 0.0) << name;
    EXPECT_LT(f / kirsch_value - 1, along_load ? 0.015 : 0.04) << name;
    medium_worst = std::max(medium_worst, std::abs(m / f - 1));
    coarse_worst = std::max(coarse_worst, std::abs(c / f - 1));
  }
  std::printf("plate with a hole: fine %d quads, medium %d, coarse %d\n", fine.quads, medium.quads, coarse.quads);
  EXPECT_LT(medium_worst, 0.019);  // measured 1.5 %
  EXPECT_LT(coarse_worst, 0.089);  // measured 7.1 %
  EXPECT_LT(medium_worst, coarse_worst);
  // The stress concentration (issue 33's stresses): sigma_xx at the hole's edge across the load,
  // read at the node (corner values extrapolated from each element's 2 x 2 points, averaged),
  // against Howland's 3.03 on the gross stress at d/W = 0.1 (Kirsch's infinite plate: 3), to 5 %
  // at every mesh; sigma_yy where the load axis meets the hole, against Kirsch's -sigma (Howland's
  // finite width changes it by under 1 %), to 5 % on the fine and medium meshes.
  const double howland = (2.0 + std::pow(1.0 - 0.1, 3.0)) / (1.0 - 0.1);  // Heywood's fit, gross section: 3.032
  for (const SceneRun* r : {&fine, &medium, &coarse}) {
    const double scf = metric(*r, "scf_hole_90") / 1.0e6, syy = metric(*r, "sigma_yy_hole_0") / 1.0e6;
    std::printf("plate with a hole, %d quads: stress concentration %.4f (Howland %.4f: %+.2f %%), sigma_yy at theta = 0 %.4f\n",
                r->quads, scf, howland, 100 * (scf / howland - 1), syy);
    EXPECT_LT(std::abs(scf / howland - 1), 0.05) << r->quads << " quads";
    if (r != &coarse) { EXPECT_LT(std::abs(syy + 1.0), 0.05) << r->quads << " quads"; }
  }
}

// The finite-width effect shrinks as Howland's plate widens: the same plate with the hole's radius
// halved (d/W = 0.05) is within 0.7 % of Kirsch where d/W = 0.1 was 1.2-3.2 % off.
TEST(ImportedGeometryAccuracy, PlateWithAHoleApproachesKirschAsTheHoleShrinks) {
  std::ifstream in(std::string(FF_SOURCE_DIR) + "/assets/geometry/plate_with_hole.geo");
  std::stringstream text;
  text << in.rdbuf();
  std::string geo = text.str();
  const std::string radius = "a = 1;";
  ASSERT_NE(geo.find(radius), std::string::npos);
  geo.replace(geo.find(radius), radius.size(), "a = 0.5;");
  const std::filesystem::path dir = std::filesystem::path(FF_BINARY_DIR) / "test_out" / "imported_geometry";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "plate_with_small_hole.geo").string();
  std::ofstream(path) << geo;
  const SceneRun r = run("plate_with_hole_geo", {"part[0].file=" + path, "part[0].mesh_size=0.25", "part[0].local_sizes=[0.0125]"});
  const Kirsch k = kirsch(1.0e6, 0.5, 2.1e11, 0.3);
  for (const auto& [name, kirsch_value] : std::vector<std::pair<std::string, double>>{
           {"ux_hole_0", k.ux_hole_0}, {"uy_hole_90", k.uy_hole_90}, {"ux_axis_2a", k.ux_axis_2a}, {"uy_axis_2a", k.uy_axis_2a}}) {
    const double u = metric(r, name);
    std::printf("plate with a hole of d/W = 0.05, %-10s %.5e (Kirsch %+.2f %%)\n", name.c_str(), u, 100 * (u / kirsch_value - 1));
    EXPECT_NEAR(u / kirsch_value, 1.0, 0.009) << name;
  }
}

// Regression: the averaged directors summed each node's quad normals into a std::map entry that
// operator[] had left uninitialized (Eigen vectors are not zeroed), so a split triangle mesh read
// in a process whose heap held old values got zero or NaN directors ("bad normal: node 310 normal
// (0, 0, 0)" when the plate test above read its .msh after the .geo). The heap is filled here with
// freed map nodes of the same size holding NaN first.
TEST(ImportedGeometryAccuracy, AveragedDirectorsDoNotDependOnWhatTheHeapHeld) {
  {
    std::map<std::pair<int, int>, Eigen::Vector3d> garbage;
    for (int i = 0; i < 200000; ++i) garbage[{i, i}] = Eigen::Vector3d::Constant(std::nan(""));
  }
  ff::scene::MeshFileRequest q;
  q.path = msh("clamped_plate_tri_0p15.msh");
  ff::mesh::ShellMesh m;
  ff::scene::MeshFileError error;
  ASSERT_TRUE(ff::io::read_mesh_file(q, m, error)) << error.message;
  for (int i = 0; i < m.node_count(); ++i) { EXPECT_NEAR(m.normals[static_cast<std::size_t>(i)].z(), 1.0, 1e-12) << "node " << i; }
}

// The CAD hemisphere (assets/geometry/hemisphere_18deg_quarter.geo): an OpenCASCADE sphere's face
// whose seam is its edge on y = 0 and whose pole lies in the hole. The directors are the sphere's
// radial normals at every node, seam edge included, and no node is a fold (a seam inside the mesh
// would give its nodes two normals and make them folds).
TEST(ImportedGeometryAccuracy, CadHemisphereDirectorsAreRadialWithNoFoldAtTheSeam) {
  ff::scene::MeshFileRequest q;
  q.path = std::string(FF_SOURCE_DIR) + "/assets/geometry/hemisphere_18deg_quarter.geo";
  q.mesh_size = 1.0;
  ff::mesh::ShellMesh m;
  ff::scene::MeshFileError error;
  ASSERT_TRUE(ff::io::read_mesh_file(q, m, error)) << error.message;
  EXPECT_EQ(m.fold_count(), 0);
  double worst = 0, radius_error = 0;
  int on_seam = 0;
  for (int i = 0; i < m.node_count(); ++i) {
    const Eigen::Vector3d x = m.points[static_cast<std::size_t>(i)];
    worst = std::max(worst, 1.0 - std::abs(m.normals[static_cast<std::size_t>(i)].dot(x.normalized())));
    radius_error = std::max(radius_error, std::abs(x.norm() - 10.0));
    on_seam += std::abs(x.y()) < 1e-9;
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(radius_error, 1e-9);
  EXPECT_GE(on_seam, 10);
  EXPECT_EQ(m.find_group("symmetry_y") >= 0 ? m.groups[static_cast<std::size_t>(m.find_group("symmetry_y"))].nodes.size() : 0u,
            static_cast<std::size_t>(on_seam));
}
