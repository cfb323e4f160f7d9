#include "core/scene/mesh_file.h"

namespace ff::scene {

namespace {
MeshFileReader& installed() {
  static MeshFileReader reader;
  return reader;
}
}  // namespace

void set_mesh_file_reader(MeshFileReader reader) { installed() = std::move(reader); }
const MeshFileReader& mesh_file_reader() { return installed(); }

}  // namespace ff::scene
