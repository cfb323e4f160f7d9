// Issue 33, the scene vocabulary of laminated sections (core/scene/structure_parts.cpp): orthotropic
// [[material]]s, [[layup]]s, part.layup and the fibre reference per part. Bad input is refused at
// its file:line and key (a ply of zero thickness, an unstable ply, a ply material with a thickness
// of its own, a partial orthotropic set, part.material with part.layup, a fibre vector along an
// element's normal, an unknown ply material, lists of different lengths); angles that look like
// radians are a located warning. An isotropic scene reaches its model exactly as before (no
// sections, no per-quad directions); a laminated one builds elements that carry its plies and the
// reference direction of each quad for fibre_reference = "u", "v" and "vector".
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "core/scene/mesh_generator_keys.h"
#include "core/scene/scene.h"
#include "core/scene/shell_scene.h"
#include "core/scene/structure_parts.h"
#include "core/shell/shell_dynamic_simulation.h"
#include "core/shell/shell_static_simulation.h"

using namespace ff;

namespace {

std::string write_scene(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / ("ff_layup_input_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / (name + ".toml");
  std::ofstream(path) << text;
  return path.string();
}

// 1-based line of the first line of `text` that contains `needle` (0 when none)
int line_of(const std::string& text, const std::string& needle) {
  std::istringstream in(text);
  std::string line;
  for (int n = 1; std::getline(in, line); ++n)
    if (line.find(needle) != std::string::npos) return n;
  return 0;
}

// The [0/90/0] hinged roof of Sze, Liu & Lo (quarter model, 4 x 4), statics, 0 degrees along its
// axis as in the bundled scene. `material`, `layup` and `part_extra` replace the defaults.
const std::string kPly =
    "[[material]]\nname = \"ply\"\ne1 = 3300.0\ne2 = 1100.0\ng12 = 660.0\ng13 = 660.0\ng23 = 660.0\nnu12 = 0.25\n";
const std::string kLayup =
    "[[layup]]\nname = \"cross\"\nplies = [\"ply\", \"ply\", \"ply\"]\n"
    "ply_thicknesses = [4.233333333333333, 4.233333333333333, 4.233333333333334]\nply_angles = [0.0, 90.0, 0.0]\n";

std::string roof(const std::string& material = kPly, const std::string& layup = kLayup,
                 const std::string& part_extra = "layup = \"cross\"\nfibre_reference = \"v\"\n") {
  return "[scene]\nname = \"laminated_roof\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = [\"elastic\", \"hr\", \"ans\"]\n"
         "[[part]]\ngenerator = \"cylinder\"\nname = \"roof\"\nradius = 2540.0\norigin = [0.0, 0.0, -2540.0]\n"
         "axis = [1.0, 0.0, 0.0]\nreference = [0.0, 0.0, 1.0]\nstart_angle = -5.729577951308232\nend_angle = 0.0\n"
         "length = 254.0\nn1 = 4\nn2 = 4\n" +
         part_extra + material + layup +
         "[[bc]]\ntype = \"hinged\"\nselect = \"patch_edge\"\npatch = \"roof\"\nedge = \"u=0\"\n"
         "[[load]]\ntype = \"force\"\ntotal = [0.0, 0.0, -750.0]\nselect = \"nearest\"\npoint = [0.0, 0.0, 0.0]\n"
         "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, -1.0]\npoint = [0.0, 0.0, 0.0]\n[solver]\n";
}

// The first issue of loading `text` (empty key when it loads)
scene::Issue first_issue(const std::string& name, const std::string& text) {
  try {
    scene::load_scene(write_scene(name, text));
  } catch (const scene::SceneError& e) {
    return e.issues.at(0);
  }
  return {};
}

void expect_refused(const std::string& name, const std::string& text, const std::string& key, int line,
                    const std::string& says) {
  SCOPED_TRACE(name);
  const scene::Issue issue = first_issue(name, text);
  EXPECT_EQ(issue.key, key) << issue.to_string();
  EXPECT_EQ(issue.line, line) << issue.to_string();
  EXPECT_NE(issue.file.find(name + ".toml"), std::string::npos) << issue.to_string();
  EXPECT_NE(issue.message.find(says), std::string::npos) << issue.to_string();
}
void expect_refused(const std::string& name, const std::string& text, const std::string& key, const std::string& line_text,
                    const std::string& says) {
  expect_refused(name, text, key, line_of(text, line_text), says);
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

const shell::ShellModel& static_model(const scene::LoadedScene& s) {
  return dynamic_cast<const shell::ShellStaticSimulation&>(*s.simulation).model();
}

}  // namespace

TEST(LayupInput, TheLaminatedRoofLoads) {
  const scene::LoadedScene s = scene::load_scene(write_scene("roof_ok", roof()));
  EXPECT_TRUE(s.warnings.empty());
}

TEST(LayupInput, BadInputIsRefusedAtItsLineAndKey) {
  // a ply of zero thickness, named by its index
  expect_refused("zero_ply", replaced(roof(), "4.233333333333333, 4.233333333333334]", "0.0, 4.233333333333334]"),
                 "layup[0].ply_thicknesses", "ply_thicknesses", "entry 2");
  expect_refused("negative_ply", replaced(roof(), "[4.233333333333333,", "[-1.0,"), "layup[0].ply_thicknesses",
                 "ply_thicknesses", "entry 1");
  // an unstable ply (L2): 1 - nu12 nu21 = 1 - 1.8^2 / 3 < 0, at nu12 with the numbers
  expect_refused("unstable", replaced(roof(), "nu12 = 0.25", "nu12 = 1.8"), "material[0].nu12", "nu12 = 1.8",
                 "1 - nu12 nu21 = -0.08");
  // a ply's material with a thickness of its own
  expect_refused("ply_thickness", replaced(roof(), "nu12 = 0.25\n", "nu12 = 0.25\nthickness = 3.0\n"),
                 "material[0].thickness", "thickness = 3.0", "ply of layup 'cross'");
  // a partial orthotropic set: the first key missing from it, at the material's header
  {
    const std::string text = replaced(roof(), "g13 = 660.0\n", "");
    expect_refused("partial", text, "material[0].g13", "[[material]]", "g13 is missing");
  }
  // both forms of one material
  expect_refused("both_forms", replaced(roof(), "nu12 = 0.25\n", "nu12 = 0.25\nyoungs_modulus = 3300.0\n"),
                 "material[0].youngs_modulus", "youngs_modulus = 3300.0", "give one form");
  // part.material and part.layup
  expect_refused("material_and_layup", roof(kPly, kLayup, "material = \"ply\"\nlayup = \"cross\"\n"), "part[0].layup",
                 "layup = \"cross\"", "not both");
  // an unknown ply material
  expect_refused("unknown_ply", replaced(roof(), "\"ply\", \"ply\"]", "\"ply\", \"plx\"]"), "layup[0].plies",
                 "plies = [", "no [[material]] is called 'plx'");
  // lists of different lengths
  expect_refused("short_angles", replaced(roof(), "ply_angles = [0.0, 90.0, 0.0]", "ply_angles = [0.0, 90.0]"),
                 "layup[0].ply_angles", "ply_angles", "2 entries for the 3 plies");
  expect_refused("long_thicknesses", replaced(roof(), "4.233333333333334]", "4.233333333333334, 1.0]"),
                 "layup[0].ply_thicknesses", "ply_thicknesses", "4 entries for the 3 plies");
  // a layup no part is made of, a layup named like a material
  expect_refused("unused_layup",
                 roof(kPly + "[[material]]\nname = \"iso\"\nyoungs_modulus = 3102.75\nthickness = 12.7\n", kLayup,
                      "material = \"iso\"\n"),
                 "layup[0].name", "name = \"cross\"", "no part is made of layup 'cross'");
  {
    const std::string text = replaced(replaced(roof(), "name = \"cross\"", "name = \"ply\""), "layup = \"cross\"", "layup = \"ply\"");
    expect_refused("layup_named_like_material", text, "layup[0].name", line_of(text, "plies = [") - 1,
                   "a material is called 'ply'");
  }
  // a material a part uses directly needs its thickness
  expect_refused("no_thickness", roof(kPly, "", "material = \"ply\"\n"), "material[0].thickness", "[[material]]",
                 "needs its thickness");
  // fibre_vector without "vector", and "vector" without fibre_vector
  expect_refused("vector_ignored", roof(kPly, kLayup, "layup = \"cross\"\nfibre_vector = [1.0, 0.0, 0.0]\n"),
                 "part[0].fibre_vector", "fibre_vector", "would ignore it");
  expect_refused("vector_missing", roof(kPly, kLayup, "layup = \"cross\"\nfibre_reference = \"vector\"\n"),
                 "part[0].fibre_reference", "fibre_reference", "needs part.fibre_vector");
}

// A reference vector along the normal of some element is refused there, naming the quad (its
// index in the part) and where it is.
TEST(LayupInput, FibreVectorAlongANormalNamesTheElement) {
  // a closed cylinder about z, 8 around, 1 along: quad 2 (by the grid, u around from azimuth 0)
  // has its centre at azimuth 112.5 degrees, where the outward normal is (cos 112.5, sin 112.5, 0)
  const double a = 112.5 * std::numbers::pi / 180.0;
  std::ostringstream vector;
  vector.precision(17);
  vector << "fibre_reference = \"vector\"\nfibre_vector = [" << std::cos(a) << ", " << std::sin(a) << ", 0.0]\n";
  const std::string text =
      "[scene]\nname = \"tube\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = [\"elastic\"]\n"
      "[[part]]\ngenerator = \"cylinder\"\nname = \"tube\"\nradius = 1.0\nlength = 1.0\nn1 = 8\nn2 = 1\nlayup = \"l\"\n" +
      vector.str() + kPly + "[[layup]]\nname = \"l\"\nplies = [\"ply\"]\nply_thicknesses = [0.01]\nply_angles = [30.0]\n" +
      "[[bc]]\ntype = \"clamped\"\nselect = \"patch_edge\"\npatch = \"tube\"\nedge = \"bottom\"\n"
      "[[load]]\ntype = \"force\"\ntotal = [0.0, 0.0, 1.0]\nselect = \"nearest\"\npoint = [1.0, 0.0, 1.0]\n"
      "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, 1.0]\npoint = [1.0, 0.0, 1.0]\n[solver]\n";
  const scene::Issue issue = first_issue("tube", text);
  EXPECT_EQ(issue.key, "part[0].fibre_vector") << issue.to_string();
  EXPECT_EQ(issue.line, line_of(text, "fibre_vector")) << issue.to_string();
  EXPECT_NE(issue.message.find("quad 2 of part 'tube'"), std::string::npos) << issue.to_string();
  // its centre: the chord's middle at azimuth 112.5, half-way up
  const double r = std::cos(std::numbers::pi / 8);
  std::ostringstream where;
  where.precision(6);
  where << "at (" << r * std::cos(a) << ", " << r * std::sin(a) << ", 0.5)";
  EXPECT_NE(issue.message.find(where.str()), std::string::npos) << issue.to_string() << " (expected " << where.str() << ")";
  // a vector across every element is accepted
  const std::string along_axis = replaced(text, vector.str(), "fibre_reference = \"vector\"\nfibre_vector = [0.0, 0.0, 1.0]\n");
  EXPECT_EQ(first_issue("tube_axis", along_axis).key, "") << first_issue("tube_axis", along_axis).to_string();
}

// Radians by mistake: every |angle| <= 2 pi, one non-zero, one not a whole number of degrees:
// accepted with a warning located at layup.ply_angles; plausible degrees pass silently.
// Issue 48, item 4: orthotropic plies have no default reference direction. Without
// part.fibre_reference the part is refused at its [[part]] line, the message saying what u and v are
// on its generator (the default "u" ran around the roof's arc and made [0/90/0] the [90/0/90]
// stack); a layup of isotropic plies needs none, and every generator has its u and v in words.
TEST(LayupInput, OrthotropicPartsNeedTheirFibreReference) {
  const std::string roof_text = roof(kPly, kLayup, "layup = \"cross\"\n");
  expect_refused("roof_without_reference", roof_text, "part[0].fibre_reference", "[[part]]", "no default");
  const scene::Issue issue = first_issue("roof_without_reference", roof_text);
  EXPECT_NE(issue.message.find("u around the arc"), std::string::npos) << issue.to_string();
  EXPECT_NE(issue.message.find("v along the axis"), std::string::npos) << issue.to_string();
  EXPECT_NE(issue.message.find("layup 'cross'"), std::string::npos) << issue.to_string();
  // an orthotropic material as the whole section (one ply at 0 degrees) is orthotropic too
  const std::string single_ply = roof(kPly + "thickness = 12.7\n", "", "material = \"ply\"\n");
  expect_refused("single_ply_without_reference", single_ply, "part[0].fibre_reference", "[[part]]", "material 'ply'");
  // isotropic plies: u, as before
  const std::string iso = "[[material]]\nname = \"ply\"\nyoungs_modulus = 3300.0\n";
  EXPECT_NO_THROW(scene::load_scene(write_scene("isotropic_layup", roof(iso, kLayup, "layup = \"cross\"\n"))));
  for (const std::string generator :
       {"rectangular_plate", "l_plate", "folded_plate", "cylinder", "cut_cylinder", "annulus", "spherical_cap"})
    EXPECT_NE(scene::generator_grid_directions(generator).find("u "), std::string::npos) << generator;
}

TEST(LayupInput, AnglesThatLookLikeRadiansWarnAtTheirLine) {
  const std::string text = replaced(roof(), "ply_angles = [0.0, 90.0, 0.0]", "ply_angles = [0.0, 1.5708, 0.0]");
  const scene::LoadedScene s = scene::load_scene(write_scene("radians", text));
  ASSERT_EQ(s.warnings.size(), 1u);
  const std::string where = "radians.toml:" + std::to_string(line_of(text, "ply_angles")) + ":";
  EXPECT_NE(s.warnings[0].find(where), std::string::npos) << s.warnings[0];
  EXPECT_NE(s.warnings[0].find("key 'layup[0].ply_angles'"), std::string::npos) << s.warnings[0];
  EXPECT_NE(s.warnings[0].find("1.5708 rad would be 90"), std::string::npos) << s.warnings[0];
  // `check` prints it
  const std::string report = scene::check_scene_report(write_scene("radians_check", text));
  EXPECT_NE(report.find("\nwarning: "), std::string::npos) << report;
  EXPECT_NE(report.find("layup[0].ply_angles"), std::string::npos) << report;
  for (const char* degrees : {"[0.0, 90.0, 0.0]", "[0.0, 1.0, 0.0]", "[0.0, 0.0, 0.0]", "[45.0, -45.5, 45.0]", "[0.0, 6.5, 0.0]"}) {
    const scene::LoadedScene ok =
        scene::load_scene(write_scene("degrees", replaced(roof(), "[0.0, 90.0, 0.0]", degrees)));
    EXPECT_TRUE(ok.warnings.empty()) << degrees << ": " << (ok.warnings.empty() ? "" : ok.warnings[0]);
  }
}

// An isotropic scene is untouched: one section, no per-quad sections, no reference directions,
// elements without plies and with a zero reference direction (their own xi direction), as before.
TEST(LayupInput, IsotropicScenesAreUnchanged) {
  const scene::LoadedScene s = scene::load_scene(std::string(FF_SOURCE_DIR) + "/assets/scenes/hinged_roof_h127.toml");
  const shell::ShellModel& model = static_model(s);
  EXPECT_TRUE(model.spec().sections.empty());
  EXPECT_TRUE(model.spec().quad_section.empty());
  EXPECT_TRUE(model.spec().quad_reference_direction.empty());
  EXPECT_EQ(model.spec().section.plies, nullptr);
  EXPECT_EQ(model.spec().section.thickness, 12.7);
  EXPECT_EQ(model.spec().section.youngs_modulus, 3102.75);
  ASSERT_EQ(model.elements().size(), 256);
  for (const shell::ShellElement& e : model.elements().all()) {
    EXPECT_EQ(e.elastic->section().plies, nullptr);
    EXPECT_EQ(e.elastic->section().reference_direction, Eigen::Vector3d::Zero());
  }
  EXPECT_TRUE(s.warnings.empty());
  // dynamics: the bodies carry no directions either
  const scene::LoadedScene dynamic =
      scene::load_scene(std::string(FF_SOURCE_DIR) + "/assets/scenes/double_pendulum_shells.toml");
  const auto& multibody = dynamic_cast<const shell::ShellDynamicSimulation&>(*dynamic.simulation).model();
  for (const shell::ShellBodySpec& b : multibody.spec().shells) {
    EXPECT_TRUE(b.quad_reference_direction.empty()) << b.name;
    EXPECT_EQ(b.section.plies, nullptr) << b.name;
  }
  for (const shell::ShellElement& e : multibody.elements().all())
    EXPECT_EQ(e.elastic->section().reference_direction, Eigen::Vector3d::Zero());
}

// The laminated roof: every element carries the three plies (angles in radians, bottom first,
// their thicknesses summing to the section's), and its reference direction: for "u" the roof's
// circumferential tangent at the element's centre (the cylinder's u runs around), for "v" its
// axis, for "vector" the vector as given.
TEST(LayupInput, LaminatedElementsCarryPliesAndReferenceDirections) {
  const Eigen::Vector3d r0(0, 0, 1), et = Eigen::Vector3d::UnitX().cross(r0), origin(0, 0, -2540);
  for (const char* reference : {"u", "v", "vector"}) {
    SCOPED_TRACE(reference);
    const std::string extra = std::string("layup = \"cross\"\nfibre_reference = \"") + reference + "\"\n" +
                              (std::string(reference) == "vector" ? "fibre_vector = [1.0, 2.0, 0.5]\n" : "");
    const scene::LoadedScene s = scene::load_scene(write_scene(std::string("roof_") + reference, roof(kPly, kLayup, extra)));
    const shell::ShellModel& model = static_model(s);
    const mesh::ShellMesh& m = model.spec().mesh;
    ASSERT_EQ(model.elements().size(), 16);
    // the model's own section is the first part's (the layup), not the first [[material]] (a ply)
    EXPECT_EQ(model.spec().section.plies, model.elements()[0].elastic->section().plies);
    EXPECT_NEAR(model.spec().section.thickness, 12.7, 1e-12);
    ASSERT_EQ(model.spec().quad_reference_direction.size(), 16u);
    for (int q = 0; q < 16; ++q) {
      const shell::ShellSection& section = model.elements()[q].elastic->section();
      ASSERT_NE(section.plies, nullptr);
      ASSERT_EQ(section.plies->size(), 3u);
      const std::vector<shell::Ply>& plies = *section.plies;
      EXPECT_EQ(plies[0].angle, 0.0);
      EXPECT_EQ(plies[1].angle, std::numbers::pi / 2);
      EXPECT_EQ(plies[2].angle, 0.0);
      EXPECT_EQ(plies[1].e1, 3300.0);
      EXPECT_EQ(plies[1].e2, 1100.0);
      EXPECT_EQ(plies[1].g23, 660.0);
      EXPECT_EQ(plies[1].nu12, 0.25);
      EXPECT_EQ(plies[2].thickness, 4.233333333333334);
      EXPECT_NEAR(section.thickness, plies[0].thickness + plies[1].thickness + plies[2].thickness, 0.0);
      EXPECT_NEAR(section.thickness, 12.7, 1e-12);
      EXPECT_EQ(model.elements()[q].thickness, section.thickness);
      const Eigen::Vector3d dir = section.reference_direction;
      EXPECT_EQ(dir, model.spec().quad_reference_direction[q]);
      const auto& c = m.quads[q];
      const Eigen::Vector3d centre = 0.25 * (m.points[c[0]] + m.points[c[1]] + m.points[c[2]] + m.points[c[3]]);
      const Eigen::Vector3d radial = centre - origin - (centre - origin).dot(Eigen::Vector3d::UnitX()) * Eigen::Vector3d::UnitX();
      const double phi = std::atan2(radial.dot(et), radial.dot(r0));
      if (std::string(reference) == "u") {  // d x / d phi, phi increasing from start_angle to end_angle
        const Eigen::Vector3d tangent = -std::sin(phi) * r0 + std::cos(phi) * et;
        EXPECT_NEAR((dir - tangent).norm(), 0.0, 1e-12) << "quad " << q << ": " << dir.transpose();
      } else if (std::string(reference) == "v") {
        EXPECT_NEAR((dir - Eigen::Vector3d::UnitX()).norm(), 0.0, 1e-12) << "quad " << q;
      } else {
        EXPECT_EQ(dir, Eigen::Vector3d(1.0, 2.0, 0.5)) << "quad " << q;
      }
    }
  }
}

// Every generator's patches carry the grid their u and v are read from (the guard in
// fibre_reference_directions), and the directions are unit vectors in each element's surface,
// u across v.
TEST(LayupInput, EveryGeneratorGivesUAndVDirections) {
  const std::vector<std::string> parts = {
      "generator = \"rectangular_plate\"\nlength = 2.0\nwidth = 1.0\nn1 = 4\nn2 = 2",
      "generator = \"l_plate\"\nlength = 10.0\nlength2 = 5.0\nwidth = 1.0\nn1 = 4\nn2 = 1",
      "generator = \"folded_plate\"\nlength = 2.0\nlength2 = 1.0\nwidth = 1.0\nfold_angle = 60.0\nn1 = 2\nn2 = 2\nn3 = 3",
      "generator = \"cylinder\"\nradius = 1.0\nlength = 2.0\nn1 = 12\nn2 = 2",
      "generator = \"cylinder\"\nradius = 1.0\nlength = 2.0\nslit = true\nn1 = 12\nn2 = 2\nflip_director = true",
      "generator = \"cut_cylinder\"\nradius = 1.0\nlength = 2.0\nstart_angle = 0.0\nend_angle = 90.0\nn1 = 4\nn2 = 2",
      "generator = \"annulus\"\nradius = 10.0\ninner_radius = 6.0\nn1 = 2\nn2 = 12",
      "generator = \"annulus\"\nradius = 1.0\nn1 = 2\nn2 = 16",
      "generator = \"spherical_cap\"\nradius = 1.0\npolar_start = 20.0\npolar_end = 90.0\nn1 = 4\nn2 = 8",
      "generator = \"spherical_cap\"\nradius = 1.0\npolar_end = 60.0\nn1 = 2\nn2 = 8"};
  for (const std::string& part : parts) {
    SCOPED_TRACE(part);
    std::vector<std::vector<Eigen::Vector3d>> dirs;
    for (const char* reference : {"u", "v"}) {
      const std::string text = "[scene]\nname = \"t\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = [\"elastic\"]\n[[part]]\n" +
                               part + "\nfibre_reference = \"" + reference + "\"\n" + kPly + "thickness = 0.01\n" +
                               "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, 1.0]\n[solver]\n";
      const scene::Document d = scene::validate(scene::shell_static_schema(), text, "t.toml");
      const scene::Structure st = scene::read_structure(d, "t.toml", {});
      ASSERT_EQ(st.quad_reference_direction.size(), static_cast<std::size_t>(st.joined.quad_count()));
      dirs.push_back(st.quad_reference_direction);
      for (int q = 0; q < st.joined.quad_count(); ++q) {
        const auto& c = st.joined.quads[q];
        const auto& x = st.joined.points;
        const Eigen::Vector3d n = (x[c[2]] - x[c[0]]).cross(x[c[3]] - x[c[1]]).normalized();
        EXPECT_NEAR(st.quad_reference_direction[q].norm(), 1.0, 1e-12);
        EXPECT_LT(std::abs(st.quad_reference_direction[q].dot(n)), 0.2) << reference << " quad " << q;
      }
    }
    for (std::size_t q = 0; q < dirs[0].size(); ++q)
      EXPECT_GT(dirs[0][q].cross(dirs[1][q]).norm(), 0.5) << "quad " << q << ": u and v nearly parallel";
  }
}

// A layup's density is the thickness-weighted mean of its plies'; a dynamic analysis refuses a
// layup whose plies have densities only in part, at the ply material without one.
TEST(LayupInput, LayupDensityInDynamics) {
  auto plate = [](const std::string& materials) {
    return "[scene]\nname = \"swing\"\nmodel = \"shell\"\nanalysis = \"dynamic\"\n"
           "effects = [\"elastic\", \"inertia\", \"hr\", \"ans\"]\n[solver]\ndt = 1e-3\nend = 0.01\n" +
           materials +
           "[[layup]]\nname = \"two\"\nplies = [\"a\", \"b\"]\nply_thicknesses = [0.001, 0.003]\nply_angles = [0.0, 90.0]\n"
           "[[part]]\nname = \"plate\"\ngenerator = \"rectangular_plate\"\nn1 = 4\nn2 = 2\nlength = 0.6\nwidth = 0.2\n"
           "layup = \"two\"\nfibre_reference = \"u\"\n"
           "[[probe]]\nname = \"tip_z\"\nselect = \"nearest\"\npoint = [0.6, 0.1, 0.0]\ndirection = [0.0, 0.0, 1.0]\n";
  };
  const std::string a = "[[material]]\nname = \"a\"\nyoungs_modulus = 70e9\ndensity = 1000.0\n";
  const std::string b_ortho = "[[material]]\nname = \"b\"\ne1 = 140e9\ne2 = 10e9\ng12 = 5e9\ng13 = 5e9\ng23 = 4e9\nnu12 = 0.3\n";
  const scene::LoadedScene s = scene::load_scene(write_scene("swing", plate(a + b_ortho + "density = 2000.0\n")));
  const auto& model = dynamic_cast<const shell::ShellDynamicSimulation&>(*s.simulation).model();
  ASSERT_EQ(model.spec().shells.size(), 1u);
  const shell::ShellBodySpec& body = model.spec().shells[0];
  EXPECT_NEAR(body.density, (1000.0 * 0.001 + 2000.0 * 0.003) / 0.004, 1e-9);
  EXPECT_EQ(body.quad_reference_direction.size(), 8u);  // a plate's u: x
  for (const Eigen::Vector3d& r : body.quad_reference_direction) { EXPECT_NEAR((r - Eigen::Vector3d::UnitX()).norm(), 0.0, 1e-15); }
  ASSERT_NE(body.section.plies, nullptr);
  const std::vector<shell::Ply>& plies = *body.section.plies;
  ASSERT_EQ(plies.size(), 2u);
  // the isotropic ply: E1 = E2 = E, G = E / (2 (1 + nu)) with the default nu = 0.3
  EXPECT_EQ(plies[0].e2, 70e9);
  EXPECT_EQ(plies[0].g13, 70e9 / 2.6);
  EXPECT_EQ(plies[0].nu12, 0.3);
  EXPECT_EQ(plies[0].density, 1000.0);
  EXPECT_EQ(plies[1].g23, 4e9);
  EXPECT_EQ(plies[1].density, 2000.0);
  for (const shell::ShellElement& e : model.elements().all()) { ASSERT_EQ(e.elastic->section().plies, body.section.plies); }
  // ply b without a density
  const std::string text = plate(a + b_ortho);
  const scene::Issue issue = first_issue("swing_no_density", text);
  EXPECT_EQ(issue.key, "material[1].e1") << issue.to_string();
  EXPECT_EQ(issue.line, line_of(text, "e1 = 140e9")) << issue.to_string();
  EXPECT_NE(issue.message.find("ply material 'b' has no material.density"), std::string::npos) << issue.to_string();
}
