#include "core/scene/node_selection.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/frame/text.h"
#include "core/mesh/node_sets.h"

namespace ff::scene {

namespace {
const std::vector<std::string> kSelect = {"nearest", "plane", "box", "sphere", "patch_edge", "group", "nodes", "all"};

Eigen::Vector3d vec(const std::vector<double>& v) { return Eigen::Vector3d(v[0], v[1], v[2]); }

mesh::NodeSelector base_selector(const Document& d, const mesh::ShellMesh& m, const std::string& t, std::size_t i) {
  const std::string kind = d.string(t + ".select", i);
  const double tol = d.number(t + ".tolerance", i) > 0 ? d.number(t + ".tolerance", i) : mesh::kAutoTolerance;
  if (kind == "nearest") return mesh::NodeSelector::nearest(vec(d.numbers(t + ".point", i)));
  if (kind == "plane") {
    const Eigen::Vector3d n = vec(d.numbers(t + ".normal", i));
    if (!(n.allFinite() && n.norm() > 0 && std::isfinite(n.squaredNorm())))
      throw SceneError({d.issue(t + ".normal", i, "the plane normal must be a finite non-zero vector")});
    return mesh::NodeSelector::plane(vec(d.numbers(t + ".point", i)), n, tol);
  }
  if (kind == "box") return mesh::NodeSelector::box(vec(d.numbers(t + ".box_min", i)), vec(d.numbers(t + ".box_max", i)), tol);
  if (kind == "sphere") return mesh::NodeSelector::sphere(vec(d.numbers(t + ".point", i)), d.number(t + ".radius", i), tol);
  if (kind == "patch_edge") {
    std::string patch = d.string(t + ".patch", i);
    if (patch.empty()) {  // the only patch, when there is one
      if (m.patches.size() != 1) {
        std::string names;
        for (const mesh::Patch& p : m.patches) names += (names.empty() ? "" : ", ") + p.name;
        throw SceneError({d.issue(t + ".select", i, "select = \"patch_edge\" needs " + t + ".patch: this structure "
                                                    "has the patches " + names)});
      }
      patch = m.patches[0].name;
    }
    try {
      return mesh::NodeSelector::patch_edge(patch, mesh::resolve_patch_edge(m, patch, d.string(t + ".edge", i)));
    } catch (const std::invalid_argument& e) {
      const bool patch_exists = m.find_patch(patch) >= 0;
      throw SceneError({d.issue(patch_exists ? t + ".edge" : t + ".patch", i, e.what())});
    }
  }
  if (kind == "group") {
    const std::string& name = d.string(t + ".group", i);
    const int g = m.find_group(name);
    if (g < 0) {
      std::string names;
      for (const mesh::MeshGroup& group : m.groups) names += (names.empty() ? "" : ", ") + group.name;
      throw SceneError({d.issue(t + ".group", i,
                                name.empty() ? "select = \"group\" needs " + t + ".group, the name of a group of the mesh file" +
                                                   (names.empty() ? std::string(" (this structure has none)") : " (" + names + ")")
                                             : "the structure has no group called '" + name + "' (" +
                                                   (names.empty() ? std::string("its meshes define no named groups: they come "
                                                                                "from Gmsh physical groups or Abaqus sets")
                                                                  : "its groups: " + names) + ")")});
    }
    return mesh::NodeSelector::ids(m.groups[static_cast<std::size_t>(g)].nodes);
  }
  if (kind == "nodes") {
    // node numbers of the joined structure, as the window's picking writes them
    const std::vector<double> given = d.numbers(t + ".nodes", i);
    if (given.empty()) throw SceneError({d.issue(t + ".nodes", i, "select = \"nodes\" needs " + t + ".nodes, a list of node numbers")});
    std::vector<int> ids;
    for (double v : given) {
      if (v != std::floor(v) || v < 0 || v >= m.node_count())
        throw SceneError({d.issue(t + ".nodes", i, "node " + significant(v) + " is not a node number of this structure (0 to " +
                                                       std::to_string(m.node_count() - 1) + ")")});
      ids.push_back(static_cast<int>(v));
    }
    return mesh::NodeSelector::ids(std::move(ids));
  }
  return mesh::NodeSelector::all();
}

mesh::NodeSelector selector(const Document& d, const mesh::ShellMesh& m, const std::string& t, std::size_t i) {
  mesh::NodeSelector base = base_selector(d, m, t, i);
  const Eigen::Vector3d side = vec(d.numbers(t + ".side", i));
  if (side.isZero(0.0)) return base;
  if (!(side.allFinite() && std::isfinite(side.squaredNorm())))
    throw SceneError({d.issue(t + ".side", i, "the side direction must be a finite vector")});
  return mesh::NodeSelector::facing(std::move(base), side);
}
std::string point_text(const Eigen::Vector3d& x) {
  std::ostringstream s;
  s.precision(6);
  s << "[" << x.x() << ", " << x.y() << ", " << x.z() << "]";
  return s.str();
}

// `nearest` takes one node; when another (of the side, if one is given) is as near, which one is
// read or held would be decided by node numbering, e.g. the clamped lip of a slit instead of the
// free one: refused, naming both
void refuse_ambiguous_nearest(const Document& d, const mesh::ShellMesh& m, const std::string& t, std::size_t i, int chosen) {
  const Eigen::Vector3d point = vec(d.numbers(t + ".point", i));
  const Eigen::Vector3d side = vec(d.numbers(t + ".side", i));
  const std::vector<int> candidates = side.isZero(0.0) ? std::vector<int>{} : mesh::nodes_facing(m, side);
  Eigen::Vector3d lo = m.points.front(), hi = lo;
  for (const Eigen::Vector3d& x : m.points) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  // equally near within round-off of the mesh's size
  const double tie = 1e-9 * std::max((hi - lo).norm(), (point - lo).norm());
  const double nearest = (m.points[chosen] - point).norm();
  auto check = [&](int k) {
    if (k == chosen || !((m.points[k] - point).norm() - nearest <= tie)) return;
    // two nodes at one place are a seam the mesh keeps open: a slit's lips, or faces of a mesh
    // file that were not joined there
    if ((m.points[k] - m.points[chosen]).norm() <= tie)
      throw SceneError({d.issue(t + ".point", i,
                                "the point " + point_text(point) + " is equally near node " + std::to_string(chosen) +
                                    " and node " + std::to_string(k) + ", which lie at the same place " +
                                    point_text(m.points[chosen]) + ": the mesh holds two unconnected nodes there (the "
                                    "lips of a slit, or faces of a mesh file that are not joined along that line; "
                                    "part.weld_tolerance welds a file's), so select = \"nearest\" cannot tell which "
                                    "one is meant; " +
                                    (side.isZero(0.0) ? "pick a side with " + t + ".side"
                                                      : t + ".side does not tell them apart either") +
                                    ", or join the faces")});
    throw SceneError({d.issue(t + ".point", i,
                              "the point " + point_text(point) + " is equally near node " + std::to_string(chosen) +
                                  " at " + point_text(m.points[chosen]) + " and node " + std::to_string(k) + " at " +
                                  point_text(m.points[k]) + " (distance " + significant(nearest) +
                                  "), so select = \"nearest\" is ambiguous; move the point towards the node you "
                                  "mean" + (side.isZero(0.0) ? std::string(", or pick one lip of a slit with " + t + ".side") : std::string()))});
  };
  if (side.isZero(0.0))
    for (int k = 0; k < m.node_count(); ++k) check(k);
  else
    for (int k : candidates) check(k);
}
}  // namespace

void declare_selector_keys(Schema& s, const std::string& t) {
  s.choice(t + ".select", "how nodes are chosen", kSelect, "nearest")
      .number_list(t + ".point", "nearest/plane/sphere: a point", std::vector<double>{0, 0, 0}, {}, 3, 3)
      .number_list(t + ".normal", "plane: its normal", std::vector<double>{1, 0, 0}, {}, 3, 3)
      .number_list(t + ".box_min", "box: lower corner", std::vector<double>{0, 0, 0}, {}, 3, 3)
      .number_list(t + ".box_max", "box: upper corner", std::vector<double>{0, 0, 0}, {}, 3, 3)
      .number(t + ".radius", "sphere: radius", 0.0, Range::non_negative())
      .string(t + ".patch",
              "patch_edge: the patch (a part's name, or the patch names of l_plate and folded_plate); \"\" = the "
              "structure's only patch",
              std::string{})
      .string(t + ".edge",
              "patch_edge: which edge, u=0, u=1, v=0, v=1 or the generator's name for it (see [[part]]: e.g. "
              "\"start_angle\", \"rim\", \"inner\", \"x_min\")",
              std::string("u=0"))
      .string(t + ".group",
              "group: the name of a named group of a mesh file (a Gmsh physical group, an Abaqus *NSET or *ELSET)",
              std::string{})
      .number(t + ".tolerance", "plane/box/sphere tolerance; 0 = automatic (1e-3 x shortest edge)", 0.0,
              Range::non_negative())
      .number_list(t + ".side",
                   "keep only the selected nodes whose quads all lie toward this direction from the node: "
                   "picks one lip of a slit (two coincident edges) apart from the other; with nearest, the "
                   "nearest such node; [0, 0, 0] = every selected node",
                   std::vector<double>{0, 0, 0}, {}, 3, 3)
      .number_list(t + ".nodes",
                   "nodes: the node numbers of the joined structure (what the window's picking writes; `flexframe "
                   "check --picture` shows the structure)",
                   std::vector<double>{}, Range::non_negative());
  s.unit_of(t + ".point", "length")
      .unit_of(t + ".box_min", "length")
      .unit_of(t + ".box_max", "length")
      .unit_of(t + ".radius", "length")
      .unit_of(t + ".tolerance", "length");
  // each selector key serves the kinds of selection that read it
  s.applies_when(t + ".point", t + ".select", {"nearest", "plane", "sphere"})
      // a symmetry support on a named group takes the plane's normal from bc.normal
      .applies_when(t + ".normal", t + ".select", t == "bc" ? std::vector<std::string>{"plane", "group"} : std::vector<std::string>{"plane"})
      .applies_when(t + ".box_min", t + ".select", {"box"})
      .applies_when(t + ".box_max", t + ".select", {"box"})
      .applies_when(t + ".radius", t + ".select", {"sphere"})
      .applies_when(t + ".patch", t + ".select", {"patch_edge"})
      .applies_when(t + ".edge", t + ".select", {"patch_edge"})
      .applies_when(t + ".group", t + ".select", {"group"})
      .applies_when(t + ".tolerance", t + ".select", {"plane", "box", "sphere"})
      .applies_when(t + ".nodes", t + ".select", {"nodes"});
}

std::vector<int> select_nodes(const Document& d, const mesh::ShellMesh& m, const std::string& t, std::size_t i) {
  const mesh::NodeSelector sel = selector(d, m, t, i);
  std::vector<int> ids;
  try {
    ids = sel.select(m);
  } catch (const std::invalid_argument& e) {
    // a request the mesh cannot answer (no such patch, or a patch with no parametric grid)
    const bool by_patch = d.string(t + ".select", i) == "patch_edge";
    throw SceneError({d.issue(by_patch ? t + ".patch" : t + ".select", i, e.what())});
  }
  if (ids.empty())
    throw SceneError({d.issue(t + ".select", i, mesh::empty_selection_message(t + "[" + std::to_string(i) + "]", sel, m))});
  if (d.string(t + ".select", i) == "nearest") refuse_ambiguous_nearest(d, m, t, i, ids.front());
  return ids;
}

std::vector<int> selected_quads(const Document& d, const mesh::ShellMesh& m, const std::string& t, std::size_t i,
                                const std::vector<int>& ids) {
  if (d.string(t + ".select", i) == "group") {
    const int g = m.find_group(d.string(t + ".group", i));
    // a surface group names its elements: exactly those (a quad outside it whose corners all
    // lie in it, e.g. across a narrow strip, is not part of it)
    if (g >= 0 && !m.groups[static_cast<std::size_t>(g)].quads.empty()) return m.groups[static_cast<std::size_t>(g)].quads;
  }
  return quads_within(m, ids);
}

std::vector<int> quads_within(const mesh::ShellMesh& m, const std::vector<int>& ids) {
  std::vector<char> in(m.node_count(), 0);
  for (int i : ids) in[i] = 1;
  std::vector<int> q;
  for (int k = 0; k < m.quad_count(); ++k)
    if (std::all_of(m.quads[k].begin(), m.quads[k].end(), [&](int i) { return in[i] != 0; })) q.push_back(k);
  return q;
}

std::vector<double> tributary_weights(const mesh::ShellMesh& m, const std::vector<int>& ids) {
  if (ids.size() == 1) return {1.0};
  Eigen::Vector3d lo = m.points[ids[0]], hi = lo;
  for (int i : ids) lo = lo.cwiseMin(m.points[i]), hi = hi.cwiseMax(m.points[i]);
  const Eigen::Vector3d dir = (hi - lo).normalized();
  std::vector<std::pair<double, int>> s;
  for (std::size_t k = 0; k < ids.size(); ++k) s.emplace_back(dir.dot(m.points[ids[k]] - lo), static_cast<int>(k));
  std::sort(s.begin(), s.end());
  std::vector<double> w(ids.size(), 0.0);
  double total = 0.0;
  for (std::size_t k = 0; k + 1 < s.size(); ++k) {
    const double h = s[k + 1].first - s[k].first;
    w[s[k].second] += 0.5 * h;
    w[s[k + 1].second] += 0.5 * h;
    total += h;
  }
  for (double& x : w) x = total > 0 ? x / total : 1.0 / ids.size();
  return w;
}

}  // namespace ff::scene
