#include "core/mesh/shell_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <sstream>
#include <unordered_map>

namespace ff::mesh {

namespace {

using Vec3 = Eigen::Vector3d;

std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return (hi << 32) | lo;
}

// every edge of the mesh with the quads that use it and the direction they run it in
struct EdgeUse {
  int quad;
  int from;  // start node as traversed by this quad
};
using EdgeMap = std::unordered_map<std::uint64_t, std::vector<EdgeUse>>;

EdgeMap build_edge_map(const ShellMesh& mesh) {
  EdgeMap edges;
  edges.reserve(mesh.quads.size() * 2);
  for (int q = 0; q < mesh.quad_count(); ++q) {
    const auto& c = mesh.quads[q];
    for (int k = 0; k < 4; ++k) edges[edge_key(c[k], c[(k + 1) % 4])].push_back({q, c[k]});
  }
  return edges;
}

// bilinear tangents at (xi, eta) in [-1, 1]^2
void bilinear_tangents(const std::array<Vec3, 4>& x, double xi, double eta, Vec3& x_xi,
                       Vec3& x_eta) {
  x_xi = 0.25 * (-(1 - eta) * x[0] + (1 - eta) * x[1] + (1 + eta) * x[2] - (1 + eta) * x[3]);
  x_eta = 0.25 * (-(1 - xi) * x[0] - (1 + xi) * x[1] + (1 + xi) * x[2] + (1 - xi) * x[3]);
}

std::array<Vec3, 4> corners(const ShellMesh& mesh, int q) {
  const auto& c = mesh.quads[q];
  return {mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]], mesh.points[c[3]]};
}

std::string vec_str(const Vec3& v) {
  std::ostringstream s;
  s.precision(6);
  s << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return s.str();
}

void flip_quad(ShellMesh& mesh, int q) {
  auto& c = mesh.quads[q];
  std::swap(c[1], c[3]);
  if (static_cast<int>(mesh.corner_normals.size()) > q) std::swap(mesh.corner_normals[q][1], mesh.corner_normals[q][3]);
}

}  // namespace

int ShellMesh::fold_count() const {
  return static_cast<int>(std::count_if(fold.begin(), fold.end(), [](std::uint8_t f) { return f != 0; }));
}

int ShellMesh::find_group(const std::string& name) const {
  for (std::size_t i = 0; i < groups.size(); ++i)
    if (groups[i].name == name) return static_cast<int>(i);
  return -1;
}

int ShellMesh::find_patch(const std::string& name) const {
  for (std::size_t i = 0; i < patches.size(); ++i)
    if (patches[i].name == name) return static_cast<int>(i);
  return -1;
}

double quad_area(const ShellMesh& mesh, int q) {
  const auto x = corners(mesh, q);
  const double g = 1.0 / std::sqrt(3.0);
  double area = 0;
  for (double xi : {-g, g})
    for (double eta : {-g, g}) {
      Vec3 a, b;
      bilinear_tangents(x, xi, eta, a, b);
      area += a.cross(b).norm();  // weights 1 x 1
    }
  return area;
}

Eigen::Vector3d quad_normal(const ShellMesh& mesh, int q) {
  const auto x = corners(mesh, q);
  const Vec3 n = (x[2] - x[0]).cross(x[3] - x[1]);
  const double len = n.norm();
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

double total_area(const ShellMesh& mesh) {
  double a = 0;
  for (int q = 0; q < mesh.quad_count(); ++q) a += quad_area(mesh, q);
  return a;
}

double min_edge_length(const ShellMesh& mesh) {
  double h = mesh.quads.empty() ? 0.0 : std::numeric_limits<double>::infinity();
  for (const auto& c : mesh.quads)
    for (int k = 0; k < 4; ++k) h = std::min(h, (mesh.points[c[(k + 1) % 4]] - mesh.points[c[k]]).norm());
  return h;
}

double max_edge_length(const ShellMesh& mesh) {
  double h = 0;
  for (const auto& c : mesh.quads)
    for (int k = 0; k < 4; ++k) h = std::max(h, (mesh.points[c[(k + 1) % 4]] - mesh.points[c[k]]).norm());
  return h;
}

double mean_edge_length(const ShellMesh& mesh, const MeshGroup* group, int* edges) {
  std::vector<char> in_group(mesh.points.size(), group ? 0 : 1);
  if (group)
    for (int i : group->nodes)
      if (i >= 0 && i < mesh.node_count()) in_group[i] = 1;
  std::map<std::uint64_t, double> length;
  for (const auto& c : mesh.quads)
    for (int k = 0; k < 4; ++k) {
      const int a = c[k], b = c[(k + 1) % 4];
      if (in_group[a] || in_group[b]) length.emplace(edge_key(a, b), (mesh.points[b] - mesh.points[a]).norm());
    }
  double sum = 0;
  for (const auto& [key, l] : length) sum += l;
  if (edges) *edges = static_cast<int>(length.size());
  return length.empty() ? 0.0 : sum / static_cast<double>(length.size());
}

void compute_area_weighted_normals(ShellMesh& mesh) {
  mesh.normals.assign(mesh.points.size(), Vec3::Zero());
  for (const auto& c : mesh.quads) {
    // vector area of a (possibly warped) quad: half the cross product of its diagonals
    const Vec3 area = 0.5 * (mesh.points[c[2]] - mesh.points[c[0]]).cross(mesh.points[c[3]] - mesh.points[c[1]]);
    for (int k = 0; k < 4; ++k) mesh.normals[c[k]] += area;
  }
  for (auto& n : mesh.normals) {
    const double len = n.norm();
    if (len > 0) n /= len;
  }
  mesh.fold.assign(mesh.points.size(), 0);
  corner_normals_from_nodes(mesh);
}

void corner_normals_from_nodes(ShellMesh& mesh) {
  mesh.corner_normals.resize(mesh.quads.size());
  for (std::size_t q = 0; q < mesh.quads.size(); ++q)
    for (int k = 0; k < 4; ++k) mesh.corner_normals[q][k] = mesh.normals[mesh.quads[q][k]];
}

Eigen::Matrix3d frame_from_normal(const Eigen::Vector3d& n, const Eigen::Vector3d& reference) {
  const double ref_len = reference.norm();
  Vec3 t = ref_len > 0 ? Vec3(reference / ref_len) : Vec3::UnitX();
  t -= t.dot(n) * n;
  if (t.norm() < 1e-3) {
    // reference (nearly) parallel to the normal: use the global axis least aligned with it
    int axis = 0;
    n.cwiseAbs().minCoeff(&axis);
    t = Vec3::Unit(axis) - n[axis] * n;
  }
  Eigen::Matrix3d R;
  R.col(0) = t.normalized();
  R.col(2) = n;
  R.col(1) = n.cross(R.col(0));
  return R;
}

void compute_frames(ShellMesh& mesh, const Eigen::Vector3d& reference) {
  mesh.frame_reference = reference;
  mesh.frames.resize(mesh.points.size());
  for (std::size_t i = 0; i < mesh.points.size(); ++i) mesh.frames[i] = frame_from_normal(mesh.normals[i], reference);
}

void complete_layout(ShellMesh& mesh, const std::string& patch_name) {
  mesh.fold.resize(mesh.points.size(), 0);
  if (mesh.patches.empty()) {
    Patch p;
    p.name = patch_name;
    p.description = "unstructured quad surface";
    p.quad_count = mesh.quad_count();
    mesh.patches.push_back(p);
  }
  mesh.quad_patch.resize(mesh.quads.size(), 0);
}

bool orient_consistently(ShellMesh& mesh, std::string* why, const OrientationOptions& options, OrientationReport* report) {
  const EdgeMap edges = build_edge_map(mesh);
  const int nq = mesh.quad_count();
  // quads whose orientations depend on each other: `same` when both run their common edge the
  // same way as stored (then exactly one of them turns)
  struct Link {
    int other;
    bool same;
  };
  std::vector<std::vector<Link>> links(static_cast<std::size_t>(nq));
  const auto join = [&](const EdgeUse& u, const EdgeUse& v) {
    links[u.quad].push_back({v.quad, u.from == v.from});
    links[v.quad].push_back({u.quad, u.from == v.from});
  };
  const double continuation = options.continuation_angle_deg * std::numbers::pi / 180.0;
  for (const auto& [key, uses] : edges) {
    if (uses.size() == 2) join(uses[0], uses[1]);
    if (uses.size() <= 2) continue;
    const int a = static_cast<int>(key & 0xffffffffu), b = static_cast<int>(key >> 32);
    if (!options.junction_edges) {
      if (why)
        *why = "edge " + std::to_string(a) + "-" + std::to_string(b) + " is shared by " + std::to_string(uses.size()) +
               " quads (non-manifold), so no consistent orientation exists";
      return false;
    }
    // each quad's wing: from the edge towards its centre, across the edge; two quads continue each
    // other where their wings point (nearly) opposite ways
    const Vec3 along = (mesh.points[b] - mesh.points[a]).normalized();
    std::vector<Vec3> wing;
    for (const EdgeUse& u : uses) {
      Vec3 centre = Vec3::Zero();
      for (int k : mesh.quads[u.quad]) centre += 0.25 * mesh.points[k];
      Vec3 w = centre - mesh.points[a];
      w -= w.dot(along) * along;
      wing.push_back(w.normalized());
    }
    struct Pair {
      double turn;
      std::size_t i, j;
    };
    std::vector<Pair> pairs;
    for (std::size_t i = 0; i < uses.size(); ++i)
      for (std::size_t j = i + 1; j < uses.size(); ++j) {
        const double turn = std::atan2(wing[i].cross(-wing[j]).norm(), wing[i].dot(-wing[j]));
        if (turn < continuation) pairs.push_back({turn, i, j});
      }
    std::sort(pairs.begin(), pairs.end(), [](const Pair& x, const Pair& y) { return x.turn < y.turn; });
    std::vector<char> paired(uses.size(), 0);
    for (const Pair& p : pairs)
      if (!paired[p.i] && !paired[p.j]) paired[p.i] = paired[p.j] = 1, join(uses[p.i], uses[p.j]);
  }

  // each piece breadth-first from its first quad; then the side the larger area had stays
  std::vector<int> state(static_cast<std::size_t>(nq), -1);  // -1 unvisited, 0 kept, 1 flipped
  std::vector<double> area(static_cast<std::size_t>(nq));
  for (int q = 0; q < nq; ++q) area[q] = quad_area(mesh, q);
  OrientationReport r;
  for (int seed = 0; seed < nq; ++seed) {
    if (state[seed] >= 0) continue;
    state[seed] = 0;
    std::vector<int> piece{seed};
    for (std::size_t next = 0; next < piece.size(); ++next) {
      const int q = piece[next];
      for (const Link& l : links[q]) {
        const int want = l.same ? 1 - state[q] : state[q];
        if (state[l.other] < 0) {
          state[l.other] = want;
          piece.push_back(l.other);
        } else if (state[l.other] != want) {
          if (why)
            *why = "the surface is not orientable (quads " + std::to_string(q) + " and " + std::to_string(l.other) +
                   " cannot agree; a Moebius-like band?)";
          return false;
        }
      }
    }
    double kept = 0.0, turned = 0.0;
    for (int q : piece) (state[q] ? turned : kept) += area[q];
    if (turned > kept) {
      for (int q : piece) state[q] = 1 - state[q];
      std::swap(kept, turned);
    }
    ++r.pieces;
    if (kept + turned > 0) r.largest_turned_share = std::max(r.largest_turned_share, turned / (kept + turned));
  }
  for (int q = 0; q < nq; ++q) {
    r.area += area[q];
    if (state[q] != 1) continue;
    flip_quad(mesh, q);
    ++r.flipped;
    r.flipped_area += area[q];
  }
  if (report) *report = r;
  return true;
}

const char* to_string(IssueKind kind) {
  switch (kind) {
    case IssueKind::layout: return "layout";
    case IssueKind::non_finite: return "non-finite value";
    case IssueKind::bad_normal: return "bad normal";
    case IssueKind::degenerate_quad: return "degenerate quad";
    case IssueKind::inverted_quad: return "inverted quad";
    case IssueKind::normal_mismatch: return "normal mismatch";
    case IssueKind::unused_node: return "unused node";
    case IssueKind::duplicate_quad: return "duplicate quad";
    case IssueKind::inconsistent_orientation: return "inconsistent orientation";
    case IssueKind::non_manifold_edge: return "non-manifold edge";
    case IssueKind::bad_frame: return "bad frame";
  }
  return "unknown";
}

int MeshCheck::count(IssueKind kind) const {
  return static_cast<int>(std::count_if(issues.begin(), issues.end(), [kind](const MeshIssue& i) { return i.kind == kind; }));
}

std::string MeshCheck::summary(int max_lines) const {
  std::ostringstream s;
  int shown = 0;
  for (const auto& i : issues) {
    if (shown == max_lines) break;
    s << to_string(i.kind) << ": " << i.message << "\n";
    ++shown;
  }
  if (static_cast<int>(issues.size()) > shown) s << "... and " << issues.size() - shown << " more\n";
  return s.str();
}

MeshCheck validate(const ShellMesh& mesh) {
  MeshCheck check;
  auto add = [&check](IssueKind k, std::string msg, int quad = -1, int node = -1) {
    check.issues.push_back({k, std::move(msg), quad, node});
  };
  const std::size_t n = mesh.points.size(), nq = mesh.quads.size();

  // layout first: everything below indexes these arrays
  auto size_check = [&](const char* what, std::size_t got, std::size_t want, const char* per) {
    if (got != want)
      add(IssueKind::layout, std::string(what) + " has " + std::to_string(got) + " entries, expected " +
                                 std::to_string(want) + " (one per " + per + ")");
  };
  size_check("normals", mesh.normals.size(), n, "node");
  size_check("frames", mesh.frames.size(), n, "node");
  size_check("fold", mesh.fold.size(), n, "node");
  size_check("corner_normals", mesh.corner_normals.size(), nq, "quad");
  size_check("quad_patch", mesh.quad_patch.size(), nq, "quad");
  for (std::size_t q = 0; q < nq; ++q) {
    const auto& c = mesh.quads[q];
    for (int k = 0; k < 4; ++k) {
      if (c[k] < 0 || c[k] >= static_cast<int>(n))
        add(IssueKind::layout, "quad " + std::to_string(q) + " corner " + std::to_string(k) + " refers to node " +
                                   std::to_string(c[k]) + " but the mesh has " + std::to_string(n) + " nodes",
            static_cast<int>(q));
      for (int l = k + 1; l < 4; ++l)
        if (c[k] == c[l])
          add(IssueKind::layout, "quad " + std::to_string(q) + " uses node " + std::to_string(c[k]) +
                                     " twice (collapsed corner)", static_cast<int>(q), c[k]);
    }
    if (q < mesh.quad_patch.size() &&
        (mesh.quad_patch[q] < 0 || mesh.quad_patch[q] >= static_cast<int>(mesh.patches.size())))
      add(IssueKind::layout, "quad " + std::to_string(q) + " belongs to patch " + std::to_string(mesh.quad_patch[q]) +
                                 " but the mesh has " + std::to_string(mesh.patches.size()) + " patches",
          static_cast<int>(q));
  }
  for (const auto& p : mesh.patches)
    for (int id : p.grid)
      if (id < 0 || id >= static_cast<int>(n)) {
        add(IssueKind::layout, "patch '" + p.name + "' grid refers to node " + std::to_string(id) +
                                   " outside the mesh");
        break;
      }
  for (const auto& g : mesh.groups) {
    const bool nodes_ok = std::all_of(g.nodes.begin(), g.nodes.end(), [&](int id) { return id >= 0 && id < static_cast<int>(n); });
    const bool quads_ok = std::all_of(g.quads.begin(), g.quads.end(), [&](int q) { return q >= 0 && q < static_cast<int>(nq); });
    if (!nodes_ok || !quads_ok)
      add(IssueKind::layout, "group '" + g.name + "' refers to a " + (nodes_ok ? "quad" : "node") + " outside the mesh");
  }
  if (!check.ok()) return check;

  for (std::size_t i = 0; i < n; ++i) {
    if (!mesh.points[i].allFinite() || !mesh.normals[i].allFinite()) {
      add(IssueKind::non_finite, "node " + std::to_string(i) + " has a non-finite position or normal",
          -1, static_cast<int>(i));
      continue;
    }
    if (std::abs(mesh.normals[i].norm() - 1.0) > 1e-9)
      add(IssueKind::bad_normal, "node " + std::to_string(i) + " normal " + vec_str(mesh.normals[i]) +
                                     " is not of unit length", -1, static_cast<int>(i));
    const Eigen::Matrix3d& R = mesh.frames[i];
    if (!R.allFinite() || (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() > 1e-9 || R.determinant() < 0 ||
        (R.col(2) - mesh.normals[i]).norm() > 1e-9)
      add(IssueKind::bad_frame, "node " + std::to_string(i) + " frame R0 is not a rotation with e3 = normal",
          -1, static_cast<int>(i));
  }
  for (std::size_t q = 0; q < nq; ++q)
    for (int k = 0; k < 4; ++k) {
      const Vec3& d = mesh.corner_normals[q][k];
      if (!d.allFinite() || std::abs(d.norm() - 1.0) > 1e-9) {
        add(IssueKind::bad_normal, "quad " + std::to_string(q) + " corner " + std::to_string(k) +
                                       " director is not a finite unit vector", static_cast<int>(q));
        break;
      }
    }

  // shape of every quad against its own corner directors
  const double h_max = max_edge_length(mesh);
  const double len_tol = 1e-10 * h_max;
  for (std::size_t q = 0; q < nq; ++q) {
    const int qi = static_cast<int>(q);
    const auto x = corners(mesh, qi);
    double longest = 0, shortest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 4; ++k) {
      const double e = (x[(k + 1) % 4] - x[k]).norm();
      longest = std::max(longest, e);
      shortest = std::min(shortest, e);
    }
    const Vec3 g = (x[2] - x[0]).cross(x[3] - x[1]);  // twice the vector area
    if (shortest <= len_tol || g.norm() <= 1e-10 * longest * longest) {
      add(IssueKind::degenerate_quad, "quad " + std::to_string(q) + " is degenerate (shortest edge " +
                                          std::to_string(shortest) + ", area " + std::to_string(0.5 * g.norm()) + ")",
          qi);
      continue;
    }
    int clockwise = 0, collapsed = 0, opposing = 0;
    for (int k = 0; k < 4; ++k) {
      const Vec3 a = x[(k + 1) % 4] - x[k], b = x[(k + 3) % 4] - x[k];
      const Vec3 c = a.cross(b);
      const Vec3& d = mesh.corner_normals[q][k];
      if (c.norm() <= 1e-10 * a.norm() * b.norm()) ++collapsed;
      else if (c.dot(d) <= 0) ++clockwise;
      if (g.dot(d) <= 0) ++opposing;
    }
    if (collapsed > 0) {
      add(IssueKind::degenerate_quad, "quad " + std::to_string(q) + " has " + std::to_string(collapsed) +
                                          " corner(s) with a 0 or 180 degree angle (a triangle or a line)", qi);
    } else if (opposing == 4) {
      add(IssueKind::normal_mismatch, "quad " + std::to_string(q) +
                                          " runs clockwise about its directors (node order or normals reversed)", qi);
    } else if (clockwise > 0) {
      add(IssueKind::inverted_quad, "quad " + std::to_string(q) + " has " + std::to_string(clockwise) +
                                        " corner(s) turning clockwise about the director (non-convex or twisted)", qi);
    } else if (opposing > 0) {
      add(IssueKind::normal_mismatch, "quad " + std::to_string(q) + " geometric normal opposes the director at " +
                                          std::to_string(opposing) + " corner(s)", qi);
    }
  }

  std::vector<char> used(n, 0);
  for (const auto& c : mesh.quads)
    for (int k : c) used[k] = 1;
  for (std::size_t i = 0; i < n; ++i)
    if (!used[i])
      add(IssueKind::unused_node, "node " + std::to_string(i) + " at " + vec_str(mesh.points[i]) +
                                      " belongs to no quad", -1, static_cast<int>(i));

  // the same four nodes twice (a face exported twice, or an assembly overlapping itself)
  std::map<std::array<int, 4>, int> seen;
  for (std::size_t q = 0; q < nq; ++q) {
    std::array<int, 4> key = mesh.quads[q];
    std::sort(key.begin(), key.end());
    const auto [it, fresh] = seen.emplace(key, static_cast<int>(q));
    if (!fresh)
      add(IssueKind::duplicate_quad, "quad " + std::to_string(q) + " has the same nodes as quad " +
                                         std::to_string(it->second), static_cast<int>(q));
  }

  // topology: two quads per interior edge, running it in opposite directions
  const EdgeMap edges = build_edge_map(mesh);
  std::vector<std::pair<std::uint64_t, const std::vector<EdgeUse>*>> sorted;
  sorted.reserve(edges.size());
  for (const auto& e : edges) sorted.emplace_back(e.first, &e.second);
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [key, uses] : sorted) {
    const int lo = static_cast<int>(key & 0xffffffffu), hi = static_cast<int>(key >> 32);
    const std::string edge = "edge " + std::to_string(lo) + "-" + std::to_string(hi);
    if (uses->size() > 2) {
      std::string qs;
      for (const auto& u : *uses) qs += (qs.empty() ? "" : ", ") + std::to_string(u.quad);
      add(IssueKind::non_manifold_edge, edge + " is shared by " + std::to_string(uses->size()) + " quads (" + qs + ")",
          (*uses)[0].quad);
    } else if (uses->size() == 2 && (*uses)[0].from == (*uses)[1].from) {
      add(IssueKind::inconsistent_orientation, edge + " is run in the same direction by quads " +
                                                   std::to_string((*uses)[0].quad) + " and " +
                                                   std::to_string((*uses)[1].quad) + " (one of them is flipped)",
          (*uses)[1].quad);
    }
  }
  return check;
}

}  // namespace ff::mesh
