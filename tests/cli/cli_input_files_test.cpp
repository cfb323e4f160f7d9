// Issue 48, items 7, 12-15: the files a scene names, as `flexframe check` meets them. Damaged STL
// files, a .msh header that claims more than its file holds, a FIFO or /dev/zero as a part, scene
// or reference file, and a CAD part too fine for the memory are refused with exit 2 at their key,
// at once; the Gmsh child ends with a flexframe killed by SIGKILL.

#include <gtest/gtest.h>

#include <sys/stat.h>

#include "cli_support.h"

namespace ff::cli::test {
namespace {

std::string corpus(const std::string& name) { return std::string(FF_SOURCE_DIR) + "/tests/cli/fuzz_corpus/" + name; }

// `flexframe check` of the OBJ plate scene with part[0] read from `file` (and more --set)
ProcResult check_part(const std::string& dir, const std::string& file, std::vector<std::string> sets = {},
                      double timeout_s = 20.0) {
  std::vector<std::string> args{"check", "clamped_plate_pressure_obj", "--set", "part[0].file=\"" + file + "\""};
  for (const std::string& s : sets) args.insert(args.end(), {"--set", s});
  return run_flexframe(args, dir + "/check", dir, timeout_s);
}

void expect_refused_at(const ProcResult& r, const std::string& key, const std::string& fragment) {
  EXPECT_EQ(r.signal, 0) << r.describe();
  EXPECT_FALSE(r.timed_out) << r.describe();
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("key '" + key + "'"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find(fragment), std::string::npos) << r.describe();
}

const char* const kSquareGeo =
    "Point(1) = {0, 0, 0, 1}; Point(2) = {1, 0, 0, 1}; Point(3) = {1, 1, 0, 1}; Point(4) = {0, 1, 0, 1};\n"
    "Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};\n"
    "Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};\nPhysical Surface(\"plate\") = {1};\n";

// Item 7 (stl_damaged_accepted): an ASCII STL cut inside a facet, or with random bytes (a NUL among
// them) inside one, was read as 26 and 20 of its 32 triangles and ran to "completed"
TEST(CliInputFiles, DamagedStlFilesAreRefusedSayingWhere) {
  const std::string dir = fresh_test_dir();
  expect_refused_at(check_part(dir, corpus("stl_ascii_cut_inside_facet_26.stl")), "part[0].file",
                    "ends inside facet 26 (line 182, in the middle of 'endlo') with no 'endsolid'");
  expect_refused_at(check_part(dir, corpus("stl_ascii_nul_inside_facet_20.stl")), "part[0].file",
                    "line 140, inside facet 20: expected 'endloop', found 'epf' (the file is damaged)");
}

// Item 12 (msh_nodes_claim_memory): a 1.6 kB .msh whose $Nodes header claims 10^9 nodes took the
// Gmsh child past 13 GB; it is refused from its header, in the parent
TEST(CliInputFiles, AMshHeaderClaimingMoreThanItsFileHoldsIsRefused) {
  const std::string dir = fresh_test_dir();
  const ProcResult r = check_part(dir, corpus("msh_nodes_header_claims_1e9.msh"), {}, 10.0);
  expect_refused_at(r, "part[0].file", "its $Nodes header claims 1000000000 nodes, but the ");
  EXPECT_LT(r.wall_s, 10.0);
}

// Item 14 (fifo_part_file_hang, dev_zero_reader_memory): a FIFO blocked check in open() for ever
// (SIGTERM ignored), /dev/zero was read until memory ran out; both as part, reference and scene file
TEST(CliInputFiles, PipesAndDevicesAreRefusedAtOnce) {
  const std::string dir = fresh_test_dir();
  const std::string fifo = dir + "/fifo.obj", zero = dir + "/zero.obj", scene_fifo = dir + "/scene.toml";
  ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
  ASSERT_EQ(mkfifo(scene_fifo.c_str(), 0600), 0);
  fs::create_symlink("/dev/zero", zero);
  expect_refused_at(check_part(dir, fifo, {}, 10.0), "part[0].file", "is a named pipe (FIFO), not a regular file");
  expect_refused_at(check_part(dir, zero, {}, 10.0), "part[0].file",
                    "is a link to '/dev/zero', which is a character device, not a regular file");
  fs::rename(fifo, fifo + ".msh");
  expect_refused_at(check_part(dir, fifo + ".msh", {}, 10.0), "part[0].file", "is a named pipe (FIFO)");
  expect_refused_at(run_flexframe({"check", "hinged_roof_h127", "--set", "reference[0].file=\"/dev/zero\""}, dir + "/ref", dir, 10.0),
                    "reference[0].file", "reference table '/dev/zero' is a character device, not a regular file");
  const ProcResult scene = run_flexframe({"check", scene_fifo}, dir + "/scene", dir, 10.0);
  EXPECT_FALSE(scene.timed_out) << scene.describe();
  EXPECT_EQ(scene.exit_code, 2) << scene.describe();
  EXPECT_NE(scene.err.find("scene file '" + scene_fifo + "' is a named pipe (FIFO), not a regular file"), std::string::npos)
      << scene.describe();
}

// Item 15 (gmsh_failure_meshed_twice): a unit square at mesh_size 1e-4 (10^8 quads) was meshed
// until its time limit, twice; it is refused before meshing, with the estimate, at the size's key
TEST(CliInputFiles, ACadPartTooFineForTheMemoryIsRefusedBeforeMeshing) {
  const std::string dir = fresh_test_dir();
  const std::string geo = dir + "/plate.geo";
  write_text(geo, kSquareGeo);
  const ProcResult r = check_part(dir, geo, {"part[0].mesh_size=1e-4", "part[0].mesh_time_limit=60"}, 15.0);
  expect_refused_at(r, "part[0].mesh_size", "Gmsh would mesh it into about 1e+08 quads");
  EXPECT_NE(r.err.find("nodes a run can hold within the "), std::string::npos) << r.describe();
}

// Item 13 (gmsh_child_orphaned): SIGKILL of flexframe while Gmsh meshes left the Gmsh child
// running, its time limit gone; it now ends with its parent
TEST(CliInputFiles, TheGmshChildEndsWithAKilledParent) {
  const std::string dir = fresh_test_dir();
  const std::string geo = dir + "/slow.geo";
  write_text(geo, std::string(kSquareGeo) + "Sleep 30;\n");
  Child parent({"check", "clamped_plate_pressure_obj", "--set", "part[0].file=\"" + geo + "\"", "--set",
                "part[0].mesh_time_limit=60"},
               dir + "/check", dir);
  ASSERT_TRUE(parent.started());
  std::vector<pid_t> gmsh;
  for (int k = 0; k < 400 && gmsh.empty() && parent.running(); ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(25));
    gmsh = children_of(parent.pid());
  }
  ASSERT_EQ(gmsh.size(), 1u) << "no Gmsh child seen within 10 s";
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // into the script's Sleep
  ASSERT_TRUE(parent.send(SIGKILL));
  parent.wait(5.0);
  bool gone = false;
  for (int k = 0; k < 100 && !gone; ++k) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    gone = process_ended(gmsh[0]);
  }
  EXPECT_TRUE(gone) << "the Gmsh child " << gmsh[0] << " outlived its parent by 2 s";
  if (!gone) kill(gmsh[0], SIGKILL);
}

}  // namespace
}  // namespace ff::cli::test
