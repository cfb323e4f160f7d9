#include "app/io/mesh_import.h"

#include <assimp/Importer.hpp>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "core/mesh/generators.h"
#include "core/scene/mesh_file.h"

namespace ff::io {

namespace {

namespace fs = std::filesystem;
using ff::mesh::ShellMesh;
using Vec3 = Eigen::Vector3d;

// how to find the nodes and quads an error message names
constexpr const char* kNumbering = " (0-based numbers: quads in file order, nodes in order of first use by the quads)";

bool fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

// faces of the scene, every mesh instance placed by its node's world transform
struct RawSurface {
  std::vector<Vec3> points;
  std::vector<std::array<int, 4>> quads;
  int triangles = 0, polygons = 0, points_or_lines = 0, faces = 0;
};

void add_mesh(const aiMesh& m, const aiMatrix4x4& X_WN, RawSurface& raw) {
  const int base = static_cast<int>(raw.points.size());
  for (unsigned v = 0; v < m.mNumVertices; ++v) {
    const aiVector3D p = X_WN * m.mVertices[v];
    raw.points.emplace_back(p.x, p.y, p.z);
  }
  for (unsigned f = 0; f < m.mNumFaces; ++f) {
    const aiFace& face = m.mFaces[f];
    ++raw.faces;
    if (face.mNumIndices == 4) {
      raw.quads.push_back({base + static_cast<int>(face.mIndices[0]), base + static_cast<int>(face.mIndices[1]),
                           base + static_cast<int>(face.mIndices[2]), base + static_cast<int>(face.mIndices[3])});
    } else if (face.mNumIndices == 3) {
      ++raw.triangles;
    } else if (face.mNumIndices > 4) {
      ++raw.polygons;
    } else {
      ++raw.points_or_lines;
    }
  }
}

void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& X_WP, RawSurface& raw) {
  const aiMatrix4x4 X_WN = X_WP * node.mTransformation;
  for (unsigned k = 0; k < node.mNumMeshes; ++k) add_mesh(*scene.mMeshes[node.mMeshes[k]], X_WN, raw);
  for (unsigned c = 0; c < node.mNumChildren; ++c) collect(scene, *node.mChildren[c], X_WN, raw);
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// joins coincident vertices (distance <= tol) keeping the first; drops unused ones
void join_vertices(RawSurface& raw, double tol) {
  ShellMesh m;
  m.points = raw.points;
  m.normals.assign(raw.points.size(), Vec3::UnitZ());  // placeholders: assemble() needs a director
  m.quads = raw.quads;
  ff::mesh::AssemblyOptions o;
  const double h = ff::mesh::min_edge_length(m);
  o.merge_tolerance = h > 0 ? tol / h : 0.0;
  const ShellMesh joined = ff::mesh::assemble({m}, o);
  // renumber by first use in the face list
  std::vector<int> id(joined.points.size(), -1);
  raw.points.clear();
  raw.quads = joined.quads;
  for (auto& q : raw.quads)
    for (int& k : q) {
      if (id[k] < 0) {
        id[k] = static_cast<int>(raw.points.size());
        raw.points.push_back(joined.points[k]);
      }
      k = id[k];
    }
}

}  // namespace

bool import_shell_mesh(const std::string& path, ShellMesh& out, std::string* error, const MeshImportOptions& options) {
  const std::string who = "mesh file '" + path + "'";
  std::error_code ec;
  if (!fs::exists(path, ec)) return fail(error, who + " does not exist");
  if (fs::is_directory(path, ec)) return fail(error, who + " is a directory, not a mesh file");

  // JoinIdenticalVertices only: no Triangulate, so quads stay quads
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, aiProcess_JoinIdenticalVertices);
  if (!scene) return fail(error, "cannot read " + who + ": " + importer.GetErrorString());
  if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) return fail(error, who + " was read only partially (incomplete scene)");

  RawSurface raw;
  if (scene->mRootNode) collect(*scene, *scene->mRootNode, aiMatrix4x4(), raw);
  else
    for (unsigned k = 0; k < scene->mNumMeshes; ++k) add_mesh(*scene->mMeshes[k], aiMatrix4x4(), raw);

  if (raw.faces == 0) return fail(error, who + " contains no faces (a shell mesh needs quads)");
  const int not_quads = raw.faces - static_cast<int>(raw.quads.size());
  if (not_quads > 0) {
    std::string msg = who + ": " + std::to_string(not_quads) + " of " + std::to_string(raw.faces) +
                      " faces are not quads (" + std::to_string(raw.triangles) + " triangles, " +
                      std::to_string(raw.polygons) + " polygons with more than 4 vertices, " +
                      std::to_string(raw.points_or_lines) +
                      " points or lines); shell elements are 4-node quads and the importer neither "
                      "triangulates nor recombines faces, so export the surface with quad faces only";
    const std::string ext = lower_extension(path);
    if (ext == ".stl" || ext == ".gltf" || ext == ".glb")
      msg += " (STL and glTF 2.0 store triangles only: use OBJ or PLY for quad meshes)";
    return fail(error, msg);
  }

  Vec3 lo = raw.points.front(), hi = raw.points.front();
  for (const auto& p : raw.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  join_vertices(raw, 1e-9 * (hi - lo).norm());

  ShellMesh m;
  m.points = std::move(raw.points);
  m.quads = std::move(raw.quads);
  {
    ShellMesh fixed = m;
    std::string why;
    if (!ff::mesh::orient_consistently(fixed, &why)) return fail(error, who + ": " + why + kNumbering);
    int flipped = 0;
    for (int q = 0; q < m.quad_count(); ++q) flipped += fixed.quads[q] != m.quads[q];
    if (flipped > 0 && !options.reorient)
      return fail(error, who + ": the faces are not consistently oriented (" + std::to_string(flipped) + " of " +
                             std::to_string(m.quad_count()) +
                             " quads wind against their neighbours); fix the winding or import with reorient");
    m.quads = std::move(fixed.quads);
  }
  ff::mesh::compute_area_weighted_normals(m);
  ff::mesh::compute_frames(m, options.frame_reference);
  m.patches.clear();
  ff::mesh::complete_layout(m, fs::path(path).stem().string());
  m.patches[0].description = "imported from " + fs::path(path).filename().string();

  const ff::mesh::MeshCheck check = ff::mesh::validate(m);
  if (!check.ok()) {
    std::string summary = check.summary();
    if (!summary.empty() && summary.back() == '\n') summary.pop_back();
    return fail(error, who + " is not a valid shell mesh" + kNumbering + ":\n" + summary);
  }
  out = std::move(m);
  return true;
}

ff::scene::SceneContext scene_context() {
  ff::scene::SceneContext ctx;
  ctx.mesh_reader = [](const std::string& path, ShellMesh& out, std::string* error) {
    return import_shell_mesh(path, out, error);
  };
  return ctx;
}

bool write_shell_mesh_obj(const std::string& path, const ShellMesh& mesh, std::string* error) {
  std::ofstream f(path);
  if (!f) return fail(error, "cannot open '" + path + "' for writing");
  f.precision(17);
  f << "# FlexFrame shell mesh: " << mesh.node_count() << " nodes, " << mesh.quad_count() << " quads\n";
  for (const auto& p : mesh.points) f << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
  for (const auto& q : mesh.quads) f << "f " << q[0] + 1 << " " << q[1] + 1 << " " << q[2] + 1 << " " << q[3] + 1 << "\n";
  if (!f) return fail(error, "writing '" + path + "' failed");
  return true;
}

bool write_shell_mesh_ply(const std::string& path, const ShellMesh& mesh, std::string* error) {
  std::ofstream f(path);
  if (!f) return fail(error, "cannot open '" + path + "' for writing");
  f.precision(17);
  f << "ply\nformat ascii 1.0\ncomment FlexFrame shell mesh\nelement vertex " << mesh.node_count()
    << "\nproperty double x\nproperty double y\nproperty double z\nelement face " << mesh.quad_count()
    << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (const auto& p : mesh.points) f << p.x() << " " << p.y() << " " << p.z() << "\n";
  for (const auto& q : mesh.quads) f << "4 " << q[0] << " " << q[1] << " " << q[2] << " " << q[3] << "\n";
  if (!f) return fail(error, "writing '" + path + "' failed");
  return true;
}

}  // namespace ff::io
