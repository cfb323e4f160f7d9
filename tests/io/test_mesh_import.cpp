// Shell-mesh import through assimp (app/io/mesh_import.h): the committed OBJ/PLY plates import
// to the generator's plate, generated meshes survive a write/import round trip, curved files
// get outward area-weighted normals, and every refusal names the file and the reason.
// Scratch files go to ${FF_BINARY_DIR}/test_out/mesh_import/.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <thread>

#include "app/io/mesh_import.h"
#include "core/mesh/generators.h"
#include "core/scene/mesh_file.h"

using namespace ff::mesh;
using Eigen::Vector3d;
namespace fs = std::filesystem;

namespace {

std::string asset(const std::string& name) { return std::string(FF_SOURCE_DIR) + "/assets/meshes/" + name; }

std::string scratch(const std::string& name) {
  const fs::path dir = fs::path(FF_BINARY_DIR) / "test_out" / "mesh_import";
  fs::create_directories(dir);
  return (dir / name).string();
}

std::string write_text(const std::string& name, const std::string& text) {
  const std::string path = scratch(name);
  std::ofstream(path) << text;
  return path;
}

std::array<int, 4> canonical(std::array<int, 4> q) {  // rotate the smallest id first, keep the cycle
  std::rotate(q.begin(), std::min_element(q.begin(), q.end()), q.end());
  return q;
}

// `got` has the same points (to tol, in any order) and the same quads with the same winding
void expect_same_mesh(const ShellMesh& got, const ShellMesh& want, double tol) {
  ASSERT_EQ(got.node_count(), want.node_count());
  ASSERT_EQ(got.quad_count(), want.quad_count());
  std::vector<int> to_want(got.node_count(), -1), hits(want.node_count(), 0);
  for (int i = 0; i < got.node_count(); ++i) {
    double best = 1e300;
    for (int j = 0; j < want.node_count(); ++j) {
      const double d = (got.points[i] - want.points[j]).norm();
      if (d < best) {
        best = d;
        to_want[i] = j;
      }
    }
    EXPECT_LT(best, tol) << "imported node " << i << " matches no generated node";
    ++hits[to_want[i]];
  }
  for (int j = 0; j < want.node_count(); ++j) { EXPECT_EQ(hits[j], 1) << "generated node " << j; }
  std::map<std::array<int, 4>, int> quads;
  for (const auto& q : want.quads) ++quads[canonical(q)];
  for (const auto& q : got.quads) {
    const std::array<int, 4> mapped{to_want[q[0]], to_want[q[1]], to_want[q[2]], to_want[q[3]]};
    EXPECT_EQ(quads[canonical(mapped)]--, 1) << "imported quad has no generated counterpart with the same winding";
  }
}

std::string import_error(const std::string& path, const ff::io::MeshImportOptions& o = {}) {
  ShellMesh m;
  std::string error;
  EXPECT_FALSE(ff::io::import_shell_mesh(path, m, &error, o)) << path;
  EXPECT_EQ(m.node_count(), 0) << "out must stay untouched on failure";
  return error;
}

std::string base64(const unsigned char* data, std::size_t n) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string s;
  for (std::size_t i = 0; i < n; i += 3) {
    const unsigned v = (data[i] << 16) | ((i + 1 < n ? data[i + 1] : 0) << 8) | (i + 2 < n ? data[i + 2] : 0);
    s += k[(v >> 18) & 63];
    s += k[(v >> 12) & 63];
    s += i + 1 < n ? k[(v >> 6) & 63] : '=';
    s += i + 2 < n ? k[v & 63] : '=';
  }
  return s;
}

}  // namespace

TEST(MeshImport, CommittedObjAndPlyPlatesAreTheGeneratorsPlate) {
  const ShellMesh want = rectangular_plate(2.0, 1.0, 4, 4);
  for (const char* file : {"plate_4x4.obj", "plate_4x4.ply"}) {
    SCOPED_TRACE(file);
    ShellMesh got;
    std::string error;
    ASSERT_TRUE(ff::io::import_shell_mesh(asset(file), got, &error)) << error;
    expect_same_mesh(got, want, 1e-7);
    for (int i = 0; i < got.node_count(); ++i) {
      EXPECT_LT((got.normals[i] - Vector3d::UnitZ()).norm(), 1e-12);
      EXPECT_LT((got.frames[i].col(0) - Vector3d::UnitX()).norm(), 1e-12);
    }
    EXPECT_NEAR(total_area(got), 2.0, 1e-6);
    ASSERT_EQ(got.patches.size(), 1u);
    EXPECT_EQ(got.patches[0].name, "plate_4x4");
    EXPECT_FALSE(got.patches[0].structured());
    EXPECT_TRUE(validate(got).ok()) << validate(got).summary();
  }
}

TEST(MeshImport, CurvedObjPatchGetsOutwardAreaWeightedNormals) {
  ShellMesh got;
  std::string error;
  ASSERT_TRUE(ff::io::import_shell_mesh(asset("cylinder_patch_4x3.obj"), got, &error)) << error;
  EXPECT_EQ(got.node_count(), 20);
  EXPECT_EQ(got.quad_count(), 12);
  CylinderPatch spec;  // R = 1 about z, phi in [0, 90 deg], z in [0, 1]
  expect_same_mesh(got, cylindrical_patch(spec, 4, 3), 1e-6);
  for (int i = 0; i < got.node_count(); ++i) {
    EXPECT_NEAR(got.points[i].head<2>().norm(), 1.0, 1e-6);
    Vector3d radial = got.points[i];
    radial.z() = 0;
    radial.normalize();
    // area-weighted facet normals: exact (radial) where equal facets meet symmetrically, half a
    // facet angle (pi/16) off at the straight edges phi = 0 and phi = 90 deg; never axial
    const bool edge = std::abs(got.points[i].x()) < 1e-6 || std::abs(got.points[i].y()) < 1e-6;
    EXPECT_NEAR(got.normals[i].dot(radial), edge ? std::cos(std::numbers::pi / 16) : 1.0, 1e-6) << "node " << i;
    EXPECT_NEAR(got.normals[i].z(), 0.0, 1e-6);
  }
  EXPECT_TRUE(validate(got).ok()) << validate(got).summary();
}

TEST(MeshImport, GeneratedMeshesRoundTripThroughObjAndPly) {
  const ShellMesh hemi = hemisphere_quarter(6, 5);
  const ShellMesh lplate = l_plate_simo_fox_rifai(5, 2);
  for (const auto& [name, want] : {std::pair{"hemisphere", &hemi}, std::pair{"lplate", &lplate}}) {
    for (const char* ext : {".obj", ".ply"}) {
      SCOPED_TRACE(std::string(name) + ext);
      const std::string path = scratch(std::string(name) + ext);
      std::string error;
      ASSERT_TRUE(std::string(ext) == ".obj" ? ff::io::write_shell_mesh_obj(path, *want, &error)
                                             : ff::io::write_shell_mesh_ply(path, *want, &error))
          << error;
      ShellMesh got;
      ASSERT_TRUE(ff::io::import_shell_mesh(path, got, &error)) << error;
      expect_same_mesh(got, *want, 1e-4);  // assimp stores float coordinates
      EXPECT_NEAR(total_area(got), total_area(*want), 1e-5 * total_area(*want));
    }
  }
  // the hemisphere's imported normals point outward like the exact ones
  ShellMesh got;
  std::string error;
  ASSERT_TRUE(ff::io::import_shell_mesh(scratch("hemisphere.obj"), got, &error)) << error;
  for (int i = 0; i < got.node_count(); ++i) { EXPECT_GT(got.normals[i].dot(got.points[i].normalized()), 0.98); }
}

TEST(MeshImport, TriangleMeshesAreRefusedWithCounts) {
  const std::string path = write_text("tri_and_quad.obj",
                                      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                                      "f 1 2 3 4\nf 2 5 6\nf 2 6 3\n");
  const std::string e = import_error(path);
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_NE(e.find("2 of 3 faces are not quads (2 triangles"), std::string::npos) << e;

  const std::string ngon = write_text("pentagon.obj", "v 0 0 0\nv 1 0 0\nv 1.5 0.5 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4 5\n");
  EXPECT_NE(import_error(ngon).find("1 polygons with more than 4 vertices"), std::string::npos);

  const std::string stl = write_text("triangle.stl",
                                     "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                     "vertex 0 1 0\nendloop\nendfacet\nendsolid t\n");
  const std::string es = import_error(stl);
  EXPECT_NE(es.find("1 of 1 faces are not quads"), std::string::npos) << es;
  EXPECT_NE(es.find("STL and glTF 2.0 store triangles only"), std::string::npos) << es;

  // glTF 2.0 with one embedded triangle
  const float xyz[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::string gltf = write_text(
      "triangle.gltf",
      R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0}],)"
      R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"mode":4}]}],)"
      R"("accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]}],)"
      R"("bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36}],)"
      R"("buffers":[{"byteLength":36,"uri":"data:application/octet-stream;base64,)" +
          base64(reinterpret_cast<const unsigned char*>(xyz), sizeof xyz) + R"("}]})");
  const std::string eg = import_error(gltf);
  EXPECT_NE(eg.find("not quads"), std::string::npos) << eg;
  EXPECT_NE(eg.find("triangle.gltf"), std::string::npos) << eg;
}

TEST(MeshImport, MissingAndUnreadableFiles) {
  const std::string missing = scratch("no_such_mesh.obj");
  fs::remove(missing);
  const std::string e = import_error(missing);
  EXPECT_EQ(e, "mesh file '" + missing + "' does not exist");
  EXPECT_NE(import_error(scratch("")).find("is a directory"), std::string::npos);
  const std::string junk = write_text("junk.xyzzy", "this is not a mesh\n");
  EXPECT_NE(import_error(junk).find("cannot read mesh file"), std::string::npos) << import_error(junk);
}

TEST(MeshImport, InconsistentWindingIsRefusedOrRepaired) {
  // two quads sharing the edge 2-3; the second is wound clockwise about +z
  const std::string path = write_text("mixed_winding.obj",
                                      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 2 1 0\n"
                                      "f 1 2 3 4\nf 2 3 6 5\n");
  const std::string e = import_error(path);
  EXPECT_NE(e.find("not consistently oriented (1 of 2 quads"), std::string::npos) << e;
  ff::io::MeshImportOptions o;
  o.reorient = true;
  ShellMesh m;
  std::string error;
  ASSERT_TRUE(ff::io::import_shell_mesh(path, m, &error, o)) << error;
  for (int q = 0; q < m.quad_count(); ++q) { EXPECT_LT((quad_normal(m, q) - Vector3d::UnitZ()).norm(), 1e-12); }
  EXPECT_TRUE(validate(m).ok());
}

TEST(MeshImport, NonManifoldAndDegenerateFilesAreRefused) {
  const std::string t = write_text("t_junction.obj",
                                   "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 1 -1 0\nv 0 -1 0\nv 1 0 1\nv 0 0 1\n"
                                   "f 1 2 3 4\nf 2 1 6 5\nf 1 2 7 8\n");
  EXPECT_NE(import_error(t).find("non-manifold"), std::string::npos) << import_error(t);
  const std::string flat = write_text("collinear.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 1 1 0\nf 1 2 3 4\n");
  const std::string e = import_error(flat);
  EXPECT_NE(e.find("not a valid shell mesh"), std::string::npos) << e;
  EXPECT_NE(e.find("degenerate quad"), std::string::npos) << e;
}

// Issue 11 (import keeps what the file says): the same two quads with every face's corners
// written separately stay 8 nodes (a slit stays open) unless welding is asked for.
TEST(MeshImport, SplitVerticesStayApartUnlessWelded) {
  const std::string path = write_text("split.obj",
                                      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                                      "v 1 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\n"
                                      "vn 0 0 1\nvn 0 0 0.999\n"
                                      "f 1//1 2//1 3//1 4//1\nf 5//2 6//2 7//2 8//2\n");
  ShellMesh m;
  std::string error;
  ASSERT_TRUE(ff::io::import_shell_mesh(path, m, &error)) << error;
  EXPECT_EQ(m.node_count(), 8);
  ff::io::MeshImportOptions weld;
  weld.weld_tolerance = 1e-6;
  ShellMesh w;
  ASSERT_TRUE(ff::io::import_shell_mesh(path, w, &error, weld)) << error;
  EXPECT_EQ(w.node_count(), 6);
  EXPECT_EQ(w.fold_count(), 0);  // the file normals agree (0.999 normalizes to +z)
  EXPECT_TRUE(validate(w).ok()) << validate(w).summary();
}

// A generated slit annulus written as OBJ (the lips are separate vertices) imports with the
// generator's node count, and the file's normals are its directors to round-off.
TEST(MeshImport, SlitAnnulusKeepsItsNodesAndFileNormals) {
  AnnularSector spec;
  spec.phi1 = 2 * std::numbers::pi;
  spec.slit = true;
  const ShellMesh want = annular_sector(spec, 2, 12);
  const std::string path = scratch("slit_annulus.obj");
  std::string error;
  ASSERT_TRUE(ff::io::write_shell_mesh_obj(path, want, &error, true)) << error;
  ShellMesh got;
  ASSERT_TRUE(ff::io::import_shell_mesh(path, got, &error)) << error;
  EXPECT_EQ(got.node_count(), want.node_count());
  expect_same_mesh(got, want, 1e-12);
  EXPECT_NE(got.patches[0].description.find("directors from the file's normals"), std::string::npos);
}

// Issue 12, finding 1-3 and 8: malformed files are refused with the file named, never a crash or hang.
TEST(MeshImport, MalformedFilesAreRefused) {
  const std::string head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                           "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                           "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
  for (const char* face : {"4 0 1 999 3\n", "4 0 1 -1 3\n", "4 0 1 2147483647 3\n", "4 0 1 2 4\n"}) {
    const std::string e = import_error(write_text("bad_index.ply", head + face));
    EXPECT_NE(e.find("bad_index.ply"), std::string::npos) << e;
  }
  EXPECT_NE(import_error(write_text("no_end.ply", "ply\nformat ascii 1.0\nelement vertex 4\n")).find("end_header"),
            std::string::npos);
  for (const char* v : {"nan", "inf", "1e308"}) {
    const std::string e = import_error(write_text("bad_coord.obj", std::string("v 0 0 0\nv 1 0 0\nv 1 1 ") + v +
                                                                      "\nv 0 1 0\nf 1 2 3 4\n"));
    EXPECT_NE(e.find("line 3"), std::string::npos) << e;
  }
  const std::string empty_face = import_error(write_text("empty_face.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf\nf 1 2 3 4\n"));
  EXPECT_NE(empty_face.find("line 5"), std::string::npos) << empty_face;
  const std::string range = import_error(write_text("range.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 9\n"));
  EXPECT_NE(range.find("line 5: vertex 9 does not exist"), std::string::npos) << range;
}

// Issue 48, item 7: an STL file that does not end as its format requires is refused, saying where,
// instead of being read as a smaller mesh (assimp read a file cut inside facet 26 as 26 triangles,
// one with random bytes inside facet 20 as 20). The intact plate: 32 triangles in ASCII.
TEST(MeshImport, DamagedStlFilesAreRefusedSayingWhere) {
  std::ifstream in(std::string(FF_SOURCE_DIR) + "/tests/io/data/stl/plate_32_triangles.stl", std::ios::binary);
  const std::string intact((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(intact.size(), 3675u);
  ff::io::MeshImportOptions split;
  split.triangles = TriangleHandling::split;
  ShellMesh m;
  std::string e;
  ASSERT_TRUE(ff::io::import_shell_mesh(write_text("intact.stl", intact), m, &e, split)) << e;
  EXPECT_EQ(m.quad_count(), 3 * 32);

  const std::string cut = import_error(write_text("cut.stl", intact.substr(0, 2970)), split);
  EXPECT_NE(cut.find("cut.stl' ends inside facet 26 (line 182, in the middle of 'endlo') with no 'endsolid'"),
            std::string::npos) << cut;
  std::size_t facet_20 = 0;
  for (int k = 0; k < 20; ++k) facet_20 = intact.find("facet normal", facet_20 + 1);
  std::string nul = intact;
  nul.insert(intact.find("vertex", facet_20) + 7, std::string("1\0x", 3));
  const std::string with_nul = import_error(write_text("nul.stl", nul), split);
  EXPECT_NE(with_nul.find("inside facet 20: a byte that is not text (0x00)"), std::string::npos) << with_nul;
  const std::string no_end = import_error(write_text("no_end.stl", intact.substr(0, intact.rfind("endsolid"))), split);
  EXPECT_NE(no_end.find("ends after facet 32 with no 'endsolid'"), std::string::npos) << no_end;
  const std::string junk = import_error(write_text("junk.stl", intact + "facet normal 0 0 1\n"), split);
  EXPECT_NE(junk.find("expected another 'solid' or the end of the file, found 'facet'"), std::string::npos) << junk;
  std::string four = intact;
  four.insert(four.find("  endloop"), "    vertex 1 1 0\n");
  const std::string quad = import_error(write_text("four_vertices.stl", four), split);
  EXPECT_NE(quad.find("line 7, inside facet 1: expected 'endloop', found 'vertex'"), std::string::npos) << quad;

  // binary: 80 header bytes (this one begins "solid", as many exporters write), the count, 50
  // bytes a triangle; exactly that many bytes, or it is refused
  std::string binary = "solid binary plate";
  binary.resize(80, ' ');
  const std::uint32_t n = 2;
  binary.append(reinterpret_cast<const char*>(&n), 4);
  const float tris[2][12] = {{0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 1, 0}, {0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 1, 0}};
  for (const auto& t : tris) {
    binary.append(reinterpret_cast<const char*>(t), sizeof t);
    binary.append(2, '\0');
  }
  ASSERT_TRUE(ff::io::import_shell_mesh(write_text("binary.stl", binary), m, &e, split)) << e;
  EXPECT_EQ(m.quad_count(), 6);
  const std::string short_binary = import_error(write_text("binary_cut.stl", binary.substr(0, binary.size() - 1)), split);
  EXPECT_NE(short_binary.find("is not a complete binary STL: its header counts 2 triangles, which take 84 + 50 x 2 = 184 "
                              "bytes, but the file has 183 (cut short)"),
            std::string::npos) << short_binary;
  const std::string long_binary = import_error(write_text("binary_long.stl", binary + "extra"), split);
  EXPECT_NE(long_binary.find("(other bytes follow them)"), std::string::npos) << long_binary;
}

// Issue 48, item 14: a mesh file that is not a regular file is refused before it is opened (a FIFO
// blocked open() for ever, a link to /dev/zero read without end), and one larger than the memory
// limit before it is read; a link to a regular file is ordinary input. Should the refusal be
// missing, a writer opens the FIFO after a few seconds, so that the test fails instead of hanging.
TEST(MeshImport, OnlyRegularFilesWithinTheMemoryLimitAreRead) {
  const auto start = std::chrono::steady_clock::now();
  for (const char* name : {"fifo.obj", "fifo.ply", "fifo.stl", "fifo.msh", "fifo.inp"}) {
    SCOPED_TRACE(name);
    const std::string fifo = scratch(name);
    fs::remove(fifo);
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    std::atomic<bool> done{false};
    std::thread unblock([&] {  // after 3 s, every open of the FIFO for reading returns (at its end)
      for (int k = 0; !done; ++k) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        if (k < 300) continue;
        const int fd = open(fifo.c_str(), O_WRONLY | O_NONBLOCK);
        if (fd >= 0) close(fd);
      }
    });
    ff::scene::MeshFileRequest q;
    q.path = fifo;
    q.time_limit_seconds = 5;  // should Gmsh read it
    ShellMesh m;
    ff::scene::MeshFileError e;
    EXPECT_FALSE(ff::io::read_mesh_file(q, m, e, 1e9));
    done = true;
    unblock.join();
    EXPECT_NE(e.message.find(name), std::string::npos) << e.message;
    EXPECT_NE(e.message.find(" is a named pipe (FIFO), not a regular file"), std::string::npos) << e.message;
    fs::remove(fifo);
  }
  for (const char* name : {"zero.obj", "zero.ply", "zero.stl", "zero.msh", "zero.step"}) {
    SCOPED_TRACE(name);
    const std::string link = scratch(name);
    fs::remove(link);
    fs::create_symlink("/dev/zero", link);
    ff::scene::MeshFileRequest q;
    q.path = link;
    q.mesh_size = fs::path(link).extension() == ".step" ? 0.25 : 0.0;
    q.time_limit_seconds = 2;  // should Gmsh read it
    ShellMesh m;
    ff::scene::MeshFileError e;
    EXPECT_FALSE(ff::io::read_mesh_file(q, m, e, 1e9));
    EXPECT_NE(e.message.find("is a link to '/dev/zero', which is a character device, not a regular file"), std::string::npos)
        << e.message;
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0);

  const std::string link = scratch("link_to_plate.obj");
  fs::remove(link);
  fs::create_symlink(asset("plate_8x8_unit.obj"), link);
  ShellMesh m;
  std::string e;
  EXPECT_TRUE(ff::io::import_shell_mesh(link, m, &e)) << e;
  ff::io::MeshImportOptions small;
  small.memory_limit_bytes = 1000;
  e = import_error(asset("plate_8x8_unit.obj"), small);
  EXPECT_NE(e.find(", more than the 1000 bytes of memory this machine allows"), std::string::npos) << e;
}
