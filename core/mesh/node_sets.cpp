#include "core/mesh/node_sets.h"

#include <algorithm>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace ff::mesh {

namespace {

using Vec3 = Eigen::Vector3d;

std::string num(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

std::string vec(const Vec3& v) {
  std::ostringstream s;
  s.precision(6);
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

// "(" + text + ")" without tripping GCC 12's -Wrestrict false positive on operator+
std::string parens(const std::string& text) {
  std::string s;
  s.reserve(text.size() + 2);
  s.push_back('(');
  s.append(text);
  s.push_back(')');
  return s;
}

std::string tol_words(double tol) { return tol < 0 ? std::string("auto") : num(tol); }

template <class Pred>
NodeSet select_if(const ShellMesh& mesh, Pred pred) {
  NodeSet out;
  for (int i = 0; i < mesh.node_count(); ++i)
    if (pred(mesh.points[i])) out.push_back(i);
  return out;
}

const Patch& find_patch_or_throw(const ShellMesh& mesh, const std::string& name) {
  const int k = mesh.find_patch(name);
  if (k < 0) {
    std::string names;
    for (const auto& p : mesh.patches) names += (names.empty() ? "'" : ", '") + p.name + "'";
    throw std::invalid_argument("the mesh has no patch named '" + name + "' (patches: " +
                                (names.empty() ? std::string("none") : names) + ")");
  }
  return mesh.patches[k];
}

NodeSet sorted_unique(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

}  // namespace

double resolve_tolerance(const ShellMesh& mesh, double tol) {
  return tol >= 0 ? tol : 1e-3 * min_edge_length(mesh);
}

const char* to_string(PatchEdge edge) {
  switch (edge) {
    case PatchEdge::u_min: return "u=0";
    case PatchEdge::u_max: return "u=1";
    case PatchEdge::v_min: return "v=0";
    case PatchEdge::v_max: return "v=1";
  }
  return "?";
}

std::optional<PatchEdge> parse_patch_edge(std::string_view t) {
  if (t == "u=0" || t == "u0") return PatchEdge::u_min;
  if (t == "u=1" || t == "u1") return PatchEdge::u_max;
  if (t == "v=0" || t == "v0") return PatchEdge::v_min;
  if (t == "v=1" || t == "v1") return PatchEdge::v_max;
  return std::nullopt;
}

PatchEdge resolve_patch_edge(const ShellMesh& mesh, const std::string& patch, std::string_view text) {
  if (const auto e = parse_patch_edge(text)) return *e;
  const Patch& p = find_patch_or_throw(mesh, patch);
  static constexpr PatchEdge kOrder[4] = {PatchEdge::u_min, PatchEdge::u_max, PatchEdge::v_min, PatchEdge::v_max};
  std::string names;
  for (int k = 0; k < 4; ++k) {
    if (!p.edge_names[k].empty() && p.edge_names[k] == text) return kOrder[k];
    if (!p.edge_names[k].empty()) names += ", \"" + p.edge_names[k] + "\" (" + to_string(kOrder[k]) + ")";
  }
  throw std::invalid_argument("patch '" + patch + "' has no edge named \"" + std::string(text) +
                              "\" (its edges: \"u=0\", \"u=1\", \"v=0\", \"v=1\"" + names + ")");
}

NodeSet nodes_on_plane(const ShellMesh& mesh, const Vec3& point, const Vec3& normal, double tol) {
  const double len = normal.norm();
  if (!(len > 0)) throw std::invalid_argument("plane node set: the plane normal is the zero vector");
  const Vec3 n = normal / len;
  const double t = resolve_tolerance(mesh, tol);
  return select_if(mesh, [&](const Vec3& x) { return std::abs((x - point).dot(n)) <= t; });
}

NodeSet nodes_in_box(const ShellMesh& mesh, const Vec3& lo, const Vec3& hi, double tol) {
  const double t = resolve_tolerance(mesh, tol);
  return select_if(mesh, [&](const Vec3& x) {
    return (x.array() >= lo.array() - t).all() && (x.array() <= hi.array() + t).all();
  });
}

NodeSet nodes_in_sphere(const ShellMesh& mesh, const Vec3& center, double radius, double tol) {
  const double t = resolve_tolerance(mesh, tol);
  return select_if(mesh, [&](const Vec3& x) { return (x - center).norm() <= radius + t; });
}

NodeSet nearest_node(const ShellMesh& mesh, const Vec3& point) {
  int best = -1;
  double best_d = std::numeric_limits<double>::infinity();
  for (int i = 0; i < mesh.node_count(); ++i) {
    const double d = (mesh.points[i] - point).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  return best < 0 ? NodeSet{} : NodeSet{best};
}

NodeSet nodes_facing(const ShellMesh& mesh, const Vec3& side) {
  if (!(side.allFinite() && side.norm() > 0))
    throw std::invalid_argument("side node set: the side direction must be a finite non-zero vector");
  // 1 = every quad seen so far lies toward side, 0 = no quad yet, -1 = some quad does not
  std::vector<signed char> state(mesh.node_count(), 0);
  for (const auto& q : mesh.quads) {
    const Vec3 c = 0.25 * (mesh.points[q[0]] + mesh.points[q[1]] + mesh.points[q[2]] + mesh.points[q[3]]);
    for (int k : q) {
      if (state[k] < 0) continue;
      state[k] = (c - mesh.points[k]).dot(side) > 0 ? 1 : -1;
    }
  }
  NodeSet out;
  for (int i = 0; i < mesh.node_count(); ++i)
    if (state[i] > 0) out.push_back(i);
  return out;
}

NodeSet patch_edge_nodes(const ShellMesh& mesh, const std::string& name, PatchEdge edge) {
  const Patch& p = find_patch_or_throw(mesh, name);
  if (!p.structured())
    throw std::invalid_argument("patch '" + name + "' has no parametric grid (an imported mesh?), so edge " +
                                to_string(edge) + " is undefined; select by plane or box instead");
  std::vector<int> ids;
  if (edge == PatchEdge::u_min || edge == PatchEdge::u_max) {
    const int i = edge == PatchEdge::u_min ? 0 : p.nu;
    for (int j = 0; j <= p.nv; ++j) ids.push_back(p.node(i, j));
  } else {
    const int j = edge == PatchEdge::v_min ? 0 : p.nv;
    for (int i = 0; i <= p.nu; ++i) ids.push_back(p.node(i, j));
  }
  return sorted_unique(std::move(ids));
}

NodeSet patch_nodes(const ShellMesh& mesh, const std::string& name) {
  const Patch& p = find_patch_or_throw(mesh, name);
  std::vector<int> ids;
  for (int q = p.first_quad; q < p.first_quad + p.quad_count; ++q)
    for (int k : mesh.quads[q]) ids.push_back(k);
  return sorted_unique(std::move(ids));
}

NodeSet set_union(const NodeSet& a, const NodeSet& b) {
  NodeSet out;
  std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

NodeSet set_intersection(const NodeSet& a, const NodeSet& b) {
  NodeSet out;
  std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

NodeSet set_difference(const NodeSet& a, const NodeSet& b) {
  NodeSet out;
  std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
  return out;
}

// ---- NodeSelector ---------------------------------------------------------------------------

NodeSelector NodeSelector::all() { return NodeSelector{}; }

NodeSelector NodeSelector::ids(std::vector<int> ids) {
  NodeSelector s;
  s.kind_ = Kind::ids;
  s.ids_ = sorted_unique(std::move(ids));
  return s;
}

NodeSelector NodeSelector::plane(const Vec3& point, const Vec3& normal, double tol) {
  if (!(normal.norm() > 0)) throw std::invalid_argument("plane node set: the plane normal is the zero vector");
  NodeSelector s;
  s.kind_ = Kind::plane;
  s.a_ = point;
  s.b_ = normal.normalized();
  s.tol_ = tol;
  return s;
}

NodeSelector NodeSelector::box(const Vec3& lo, const Vec3& hi, double tol) {
  NodeSelector s;
  s.kind_ = Kind::box;
  s.a_ = lo;
  s.b_ = hi;
  s.tol_ = tol;
  return s;
}

NodeSelector NodeSelector::sphere(const Vec3& center, double radius, double tol) {
  NodeSelector s;
  s.kind_ = Kind::sphere;
  s.a_ = center;
  s.value_ = radius;
  s.tol_ = tol;
  return s;
}

NodeSelector NodeSelector::nearest(const Vec3& point) {
  NodeSelector s;
  s.kind_ = Kind::nearest;
  s.a_ = point;
  return s;
}

NodeSelector NodeSelector::patch(const std::string& name) {
  NodeSelector s;
  s.kind_ = Kind::patch;
  s.name_ = name;
  return s;
}

NodeSelector NodeSelector::patch_edge(const std::string& name, PatchEdge edge) {
  NodeSelector s;
  s.kind_ = Kind::patch_edge;
  s.name_ = name;
  s.edge_ = edge;
  return s;
}

NodeSelector NodeSelector::union_of(std::vector<NodeSelector> parts) {
  NodeSelector s;
  s.kind_ = Kind::union_of;
  s.children_ = std::move(parts);
  return s;
}

NodeSelector NodeSelector::intersection_of(std::vector<NodeSelector> parts) {
  if (parts.empty()) throw std::invalid_argument("intersection node set: needs at least one operand");
  NodeSelector s;
  s.kind_ = Kind::intersection_of;
  s.children_ = std::move(parts);
  return s;
}

NodeSelector NodeSelector::difference(NodeSelector a, NodeSelector b) {
  NodeSelector s;
  s.kind_ = Kind::difference;
  s.children_ = {std::move(a), std::move(b)};
  return s;
}

NodeSelector NodeSelector::facing(NodeSelector base, const Vec3& side) {
  if (!(side.allFinite() && side.norm() > 0))
    throw std::invalid_argument("side node set: the side direction must be a finite non-zero vector");
  NodeSelector s;
  s.kind_ = Kind::facing;
  s.a_ = side.normalized();
  s.children_ = {std::move(base)};
  return s;
}

NodeSet NodeSelector::select(const ShellMesh& mesh) const {
  switch (kind_) {
    case Kind::all: {
      NodeSet out(mesh.node_count());
      for (int i = 0; i < mesh.node_count(); ++i) out[i] = i;
      return out;
    }
    case Kind::ids:
      for (int i : ids_)
        if (i < 0 || i >= mesh.node_count())
          throw std::invalid_argument("node id " + std::to_string(i) + " is outside the mesh (0.." +
                                      std::to_string(mesh.node_count() - 1) + ")");
      return ids_;
    case Kind::plane: return nodes_on_plane(mesh, a_, b_, tol_);
    case Kind::box: return nodes_in_box(mesh, a_, b_, tol_);
    case Kind::sphere: return nodes_in_sphere(mesh, a_, value_, tol_);
    case Kind::nearest: return nearest_node(mesh, a_);
    case Kind::patch: return patch_nodes(mesh, name_);
    case Kind::patch_edge: return patch_edge_nodes(mesh, name_, edge_);
    case Kind::union_of: {
      NodeSet out;
      for (const auto& c : children_) out = set_union(out, c.select(mesh));
      return out;
    }
    case Kind::intersection_of: {
      NodeSet out = children_.front().select(mesh);
      for (std::size_t k = 1; k < children_.size(); ++k) out = set_intersection(out, children_[k].select(mesh));
      return out;
    }
    case Kind::difference: return set_difference(children_[0].select(mesh), children_[1].select(mesh));
    case Kind::facing: {
      const NodeSet facing = nodes_facing(mesh, a_);
      const NodeSelector& base = children_[0];
      if (base.kind_ != Kind::nearest) return set_intersection(base.select(mesh), facing);
      // nearest first would pick one of two coincident lip nodes by id, not by side
      int best = -1;
      double best_d = std::numeric_limits<double>::infinity();
      for (int i : facing)
        if (const double d = (mesh.points[i] - base.a_).squaredNorm(); d < best_d) best_d = d, best = i;
      return best < 0 ? NodeSet{} : NodeSet{best};
    }
  }
  return {};
}

std::string NodeSelector::describe() const {
  auto join = [this](const char* word) {
    std::string s;
    for (std::size_t k = 0; k < children_.size(); ++k) {
      if (k) s.append(" ").append(word).append(" ");
      s.append(parens(children_[k].describe()));
    }
    return s;
  };
  switch (kind_) {
    case Kind::all: return "all nodes";
    case Kind::ids: {
      std::string s = "nodes with ids {";
      for (std::size_t k = 0; k < ids_.size(); ++k) s += (k ? ", " : "") + std::to_string(ids_[k]);
      return s + "}";
    }
    case Kind::plane:
      return "nodes within " + tol_words(tol_) + " of the plane through " + vec(a_) + " with normal " + vec(b_);
    case Kind::box: return "nodes in the box " + vec(a_) + " to " + vec(b_) + " (tolerance " + tol_words(tol_) + ")";
    case Kind::sphere:
      return "nodes within distance " + num(value_) + " of " + vec(a_) + " (tolerance " + tol_words(tol_) + ")";
    case Kind::nearest: return "the node nearest to " + vec(a_);
    case Kind::patch: return "the nodes of patch '" + name_ + "'";
    case Kind::patch_edge: return "the nodes on edge " + std::string(to_string(edge_)) + " of patch '" + name_ + "'";
    case Kind::union_of: return children_.empty() ? "no nodes (empty union)" : join("or");
    case Kind::intersection_of: return join("and");
    case Kind::difference: return parens(children_[0].describe()) + " but not " + parens(children_[1].describe());
    case Kind::facing:
      return parens(children_[0].describe()) + ", keeping nodes whose quads all lie toward " + vec(a_) +
             " (side)";
  }
  return "?";
}

std::string empty_selection_message(const std::string& set_name, const NodeSelector& selector, const ShellMesh& mesh) {
  std::string s = "node set '" + set_name + "' is empty: it asks for " + selector.describe();
  if (mesh.node_count() == 0) return s + ", but the mesh has no nodes";
  Vec3 lo = mesh.points[0], hi = mesh.points[0];
  for (const auto& p : mesh.points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  s += "; the mesh (" + std::to_string(mesh.node_count()) + " nodes) spans x in [" + num(lo.x()) + ", " + num(hi.x()) +
       "], y in [" + num(lo.y()) + ", " + num(hi.y()) + "], z in [" + num(lo.z()) + ", " + num(hi.z()) +
       "]; automatic tolerance " + num(resolve_tolerance(mesh, kAutoTolerance));
  return s;
}

}  // namespace ff::mesh
