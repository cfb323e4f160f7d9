/// \file frame_export.cpp
/// write_frame_mesh: a frame as an aiScene (built here, owned by the aiScene destructor) handed
/// to Assimp::Exporter.

#include "app/io/frame_export.h"

#include "core/frame/output_file.h"

#include <assimp/DefaultIOSystem.h>
#include <assimp/Exporter.hpp>
#include <assimp/IOStream.hpp>
#include <assimp/scene.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

namespace ff::io {

namespace {

// Assimp's own file streams neither report a short write nor check fclose, so a full disk
// would leave a truncated file behind a successful Export. These streams remember the first
// failure (with its errno) for write_frame_mesh to report.
class CheckedStream : public Assimp::IOStream {
 public:
  CheckedStream(std::FILE* f, int* first_errno) : f_(f), first_errno_(first_errno) {}
  ~CheckedStream() override { close(); }
  size_t Read(void* buffer, size_t size, size_t count) override { return std::fread(buffer, size, count, f_); }
  size_t Write(const void* buffer, size_t size, size_t count) override {
    const size_t n = std::fwrite(buffer, size, count, f_);
    if (n != count) note(errno);
    return n;
  }
  aiReturn Seek(size_t offset, aiOrigin origin) override {
    const int whence = origin == aiOrigin_SET ? SEEK_SET : origin == aiOrigin_CUR ? SEEK_CUR : SEEK_END;
    return std::fseek(f_, static_cast<long>(offset), whence) == 0 ? aiReturn_SUCCESS : aiReturn_FAILURE;
  }
  size_t Tell() const override { return static_cast<size_t>(std::ftell(f_)); }
  size_t FileSize() const override {
    const long at = std::ftell(f_);
    std::fseek(f_, 0, SEEK_END);
    const long size = std::ftell(f_);
    std::fseek(f_, at, SEEK_SET);
    return static_cast<size_t>(size);
  }
  void Flush() override {
    if (std::fflush(f_) != 0) note(errno);
  }
  void close() {
    if (f_ && std::fclose(f_) != 0) note(errno);  // the last buffer reaches the disk here
    f_ = nullptr;
  }

 private:
  void note(int e) {
    if (*first_errno_ == 0) *first_errno_ = e != 0 ? e : EIO;
  }
  std::FILE* f_;
  int* first_errno_;
};

class CheckedIOSystem : public Assimp::DefaultIOSystem {
 public:
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    // an export only writes: opened as every output is, never through a planted link
    std::string why;
    std::FILE* f = std::strchr(mode, 'w') ? open_output_stream(file, &why) : nullptr;
    if (f) opened.push_back(file);
    if (!f) {
      if (first_errno == 0) first_errno = errno;
      if (errno == 0 && refused.empty()) refused = why.empty() ? std::string("asked to read ") + file : std::string(file) + ": " + why;
      return nullptr;
    }
    return new CheckedStream(f, &first_errno);
  }
  void Close(Assimp::IOStream* stream) override { delete stream; }
  int first_errno = 0;
  std::string refused;  // why a file was not opened
  std::vector<std::string> opened;  // every file written, in order
};

// the frames' colour map ends and middle (render/frame_renderer.cpp), linear in RGB here
aiColor4D map_colour(double v, double lo, double hi) {
  constexpr double kLow[3] = {0.230, 0.299, 0.754}, kMid[3] = {0.780, 0.780, 0.800}, kHigh[3] = {0.706, 0.016, 0.150};
  double s = hi > lo && std::isfinite(v) ? std::clamp((v - lo) / (hi - lo), 0.0, 1.0) : 0.5;
  const double* a = s < 0.5 ? kLow : kMid;
  const double* b = s < 0.5 ? kMid : kHigh;
  const double w = s < 0.5 ? 2 * s : 2 * s - 1;
  return aiColor4D(static_cast<float>(a[0] + w * (b[0] - a[0])), static_cast<float>(a[1] + w * (b[1] - a[1])),
                   static_cast<float>(a[2] + w * (b[2] - a[2])), 1.0f);
}

// a mesh of the given faces (point indices) whose vertices are the points they use, in point
// order; faces are renumbered to the vertices
aiMesh* new_mesh(const char* name, const Frame& frame, std::size_t n, const std::vector<std::vector<unsigned>>& faces,
                 const std::vector<double>* colour_values, std::array<double, 2> range, unsigned primitive) {
  std::vector<int> vertex_of(n, -1);
  for (const auto& f : faces)
    for (unsigned v : f) vertex_of[v] = 0;
  unsigned count = 0;
  for (int& v : vertex_of)
    if (v == 0) v = static_cast<int>(count++);
  auto* m = new aiMesh();
  m->mName = name;
  m->mPrimitiveTypes = primitive;
  m->mMaterialIndex = 0;
  m->mNumVertices = count;
  m->mVertices = new aiVector3D[count];
  if (colour_values != nullptr) m->mColors[0] = new aiColor4D[count];
  // u = the point's index: keeps coincident points (a hinge's node pairs) apart when the
  // exporter joins identical vertices, and maps vertices back to results.h5
  m->mTextureCoords[0] = new aiVector3D[count];
  m->mNumUVComponents[0] = 2;
  for (std::size_t i = 0; i < n; ++i) {
    if (vertex_of[i] < 0) continue;
    const unsigned k = static_cast<unsigned>(vertex_of[i]);
    m->mVertices[k] = aiVector3D(static_cast<ai_real>(frame.points[3 * i]), static_cast<ai_real>(frame.points[3 * i + 1]),
                                 static_cast<ai_real>(frame.points[3 * i + 2]));
    if (colour_values != nullptr) m->mColors[0][k] = map_colour((*colour_values)[i], range[0], range[1]);
    m->mTextureCoords[0][k] = aiVector3D(static_cast<ai_real>(i), 0, 0);
  }
  m->mNumFaces = static_cast<unsigned>(faces.size());
  m->mFaces = new aiFace[faces.size()];
  for (std::size_t f = 0; f < faces.size(); ++f) {
    m->mFaces[f].mNumIndices = static_cast<unsigned>(faces[f].size());
    m->mFaces[f].mIndices = new unsigned[faces[f].size()];
    for (std::size_t j = 0; j < faces[f].size(); ++j) m->mFaces[f].mIndices[j] = static_cast<unsigned>(vertex_of[faces[f][j]]);
  }
  return m;
}

}  // namespace

const char* extension(MeshFileFormat format) { return format == MeshFileFormat::obj ? "obj" : "glb"; }

bool write_frame_mesh(const std::string& path, MeshFileFormat format, const RunInfo& info, const Frame& frame,
                      int color_field, std::array<double, 2> range, std::string* error,
                      std::vector<std::string>* files) {
  auto fail = [&](const std::string& why) {
    if (error) *error = "'" + path + "': " + why;
    return false;
  };
  const FrameMesh& mesh = info.mesh;
  const std::size_t n = mesh.point_count();
  if (frame.points.size() != 3 * n) return fail("frame points do not match the mesh");
  const std::vector<double>* colours = nullptr;
  if (color_field >= 0) {
    if (static_cast<std::size_t>(color_field) >= frame.fields.size() ||
        frame.fields[static_cast<std::size_t>(color_field)].size() != n)
      return fail("frame lacks the colour field's values");
    colours = &frame.fields[static_cast<std::size_t>(color_field)];
  }
  for (const auto* cells : {&mesh.lines, &mesh.triangles, &mesh.quads})
    for (std::int32_t v : *cells)
      if (v < 0 || static_cast<std::size_t>(v) >= n) return fail("a mesh cell refers to a point that does not exist");

  std::vector<std::vector<unsigned>> triangles, lines;
  for (std::size_t t = 0; t + 3 <= mesh.triangles.size(); t += 3)
    triangles.push_back({unsigned(mesh.triangles[t]), unsigned(mesh.triangles[t + 1]), unsigned(mesh.triangles[t + 2])});
  for (std::size_t q = 0; q + 4 <= mesh.quads.size(); q += 4) {
    const unsigned a = mesh.quads[q], b = mesh.quads[q + 1], c = mesh.quads[q + 2], d = mesh.quads[q + 3];
    triangles.push_back({a, b, c});
    triangles.push_back({a, c, d});
  }
  for (std::size_t l = 0; l + 2 <= mesh.lines.size(); l += 2)
    lines.push_back({unsigned(mesh.lines[l]), unsigned(mesh.lines[l + 1])});
  if (triangles.empty() && lines.empty()) return fail("the mesh has no cells");

  auto scene = std::make_unique<aiScene>();  // its destructor frees everything attached below
  std::vector<aiMesh*> meshes;
  if (!triangles.empty())
    meshes.push_back(new_mesh("surfaces", frame, n, triangles, colours, range, aiPrimitiveType_TRIANGLE));
  if (!lines.empty()) meshes.push_back(new_mesh("lines", frame, n, lines, colours, range, aiPrimitiveType_LINE));
  scene->mNumMeshes = static_cast<unsigned>(meshes.size());
  scene->mMeshes = new aiMesh*[meshes.size()];
  std::copy(meshes.begin(), meshes.end(), scene->mMeshes);

  auto* material = new aiMaterial();
  const aiString material_name("flexframe_body");
  material->AddProperty(&material_name, AI_MATKEY_NAME);
  const aiColor4D body(0.22f, 0.42f, 0.69f, 1.0f);  // the frames' uniform body colour
  material->AddProperty(&body, 1, AI_MATKEY_COLOR_DIFFUSE);
  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial*[1]{material};

  scene->mRootNode = new aiNode(info.scene_name.empty() ? "flexframe" : info.scene_name);
  scene->mRootNode->mNumMeshes = scene->mNumMeshes;
  scene->mRootNode->mMeshes = new unsigned[scene->mNumMeshes];
  for (unsigned k = 0; k < scene->mNumMeshes; ++k) scene->mRootNode->mMeshes[k] = k;
  if (format == MeshFileFormat::gltf_binary) {
    // z-up world -> glTF's y-up: rotate -90 degrees about x
    aiMatrix4x4::RotationX(static_cast<ai_real>(-M_PI / 2), scene->mRootNode->mTransformation);
  }

  Assimp::Exporter exporter;
  auto* io = new CheckedIOSystem;  // owned by the exporter
  exporter.SetIOHandler(io);
  const char* id = format == MeshFileFormat::obj ? "obj" : "glb2";
  const bool exported = exporter.Export(scene.get(), id, path) == AI_SUCCESS;
  if (files) *files = io->opened;
  const int e = io->first_errno;
  if (!io->refused.empty()) return fail("could not write: " + io->refused);
  if (e != 0)
    return fail(std::string("could not write: ") + (e == ENOSPC || e == EDQUOT ? "disk full (" : "(") +
                std::strerror(e) + ")");
  if (!exported) return fail(std::string("assimp: ") + exporter.GetErrorString());
  return true;
}

}  // namespace ff::io
