// `flexframe check SCENE --picture FILE.png` (issue 32, item 6): the scene's structure drawn with
// what its names select. The picture is written exactly where asked and nowhere else, at its size,
// with the colours of the selections in it; a path it may not write is refused before any work
// with the reason (exit 2) and leaves nothing behind; a full disk fails (exit 1) with no partial file.
#include <gtest/gtest.h>
#include <sys/mount.h>

#include "app/check_picture.h"
#include "cli_support.h"
#include "core/mesh/generators.h"
#include "render/graphics_context.h"
#include "render/mesh_picture.h"

namespace ff::cli::test {
namespace {

// pixels in the direction of colour c in RGB space (the lit shades of it), as in render_mesh_picture
int pixels_of(const render::test::Image& img, const std::array<double, 3>& c) {
  const double cn = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  int count = 0;
  for (const auto& px : img.rgb) {
    const double p[3] = {px[0] / 255.0, px[1] / 255.0, px[2] / 255.0};
    const double pn = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    if (pn < 0.25 * cn) continue;
    count += (p[0] * c[0] + p[1] * c[1] + p[2] * c[2]) / (pn * cn) > 0.9995;
  }
  return count;
}

TEST(CheckPicture, DrawsTheSelectionsOfAPlateWhereAsked) {
  const std::string dir = fresh_test_dir();
  const std::string work = dir + "/work";
  fs::create_directories(work);
  const std::string png = dir + "/plate.png";
  const ProcResult r = run_flexframe({"check", "clamped_plate_pressure", "--picture", png}, dir + "/check", work);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.out.find("clamped_plate_pressure: valid"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("picture: " + png + " (1280x960): 1 part, 0 named groups, 6 selections"), std::string::npos)
      << r.out;
  const render::test::Image img = render::test::read_png(png);
  ASSERT_EQ(img.width, 1280);
  ASSERT_EQ(img.height, 960);
  // the scene's four clamped edges, its pressure (filled, tinted) and its probe: colours in order
  for (int k = 0; k < 4; ++k) { EXPECT_GT(pixels_of(img, render::picture_color(k)), 100) << "bc[" << k << "]"; }
  EXPECT_GT(pixels_of(img, render::picture_color(4, 0.3)), 20000) << "load[0] pressure over the whole plate";
  EXPECT_GT(pixels_of(img, render::picture_color(5)), 10) << "probe[0]";
  // nothing else was written: not in the working folder, not beside the picture
  EXPECT_TRUE(tree(work).empty());
  std::vector<std::string> files = tree(dir);
  files.erase(std::remove_if(files.begin(), files.end(),
                             [](const std::string& f) { return f.find(".txt") != std::string::npos || f == "work"; }),
              files.end());
  EXPECT_EQ(files, std::vector<std::string>{"plate.png"});
}

TEST(CheckPicture, ShowsThePartsOfAJoinedStructureAndAMeshFileScene) {
  const std::string dir = fresh_test_dir();
  // two parts at a junction: each part its own pale colour
  ProcResult r = run_flexframe({"check", "raasch_hook", "--picture", dir + "/hook.png"}, dir + "/hook");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.out.find("2 parts, 0 named groups, 3 selections"), std::string::npos) << r.out;
  render::test::Image img = render::test::read_png(dir + "/hook.png");
  EXPECT_GT(pixels_of(img, render::picture_color(0, 0.55)), 2000) << "part 'small_arc'";
  EXPECT_GT(pixels_of(img, render::picture_color(1, 0.55)), 10000) << "part 'large_arc'";
  // one part of three named patches (l_plate: arm1, corner, arm2): each patch its pale colour
  r = run_flexframe({"check", "l_plate_force", "--picture", dir + "/l_plate.png"}, dir + "/l_plate");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  img = render::test::read_png(dir + "/l_plate.png");
  for (int k = 0; k < 3; ++k) { EXPECT_GT(pixels_of(img, render::picture_color(k, 0.55)), 500) << "patch " << k; }
  // a dynamic scene: joints and arcs are selections too
  r = run_flexframe({"check", "double_pendulum_shells", "--picture", dir + "/pendulum.png"}, dir + "/pendulum");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.out.find("2 parts, 0 named groups, 5 selections"), std::string::npos) << r.out;
  // a mesh read from a file
  r = run_flexframe({"check", "clamped_plate_pressure_obj", "--picture", dir + "/obj.png"}, dir + "/obj");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  img = render::test::read_png(dir + "/obj.png");
  EXPECT_EQ(img.width, 1280);
}

// The mesh's named groups (from a mesh file: Gmsh physical groups, Abaqus sets): a surface group
// fills its quads, a curve or point group marks its nodes, each in its own colour, labelled and
// listed with its node count. No bundled mesh file has groups yet, so the selections are made here
// and drawn as `check --picture` draws them (app::selections_picture, render::write_mesh_picture).
TEST(CheckPicture, NamedGroupsAreColouredLabelledAndListed) {
  const std::string dir = fresh_test_dir();
  scene::SceneSelections s;
  s.scene_name = "groups";
  s.mesh = mesh::rectangular_plate(2.0, 1.0, 8, 4);
  s.part_names = {"plate"};
  s.quad_part.assign(s.mesh.quads.size(), 0);
  mesh::MeshGroup skin{"skin", 2, {}, {}, "test"}, edge{"inlet", 1, {}, {}, "test"}, corner{"pin", 0, {0}, {}, "test"};
  for (int q = 0; q < 16; ++q) skin.quads.push_back(q);  // the lower half (v < 0.5)
  for (int q : skin.quads) skin.nodes.insert(skin.nodes.end(), s.mesh.quads[q].begin(), s.mesh.quads[q].end());
  std::sort(skin.nodes.begin(), skin.nodes.end());
  skin.nodes.erase(std::unique(skin.nodes.begin(), skin.nodes.end()), skin.nodes.end());
  for (int j = 0; j <= 4; ++j) edge.nodes.push_back(j * 9 + 8);  // x = 2
  s.mesh.groups = {skin, edge, corner};
  scene::EntrySelection bc;
  bc.table = "bc";
  bc.label = "bc[0] clamped";
  bc.extent = "5 nodes";
  bc.nodes = edge.nodes;
  s.entries = {bc};

  const render::MeshPicture pic = app::selections_picture(s);
  ASSERT_EQ(pic.items.size(), 4u);  // one part: not drawn apart
  EXPECT_EQ(pic.items[0].legend, "group 'skin' (surface, 27 nodes)");
  EXPECT_EQ(pic.items[0].quads.size(), 16u);
  EXPECT_TRUE(pic.items[0].nodes.empty());
  EXPECT_EQ(pic.items[1].legend, "group 'inlet' (curve, 5 nodes)");
  EXPECT_EQ(pic.items[1].nodes.size(), 5u);
  EXPECT_EQ(pic.items[1].anchor, 2 * 9 + 8);  // its middle node
  EXPECT_EQ(pic.items[2].legend, "group 'pin' (point, 1 node)");
  EXPECT_EQ(pic.items[3].legend, "bc[0] clamped (5 nodes)");
  for (const auto& item : pic.items) { EXPECT_GE(item.anchor, 0) << item.legend; }
  EXPECT_EQ(pic.items[3].label, "bc[0] clamped (5 nodes)");  // few labels: each says it all

  // many: on the picture only the entry's table and index; the legend keeps the whole line
  scene::SceneSelections crowded = s;
  for (std::size_t i = 1; i < 10; ++i) {
    scene::EntrySelection e = bc;
    e.index = i;
    e.label = "bc[" + std::to_string(i) + "] clamped";
    crowded.entries.push_back(e);
  }
  const render::MeshPicture busy = app::selections_picture(crowded);
  ASSERT_EQ(busy.items.size(), 13u);
  EXPECT_EQ(busy.items[12].label, "bc[9]");
  EXPECT_EQ(busy.items[12].legend, "bc[9] clamped (5 nodes)");

  std::string error;
  const auto gc = render::GraphicsContext::create(&error);
  ASSERT_NE(gc, nullptr) << error;
  ASSERT_TRUE(render::write_mesh_picture(*gc, pic, dir + "/groups.png", &error)) << error;
  const render::test::Image img = render::test::read_png(dir + "/groups.png");
  ASSERT_EQ(img.width, pic.width);
  for (const auto& item : pic.items) { EXPECT_GT(pixels_of(img, item.color), 10) << item.legend; }
  EXPECT_GT(pixels_of(img, pic.items[0].color), 20000) << "the surface group fills a quarter of the picture";
}

TEST(CheckPicture, APathItMayNotWriteIsRefusedBeforeAnyWork) {
  const std::string dir = fresh_test_dir();
  struct Case {
    std::string path, says;
  };
  const std::vector<Case> cases = {
      {dir + "/no_such_folder/plate.png", "the folder '" + dir + "/no_such_folder' does not exist"},
      {dir + "/plate.jpg", "give a file name ending in .png"},
      {dir + "/plate.png/", "give a file name ending in .png"},
      {"", "--picture needs a file name"},
  };
  for (const Case& c : cases) {
    const ProcResult r = run_flexframe({"check", "clamped_plate_pressure", "--picture", c.path}, dir + "/bad");
    EXPECT_EQ(r.exit_code, 2) << c.path << "\n" << r.describe();
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.path << "\n" << r.err;
    EXPECT_EQ(r.out.find("valid"), std::string::npos) << "refused before the scene was checked\n" << r.out;
  }
  EXPECT_FALSE(fs::exists(dir + "/no_such_folder"));  // no folder is made for it
  // a folder named like a picture
  fs::create_directories(dir + "/folder.png");
  ProcResult r = run_flexframe({"check", "clamped_plate_pressure", "--picture", dir + "/folder.png"}, dir + "/folder");
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("is a folder"), std::string::npos) << r.err;
  // a model without a shell structure
  r = run_flexframe({"check", "hub_beam_fem_tau1", "--picture", dir + "/hub.png"}, dir + "/hub");
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("has no shell structure"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/hub.png"));
  // an invalid scene: its error, and no picture
  write_text(dir + "/broken.toml", read_text(scene_path("clamped_plate_pressure")) + "\n[[bc]]\ntype = \"welded\"\n");
  r = run_flexframe({"check", dir + "/broken.toml", "--picture", dir + "/broken.png"}, dir + "/broken");
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("welded"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir + "/broken.png"));
}

TEST(CheckPicture, AFullDiskFailsAndLeavesNoPartialPicture) {
  const std::string dir = fresh_test_dir();
  const std::string disk = dir + "/disk";
  fs::create_directories(disk);
  // 8 KiB: the picture (tens of KiB) cannot fit
  if (::mount("flexframe-test", disk.c_str(), "tmpfs", 0, "size=8k") != 0)
    GTEST_SKIP() << "cannot mount a small tmpfs here (" << std::strerror(errno) << "; needs root)";
  const ProcResult r = run_flexframe({"check", "clamped_plate_pressure", "--picture", disk + "/plate.png"}, dir + "/full");
  const bool gone = !fs::exists(disk + "/plate.png");
  ::umount2(disk.c_str(), MNT_DETACH);
  EXPECT_EQ(r.exit_code, 1) << r.describe();
  EXPECT_NE(r.err.find("disk full"), std::string::npos) << r.err;
  EXPECT_TRUE(gone) << "a partial picture was left behind";
}

}  // namespace
}  // namespace ff::cli::test
