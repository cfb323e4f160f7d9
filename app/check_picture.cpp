#include "app/check_picture.h"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "app/input_error.h"
#include "render/graphics_context.h"

namespace ff::app {

namespace fs = std::filesystem;

namespace {

// white mixed into the palette's colours: parts beneath everything, filled groups and loads over them
constexpr double kPartTint = 0.55, kFillTint = 0.3;
// up to this many groups and entries, each label on the picture says all its legend line says
constexpr std::size_t kFullLabels = 12;

// the node of `nodes` nearest to their centroid: a point of the set to pin its label to (the
// centroid of a curved edge or an L-shaped set may lie off the set)
int representative_node(const mesh::ShellMesh& m, const std::vector<int>& nodes) {
  if (nodes.empty()) return -1;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (int v : nodes) centroid += m.points[v];
  centroid /= static_cast<double>(nodes.size());
  int best = nodes.front();
  double best_d = std::numeric_limits<double>::infinity();
  for (int v : nodes)
    if (const double d = (m.points[v] - centroid).squaredNorm(); d < best_d) best = v, best_d = d;
  return best;
}

std::string count_of(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

std::vector<std::int32_t> to_int32(const std::vector<int>& v) { return {v.begin(), v.end()}; }

}  // namespace

render::MeshPicture selections_picture(const scene::SceneSelections& s) {
  const mesh::ShellMesh& m = s.mesh;
  render::MeshPicture pic;
  for (const Eigen::Vector3d& x : m.points) pic.points.insert(pic.points.end(), {x.x(), x.y(), x.z()});
  for (const auto& q : m.quads) pic.quads.insert(pic.quads.end(), {q[0], q[1], q[2], q[3]});
  pic.title = s.scene_name;
  pic.subtitle = count_of(m.points.size(), "node", "nodes") + ", " + count_of(m.quads.size(), "quad", "quads") + ", " +
                 count_of(s.part_names.size(), "part", "parts") + "; isometric view" +
                 (s.entries.empty() ? "" : "; faint dots lie behind the surface");

  // the pieces of the structure, pale, beneath everything else: its patches where there are several
  // (a part's own, or those l_plate and folded_plate name: select = "patch_edge" names them), else
  // its parts; one piece is the whole mesh, nothing to tell apart
  const bool by_patch = m.patches.size() > 1 && m.quad_patch.size() == m.quads.size();
  const std::size_t pieces = by_patch ? m.patches.size() : s.part_names.size();
  if (pieces > 1)
    for (std::size_t p = 0; p < pieces; ++p) {
      render::PictureItem item;
      std::vector<int> nodes;
      const std::vector<int>& owner = by_patch ? m.quad_patch : s.quad_part;
      for (int q = 0; q < m.quad_count(); ++q)
        if (q < static_cast<int>(owner.size()) && owner[q] == static_cast<int>(p)) {
          item.quads.push_back(q);
          nodes.insert(nodes.end(), m.quads[q].begin(), m.quads[q].end());
        }
      const std::string& name = by_patch ? m.patches[p].name : s.part_names[p];
      const bool a_part = std::find(s.part_names.begin(), s.part_names.end(), name) != s.part_names.end();
      item.color = render::picture_color(static_cast<int>(p), kPartTint);
      item.label = (a_part ? "part '" : "patch '") + name + "'";
      item.legend = item.label + " (" + count_of(item.quads.size(), "quad", "quads") + ")";
      item.anchor = representative_node(m, nodes);
      pic.items.push_back(std::move(item));
    }
  // the next strong colour: after the hues of the pieces, so that no dot sits on its own hue
  int strong = pieces > 1 ? static_cast<int>(pieces) : 0;
  for (const mesh::MeshGroup& g : m.groups) {
    render::PictureItem item;
    item.color = render::picture_color(strong++, g.dimension == 2 ? kFillTint : 0.0);
    const char* kind = g.dimension == 2 ? "surface" : g.dimension == 1 ? "curve" : "point";
    if (g.dimension == 2 && !g.quads.empty())
      item.quads = to_int32(g.quads);
    else  // a curve or point group, or a surface group given by its nodes alone
      item.nodes = to_int32(g.nodes);
    item.label = "group '" + g.name + "'";
    item.legend = item.label + " (" + kind + ", " + count_of(g.nodes.size(), "node", "nodes") + ")";
    item.anchor = representative_node(m, g.nodes);
    pic.items.push_back(std::move(item));
  }
  for (const scene::EntrySelection& e : s.entries) {
    render::PictureItem item;
    item.color = render::picture_color(strong++, e.quads.empty() ? 0.0 : kFillTint);
    // a pressure or surface load acts on quads: they are filled; everything else marks its nodes
    if (!e.quads.empty())
      item.quads = to_int32(e.quads);
    else
      item.nodes = to_int32(e.nodes);
    item.legend = e.label + " (" + e.extent + ")";
    // many labels crowd the picture: there, only the entry's table and index (the legend has the rest)
    item.label = s.entries.size() + m.groups.size() > kFullLabels ? e.table + "[" + std::to_string(e.index) + "]"
                                                                  : item.legend;
    item.anchor = representative_node(m, e.nodes);
    pic.items.push_back(std::move(item));
  }
  return pic;
}

void check_picture_path(const std::string& png_path) {
  // exactly the file asked for, in a folder that exists (none is made)
  const fs::path target(png_path);
  if (png_path.empty()) throw InputError("--picture needs a file name, e.g. --picture scene.png");
  if (target.extension() != ".png")
    throw InputError("--picture " + png_path + ": the picture is a PNG image; give a file name ending in .png");
  const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(folder, ec))
    throw InputError("--picture " + png_path + ": the folder '" + folder.string() + "' does not exist" +
                     (fs::exists(folder, ec) ? " as a folder" : "") + "; create it first, or name another file");
  if (fs::is_directory(target, ec)) throw InputError("--picture " + png_path + ": is a folder; name a .png file in it");
}

std::string write_check_picture(const std::string& scene_path, const std::vector<std::string>& overrides,
                                const std::string& png_path, const scene::SceneContext& ctx) {
  check_picture_path(png_path);

  const std::optional<scene::SceneSelections> selections = scene::scene_selections(scene_path, overrides, ctx);
  if (!selections)
    throw InputError("--picture draws a shell structure and what its scene selects; " + scene_path +
                     " has no shell structure (model = \"hub_beam\")");
  const render::MeshPicture pic = selections_picture(*selections);

  std::string why;
  const std::unique_ptr<render::GraphicsContext> gc = render::GraphicsContext::create(&why);
  if (!gc) throw std::runtime_error("--picture: no graphics to draw with: " + why);
  if (!render::write_mesh_picture(*gc, pic, png_path, &why)) throw std::runtime_error("--picture: " + why);
  return "picture: " + png_path + " (" + std::to_string(pic.width) + "x" + std::to_string(pic.height) + "): " +
         count_of(selections->part_names.size(), "part", "parts") + ", " +
         count_of(selections->mesh.groups.size(), "named group", "named groups") + ", " +
         count_of(selections->entries.size(), "selection", "selections");
}

}  // namespace ff::app
