#include "core/scene/structure_parts.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "core/scene/mesh_file.h"
#include "core/scene/mesh_generator_keys.h"
#include "core/shell/shell_model.h"

namespace ff::scene {

namespace fs = std::filesystem;

void declare_structure_keys(Schema& s) {
  s.table_array("material",
                "what the parts are made of: St. Venant-Kirchhoff, plane stress, and the shell's section (one form "
                "for every part and every analysis)",
                1, 64)
      .string("material.name", "its name, for part.material; \"\" is allowed when the scene has one material",
              std::string{})
      .number("material.youngs_modulus", "E", std::nullopt, Range::positive())
      .number("material.poisson_ratio", "nu", 0.3, Range::right_open(0.0, 0.5))
      .number("material.thickness", "h0, the shell's thickness", std::nullopt, Range::positive())
      .number("material.shear_factor", "transverse shear correction factor", 5.0 / 6.0, Range::left_open(0.0, 1.0))
      .number("material.drilling_factor", "effect drilling: c in the drilling penalty gamma = c G h0", 1e-3,
              Range::left_open(0.0, 1e3))
      .number("material.density",
              "mass per unit volume rho; a dynamic analysis needs it, and a static one with the effect gravity "
              "(0 = not given)",
              0.0, Range::non_negative());
  declare_part_keys(s);
  s.table_array("junction",
                "parts that share their nodes where their edges coincide (a T, a stiffener, two panels meeting at a "
                "line): coincident nodes of the listed parts become one node, with 6 DoF where the parts' directors "
                "differ (a fold)",
                0, 64)
      .string_list("junction.parts", "the names of the parts joined (two or more)", std::nullopt)
      .number("junction.tolerance",
              "nodes of different parts closer than this are one node; 0 = automatic (1e-6 x the shortest element "
              "edge of the joined parts)",
              0.0, Range::non_negative(), "length");
}

int Structure::find(const std::string& name) const {
  for (std::size_t p = 0; p < parts.size(); ++p)
    if (parts[p].name == name) return static_cast<int>(p);
  return -1;
}

int Structure::first_quad(int p) const {
  int q = 0;
  for (int k = 0; k < p; ++k) q += parts[k].mesh.quad_count();
  return q;
}

namespace {

std::string g(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

// the name a part goes by: part.name, else the generator's default patch name (one-part scenes
// written before parts had names keep selecting patch "plate", "cylinder", ...)
std::string part_name(const Document& d, std::size_t i, const mesh::ShellMesh* m) {
  const std::string& n = d.string("part.name", i);
  if (!n.empty()) return n;
  if (m && m->patches.size() == 1) return m->patches[0].name;
  return d.string("part.generator", i) + std::to_string(i + 1);
}

// what part i asks of its file
MeshFileRequest file_request(const Document& d, std::size_t i, const std::string& scene_path) {
  MeshFileRequest r;
  r.path = (fs::path(scene_path).parent_path() / d.string("part.file", i)).string();
  r.weld_tolerance = d.number("part.weld_tolerance", i);
  r.triangles = d.string("part.triangles", i);
  r.crease_angle_deg = d.number("part.crease_angle", i);
  r.group = d.string("part.group", i);
  r.mesh_size = d.number("part.mesh_size", i);
  r.local_size_groups = d.strings("part.local_size_groups", i);
  r.local_sizes = d.numbers("part.local_sizes", i);
  r.time_limit_seconds = d.number("part.mesh_time_limit", i);
  if (r.local_size_groups.size() != r.local_sizes.size())
    throw SceneError({d.issue("part.local_sizes", i,
                              "part.local_sizes has " + std::to_string(r.local_sizes.size()) + " sizes for " +
                                  std::to_string(r.local_size_groups.size()) +
                                  " groups in part.local_size_groups: give one size per group, in the same order")});
  return r;
}

mesh::ShellMesh read_part_file(const Document& d, std::size_t i, const std::string& scene_path, const SceneContext& ctx) {
  const std::string& file = d.string("part.file", i);
  if (file.empty())
    throw SceneError({d.issue("part.generator", i, "generator = \"file\" needs part.file (a mesh or CAD file, "
                                                   "relative to the scene file)")});
  if (!ctx.mesh_reader)
    throw SceneError({d.issue("part.file", i, "this program reads no mesh files (no reader was passed to the scene "
                                              "loader; the flexframe executable passes its assimp importer)")});
  mesh::ShellMesh m;
  MeshFileError error;
  const MeshFileRequest request = file_request(d, i, scene_path);
  if (!ctx.mesh_reader(request, m, &error))
    throw SceneError({d.issue(error.key.empty() ? "part.file" : error.key, i, error.message)});
  return m;
}

// directors to the other side: every director and corner director negated, every quad's corner
// order reversed (so it still runs counter-clockwise about its director), frames rebuilt
void flip_directors(mesh::ShellMesh& m) {
  for (Eigen::Vector3d& n : m.normals) n = -n;
  for (auto& c : m.corner_normals) {
    for (Eigen::Vector3d& n : c) n = -n;
    std::swap(c[1], c[3]);
  }
  for (auto& q : m.quads) std::swap(q[1], q[3]);
  mesh::compute_frames(m, m.frame_reference);
}

// union-find over joined node ids
int root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

}  // namespace

StructureSize structure_size(const Document& d, const std::string& scene_path, const SceneContext& ctx) {
  StructureSize size;
  long long largest = -1;
  for (std::size_t i = 0; i < d.count("part"); ++i) {
    long long nodes = 0;
    std::string key = "part.file";
    if (!mesh_from_file(d, i)) {
      const GeneratedMeshSize g = generated_mesh_size(d, i);
      nodes = g.nodes, key = g.key;
    } else if (ctx.mesh_reader && !d.string("part.file", i).empty()) {
      mesh::ShellMesh m;
      MeshFileError error;
      if (ctx.mesh_reader(file_request(d, i, scene_path), m, &error))
        nodes = m.node_count();
    }
    size.nodes += nodes;
    if (nodes > largest) largest = nodes, size.key = key, size.part = static_cast<int>(i);
  }
  return size;
}

double estimated_structure_bytes(const Document& d, const std::string& scene_path, const SceneContext& ctx) {
  const std::vector<std::string> fx = d.strings("scene.effects");
  const bool drilling = std::find(fx.begin(), fx.end(), "drilling") != fx.end();
  const long long nodes = structure_size(d, scene_path, ctx).nodes;
  return nodes > 0 ? shell::estimated_peak_bytes(static_cast<int>(std::min<long long>(nodes, std::numeric_limits<int>::max())),
                                                 drilling ? 1.0 : 0.0)
                   : 0.0;
}

Structure read_structure(const Document& d, const std::string& scene_path, const SceneContext& ctx) {
  Structure s;
  // materials: names unique; a nameless one only when it is the only one
  const std::size_t nm = d.count("material");
  for (std::size_t k = 0; k < nm; ++k) {
    StructureMaterial m;
    m.name = d.string("material.name", k);
    if (m.name.empty() && nm > 1)
      throw SceneError({d.issue("material.name", k, "the scene has " + std::to_string(nm) +
                                                        " materials: each needs a name for part.material to use")});
    for (const StructureMaterial& other : s.materials)
      if (other.name == m.name) throw SceneError({d.issue("material.name", k, "another material is called '" + m.name + "'")});
    m.section = {d.number("material.youngs_modulus", k), d.number("material.poisson_ratio", k),
                 d.number("material.thickness", k), d.number("material.shear_factor", k)};
    m.drilling_factor = d.number("material.drilling_factor", k);
    m.density = d.number("material.density", k);
    // a density this small makes a mass matrix whose products underflow to zero (5e-324 gave a
    // zero pivot in the initial accelerations): not a material, a typo or a unit slip
    if (m.density > 0 && m.density < 1e-100)
      throw SceneError({d.issue("material.density", k,
                                "a density of " + g(m.density) + " is too small to make a mass matrix (its products with "
                                "the element's lengths underflow to zero); give it in the scene's units, e.g. 7850 for "
                                "steel in kg/m^3, or leave it out of a static analysis")});
    s.materials.push_back(m);
  }
  std::vector<char> material_used(nm, 0);
  const std::size_t np = d.count("part");
  for (std::size_t i = 0; i < np; ++i) {
    StructurePart p;
    const std::string& material = d.string("part.material", i);
    p.material = -1;
    if (material.empty()) {
      if (nm > 1)
        throw SceneError({d.issue("part.material", i, "the scene has " + std::to_string(nm) +
                                                          " materials: say which one this part is made of")});
      p.material = 0;
    } else {
      for (std::size_t k = 0; k < nm; ++k)
        if (s.materials[k].name == material) p.material = static_cast<int>(k);
      if (p.material < 0) throw SceneError({d.issue("part.material", i, "no [[material]] is called '" + material + "'")});
    }
    material_used[p.material] = 1;
    p.from_file = mesh_from_file(d, i);
    if (p.from_file) {
      try {
        p.mesh = read_part_file(d, i, scene_path, ctx);
      } catch (const std::invalid_argument& e) {
        throw SceneError({d.issue("part.generator", i, e.what())});
      }
    } else {
      p.mesh = generate_mesh(d, i);
      check_thickness_against_radius(d, i, "material.thickness", static_cast<std::size_t>(p.material));
    }
    if (d.boolean("part.flip_director", i)) flip_directors(p.mesh);
    p.name = part_name(d, i, &p.mesh);
    if (s.find(p.name) >= 0)
      throw SceneError({d.issue(d.present("part.name", i) ? "part.name" : "part.generator", i,
                                "another part is called '" + p.name + "'" +
                                    (d.present("part.name", i) ? "" : " (the generator's default name): give part.name"))});
    // a patch name selects nodes across the whole structure: one patch of one part per name
    for (const mesh::Patch& patch : p.mesh.patches)
      for (const StructurePart& other : s.parts)
        if (other.mesh.find_patch(patch.name) >= 0)
          throw SceneError({d.issue(d.present("part.name", i) ? "part.name" : "part.generator", i,
                                    "this part's patch '" + patch.name + "' has the name of a patch of part '" +
                                        other.name + "', so select = \"patch_edge\" could not tell them apart; " +
                                        (p.mesh.patches.size() > 1
                                             ? std::string("l_plate and folded_plate name their patches themselves "
                                                           "(arm1, corner, arm2; leg1, leg2), so a structure holds one "
                                                           "of each")
                                             : std::string("give the part a name of its own")))});
    s.parts.push_back(std::move(p));
  }
  for (std::size_t k = 0; k < nm; ++k)
    if (!material_used[k])
      throw SceneError({d.issue(d.present("material.name", k) ? "material.name" : "material.youngs_modulus", k,
                                "no part is made of material '" + s.materials[k].name + "'")});

  // every node of every part, in part order; a junction unites coincident nodes of its parts
  std::vector<int> offset;
  int total = 0;
  for (StructurePart& p : s.parts) offset.push_back(total), p.first_node = total, total += p.mesh.node_count();
  std::vector<int> parent(total);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<int> first_junction(np, -1);
  for (std::size_t j = 0; j < d.count("junction"); ++j) {
    const std::vector<std::string> names = d.strings("junction.parts", j);
    if (names.size() < 2)
      throw SceneError({d.issue("junction.parts", j, "a junction joins two or more parts; it names " +
                                                         std::to_string(names.size()))});
    std::vector<int> members;
    for (const std::string& n : names) {
      const int p = s.find(n);
      if (p < 0) throw SceneError({d.issue("junction.parts", j, "no part is called '" + n + "'")});
      if (std::find(members.begin(), members.end(), p) != members.end())
        throw SceneError({d.issue("junction.parts", j, "part '" + n + "' is named twice")});
      members.push_back(p);
    }
    double h = std::numeric_limits<double>::infinity();
    for (int p : members) h = std::min(h, mesh::min_edge_length(s.parts[p].mesh));
    const double tol = d.number("junction.tolerance", j) > 0 ? d.number("junction.tolerance", j) : 1e-6 * h;
    // every pair of listed parts: coincident nodes united (a hash grid of cell tol)
    struct Key {
      long long x, y, z;
      bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct Hash {
      std::size_t operator()(const Key& k) const {
        return std::hash<long long>()(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
      }
    };
    auto cell = [&](const Eigen::Vector3d& x) {
      return Key{static_cast<long long>(std::floor(x.x() / tol)), static_cast<long long>(std::floor(x.y() / tol)),
                 static_cast<long long>(std::floor(x.z() / tol))};
    };
    std::unordered_map<Key, std::vector<int>, Hash> grid;  // joined ids of the parts before the current one
    int shared = 0;
    for (int p : members) {
      const mesh::ShellMesh& m = s.parts[p].mesh;
      for (int i = 0; i < m.node_count(); ++i) {
        const Key c = cell(m.points[i]);
        for (long long dx = -1; dx <= 1; ++dx)
          for (long long dy = -1; dy <= 1; ++dy)
            for (long long dz = -1; dz <= 1; ++dz) {
              const auto it = grid.find({c.x + dx, c.y + dy, c.z + dz});
              if (it == grid.end()) continue;
              for (int other : it->second) {
                int q = 0;
                while (q + 1 < static_cast<int>(np) && offset[q + 1] <= other) ++q;
                const double dist = (s.parts[q].mesh.points[other - offset[q]] - m.points[i]).norm();
                if (dist <= tol) {
                  const int a = root(parent, other), b = root(parent, offset[p] + i);
                  if (a != b) parent[std::max(a, b)] = std::min(a, b), ++shared;
                }
              }
            }
      }
      for (int i = 0; i < m.node_count(); ++i) grid[cell(m.points[i])].push_back(offset[p] + i);
    }
    if (shared == 0)
      throw SceneError({d.issue("junction.parts", j, "the parts named share no node (none closer than " + g(tol) +
                                                         "): a junction joins parts whose edges coincide; give "
                                                         "junction.tolerance, or connect them with a [[joint]]")});
    for (int p : members)
      if (first_junction[p] < 0) first_junction[p] = static_cast<int>(j);
    s.has_junctions = true;
  }

  if (!s.has_junctions && np == 1) {
    s.joined = s.parts[0].mesh;
    s.parts[0].node_map.resize(s.joined.node_count());
    std::iota(s.parts[0].node_map.begin(), s.parts[0].node_map.end(), 0);
    s.quad_part.assign(s.joined.quad_count(), 0);
    return s;
  }
  // joined ids in order of first appearance; the first part's node keeps its director and frame,
  // a later one whose director differs makes it a fold node (each quad keeps its own director)
  mesh::ShellMesh& out = s.joined;
  std::vector<int> new_id(total, -1);
  for (std::size_t p = 0; p < np; ++p) {
    StructurePart& part = s.parts[p];
    const mesh::ShellMesh& m = part.mesh;
    part.node_map.resize(m.node_count());
    for (int i = 0; i < m.node_count(); ++i) {
      const int r = root(parent, offset[p] + i);
      if (new_id[r] < 0) {
        new_id[r] = out.node_count();
        out.points.push_back(m.points[i]);
        out.normals.push_back(m.normals[i]);
        out.frames.push_back(m.frames[i]);
        out.fold.push_back(i < static_cast<int>(m.fold.size()) ? m.fold[i] : 0);
      } else {
        const int n = new_id[r];
        const double cosine = std::clamp(out.normals[n].dot(m.normals[i]), -1.0, 1.0);
        if (std::acos(cosine) > 1e-6) out.fold[n] = 1;
      }
      part.node_map[i] = new_id[r];
    }
  }
  for (std::size_t p = 0; p < np; ++p) {
    const mesh::ShellMesh& m = s.parts[p].mesh;
    const int patch_offset = static_cast<int>(out.patches.size()), quad_offset = out.quad_count();
    for (int q = 0; q < m.quad_count(); ++q) {
      std::array<int, 4> c{};
      std::array<Eigen::Vector3d, 4> n;
      for (int k = 0; k < 4; ++k) {
        c[k] = s.parts[p].node_map[m.quads[q][k]];
        n[k] = q < static_cast<int>(m.corner_normals.size()) ? m.corner_normals[q][k] : m.normals[m.quads[q][k]];
      }
      out.quads.push_back(c);
      out.corner_normals.push_back(n);
      out.quad_patch.push_back(patch_offset + (q < static_cast<int>(m.quad_patch.size()) ? m.quad_patch[q] : 0));
      s.quad_part.push_back(static_cast<int>(p));
    }
    for (mesh::Patch patch : m.patches) {
      for (int& id : patch.grid) id = s.parts[p].node_map[id];
      patch.first_quad += quad_offset;
      out.patches.push_back(std::move(patch));
    }
    // a file's named group selects its nodes in every part that has it (parts cut from one file
    // by part.group share the file's curve and point groups)
    for (const mesh::MeshGroup& g : m.groups) {
      int k = out.find_group(g.name);
      if (k < 0) {
        k = static_cast<int>(out.groups.size());
        out.groups.push_back({g.name, g.dimension, {}, {}, g.origin});
      }
      mesh::MeshGroup& joined_group = out.groups[static_cast<std::size_t>(k)];
      for (int id : g.nodes) joined_group.nodes.push_back(s.parts[p].node_map[id]);
      for (int q : g.quads) joined_group.quads.push_back(quad_offset + q);
      std::sort(joined_group.nodes.begin(), joined_group.nodes.end());
      joined_group.nodes.erase(std::unique(joined_group.nodes.begin(), joined_group.nodes.end()), joined_group.nodes.end());
    }
  }
  out.frame_reference = s.parts[0].mesh.frame_reference;
  // the joined parts must turn their directors to one side: a shared edge then runs opposite ways
  // in the two quads that meet on it (core/mesh/README.md convention 1)
  const mesh::MeshCheck check = mesh::validate(out);
  for (const mesh::MeshIssue& issue : check.issues) {
    if (issue.kind != mesh::IssueKind::inconsistent_orientation) continue;
    const int p = issue.quad >= 0 ? s.quad_part[issue.quad] : 0;
    const int j = first_junction[p] >= 0 ? first_junction[p] : 0;
    throw SceneError({d.issue("junction.parts", static_cast<std::size_t>(j),
                              "the joined parts' directors point to opposite sides where they meet (" + issue.message +
                                  "); set part.flip_director = true on one of them")});
  }
  return s;
}

std::vector<std::pair<std::string, std::string>> mesh_import_settings(const Structure& s) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const StructurePart& part : s.parts)
    if (part.from_file && !part.mesh.patches.empty())
      out.emplace_back(s.parts.size() == 1 ? "mesh_import" : "mesh_import_" + part.name, part.mesh.patches[0].description);
  return out;
}

void structure_sections(const Structure& s, std::vector<shell::ShellSection>& sections,
                        std::vector<double>& drilling_factors, std::vector<int>& quad_section) {
  sections.clear(), drilling_factors.clear(), quad_section.clear();
  if (s.materials.size() == 1) return;
  for (const StructureMaterial& m : s.materials) sections.push_back(m.section), drilling_factors.push_back(m.drilling_factor);
  for (int p : s.quad_part) quad_section.push_back(s.parts[p].material);
}

}  // namespace ff::scene
