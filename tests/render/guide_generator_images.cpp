// Pictures of the scene mesh generators for docs/guide/writing-a-scene.md (not a test):
//   build/tests/render/guide_generator_images docs/guide/img
// Each picture is a [[part]] table built by the scene code itself (core/scene/mesh_generator_keys.h),
// drawn by the project's renderer: the quads in neutral grey and the named edges of one patch as
// tubes coloured by their number (the colour bar: 0 = u=0, 1 = u=1, 2 = v=0, 3 = v=1); the guide
// names them next to the picture. The mesh axis (where a generator has one) is a grey tube from
// the origin.
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/mesh/node_sets.h"
#include "core/scene/mesh_generator_keys.h"
#include "core/scene/shell_scene.h"
#include "render/frame_renderer.h"
#include "render/graphics_context.h"

namespace {

struct Picture {
  std::string file, title, mesh, patch;
  std::array<double, 3> view;  // from the centre towards the eye
  std::vector<std::array<double, 3>> axis;  // optional grey segment (two points)
};

ff::mesh::ShellMesh build(const std::string& mesh_table) {
  const std::string text = "[scene]\nname = \"img\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = [\"elastic\"]\n[[part]]\n" + mesh_table +
                           "\n[[material]]\nyoungs_modulus = 1.0\nthickness = 0.1\n[[probe]]\nname = \"w\"\n"
                           "direction = [0.0, 0.0, 1.0]\n[solver]\n";
  const ff::scene::Document d = ff::scene::validate(ff::scene::shell_static_schema(), text, "img.toml");
  return ff::scene::generate_mesh(d, 0);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  const std::string out = argv[1];
  std::filesystem::create_directories(out);
  const std::vector<Picture> pictures = {
      {"generator_rectangular_plate.png", "rectangular_plate (origin 0.5, 0.5, 0)",
       "generator = \"rectangular_plate\"\nlength = 2.0\nwidth = 1.0\norigin = [0.5, 0.5, 0.0]\nn1 = 8\nn2 = 4", "plate",
       {-0.6, -1.0, 1.2}, {{0, 0, 0}, {0, 0, 0.6}}},
      {"generator_l_plate.png", "l_plate (length 4, length2 3, width 1)",
       "generator = \"l_plate\"\nlength = 4.0\nlength2 = 3.0\nwidth = 1.0\nn1 = 6\nn2 = 2", "arm2", {0.0, 0.0, 1.0}, {}},
      {"generator_folded_plate.png", "folded_plate (fold_angle 90)",
       "generator = \"folded_plate\"\nlength = 2.0\nlength2 = 1.0\nwidth = 1.0\nn1 = 8\nn2 = 4\nn3 = 4", "leg2",
       {1.0, -1.6, 0.9}, {}},
      {"generator_cylinder.png", "cylinder (0 to 120 deg)",
       "generator = \"cylinder\"\nradius = 1.0\nlength = 2.0\nstart_angle = 0.0\nend_angle = 120.0\nn1 = 12\nn2 = 8",
       "cylinder", {1.6, 1.0, 0.8}, {{0, 0, 0}, {0, 0, 2.4}}},
      {"generator_annulus_slit.png", "annulus (inner_radius 0.5, slit)",
       "generator = \"annulus\"\nradius = 1.0\ninner_radius = 0.5\nslit = true\nn1 = 4\nn2 = 32", "annulus",
       {0.3, -1.0, 1.2}, {{0, 0, 0}, {0, 0, 0.6}}},
      {"generator_disk.png", "annulus without a hole (disk)",
       "generator = \"annulus\"\nradius = 1.0\nn1 = 4\nn2 = 32", "annulus", {0.0, 0.0, 1.0}, {}},
      {"generator_spherical_cap.png", "spherical_cap (polar 20 to 90, 0 to 90 deg)",
       "generator = \"spherical_cap\"\nradius = 1.0\npolar_start = 20.0\npolar_end = 90.0\nend_angle = 90.0\nn1 = 8\nn2 = 8",
       "cap", {1.0, 0.8, 0.7}, {{0, 0, 0}, {0, 0, 1.3}}},
      {"generator_spherical_cap_closed.png", "spherical_cap without a hole",
       "generator = \"spherical_cap\"\nradius = 1.0\npolar_end = 90.0\nn1 = 4\nn2 = 32", "cap", {0.6, -0.8, 1.0}, {}},
  };
  std::string error;
  auto gc = ff::render::GraphicsContext::create(&error);
  if (!gc) {
    std::fprintf(stderr, "no graphics context: %s\n", error.c_str());
    return 1;
  }
  for (const Picture& pic : pictures) {
    const ff::mesh::ShellMesh m = build(pic.mesh);
    ff::RunInfo info;
    info.scene_name = pic.title;
    auto& p = info.mesh.reference_points;
    for (const auto& x : m.points) p.insert(p.end(), {x.x(), x.y(), x.z()});
    for (const auto& q : m.quads) info.mesh.quads.insert(info.mesh.quads.end(), {q[0], q[1], q[2], q[3]});
    std::vector<double> edge(m.node_count(), 1.5);  // mid grey of the colour map
    // each named edge of the patch as its own polyline of duplicated points, valued 0..3
    const int k_patch = m.find_patch(pic.patch);
    for (int e = 0; e < 4 && k_patch >= 0; ++e) {
      if (m.patches[k_patch].edge_names[e].empty()) continue;
      const ff::mesh::Patch& pa = m.patches[k_patch];
      std::vector<int> ids;  // in grid order along the edge (not sorted), so the polyline follows it
      if (e < 2)
        for (int j = 0; j <= pa.nv; ++j) ids.push_back(pa.node(e == 0 ? 0 : pa.nu, j));
      else
        for (int i = 0; i <= pa.nu; ++i) ids.push_back(pa.node(i, e == 2 ? 0 : pa.nv));
      const int first = static_cast<int>(p.size() / 3);
      for (int id : ids) {
        const auto& x = m.points[id];
        p.insert(p.end(), {x.x(), x.y(), x.z()});
        edge.push_back(e);
      }
      for (std::size_t k = 0; k + 1 < ids.size(); ++k)
        info.mesh.lines.insert(info.mesh.lines.end(), {first + static_cast<int>(k), first + static_cast<int>(k) + 1});
    }
    if (pic.axis.size() == 2) {
      const int first = static_cast<int>(p.size() / 3);
      for (const auto& a : pic.axis) p.insert(p.end(), a.begin(), a.end()), edge.push_back(1.5);
      info.mesh.lines.insert(info.mesh.lines.end(), {first, first + 1});
    }
    info.fields = {{"edge", "", "edge"}};
    ff::Frame f;
    f.points = p;
    f.fields = {edge};
    ff::render::FrameStyle style;
    style.width = 720;
    style.height = 540;
    style.color_field = "edge";
    style.color_min = 0;
    style.color_max = 3;
    style.title = pic.title;
    style.show_base = false;
    style.camera.view_direction = pic.view;
    style.camera.view_up = {0, 0, 1};
    if (pic.view[0] == 0 && pic.view[1] == 0) style.camera.view_up = {0, 1, 0};
    style.antialias = true;
    ff::render::FrameRenderer r(*gc, info, style);
    const std::string path = out + "/" + pic.file;
    if (!r.render_png(f, path, &error)) {
      std::fprintf(stderr, "%s: %s\n", path.c_str(), error.c_str());
      return 1;
    }
    std::printf("%s\n", path.c_str());
  }
  return 0;
}
