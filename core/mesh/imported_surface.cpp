#include "core/mesh/imported_surface.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <utility>

namespace ff::mesh {

namespace {

using Vec3 = Eigen::Vector3d;

bool fail(std::string* error, const std::string& message) {
  if (error) *error = message;
  return false;
}

std::string who(const ImportedSurface& in) { return in.file.empty() ? std::string("the mesh") : "'" + in.file + "'"; }

std::string element_name(const ImportedSurface& in, int e) {
  const std::string& w = in.elements[static_cast<std::size_t>(e)].where;
  return w.empty() ? "element " + std::to_string(e) : w;
}

int corners(const ImportedElement& e) { return e.triangle() ? 3 : 4; }

std::pair<int, int> edge_key(int a, int b) { return a < b ? std::make_pair(a, b) : std::make_pair(b, a); }

// vector area of an element (twice the area for a triangle's cross product halved; the quad's
// diagonals' cross product halved): its direction is the element's normal by its winding
Vec3 vector_area(const std::vector<Vec3>& x, const std::array<int, 4>& n, int k) {
  if (k == 3) return 0.5 * (x[n[1]] - x[n[0]]).cross(x[n[2]] - x[n[0]]);
  return 0.5 * (x[n[2]] - x[n[0]]).cross(x[n[3]] - x[n[1]]);
}

double angle_between(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)); }

// distance from p to the triangle (a, b, c): the closest point by the region p projects into
// (Voronoi regions of the vertices, edges and face; e.g. Ericson, Real-Time Collision Detection, 5.1.5)
double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + d1 / (d1 - d3) * ab)).norm();
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + d2 / (d2 - d6) * ac)).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) return (p - (b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b))).norm();
  const double denom = 1.0 / (va + vb + vc);
  return (p - (a + ab * (vb * denom) + ac * (vc * denom))).norm();
}

}  // namespace

// (S9)
UnjoinedContacts find_unjoined_contacts(const ShellMesh& m) {
  UnjoinedContacts out;
  const int nq = m.quad_count(), nn = m.node_count();
  if (nq == 0) return out;
  const double tol = 1e-6 * min_edge_length(m);
  std::map<std::pair<int, int>, int> edge_uses;
  double total = 0.0;
  for (const auto& q : m.quads)
    for (int k = 0; k < 4; ++k) {
      ++edge_uses[edge_key(q[k], q[(k + 1) % 4])];
      total += (m.points[q[(k + 1) % 4]] - m.points[q[k]]).norm();
    }
  std::vector<char> boundary(static_cast<std::size_t>(nn), 0);
  for (const auto& [edge, uses] : edge_uses)
    if (uses == 1) boundary[edge.first] = boundary[edge.second] = 1;
  // every quad in each cell its box (grown by tol) touches; cells of about an element's size, and
  // at least an eighth of the longest edge so that no quad spans more than a few cells
  const double cell = std::max({total / (4.0 * nq), max_edge_length(m) / 8.0, 1e-300});
  Vec3 lo = m.points[0];
  for (const Vec3& x : m.points) lo = lo.cwiseMin(x);
  const auto cell_of = [&](const Vec3& x) {
    return std::array<long long, 3>{static_cast<long long>(std::floor((x.x() - lo.x()) / cell)),
                                    static_cast<long long>(std::floor((x.y() - lo.y()) / cell)),
                                    static_cast<long long>(std::floor((x.z() - lo.z()) / cell))};
  };
  std::map<std::array<long long, 3>, std::vector<int>> grid;
  for (int q = 0; q < nq; ++q) {
    Vec3 a = m.points[m.quads[q][0]], b = a;
    for (int k : m.quads[q]) a = a.cwiseMin(m.points[k]), b = b.cwiseMax(m.points[k]);
    const auto c0 = cell_of(a - Vec3::Constant(tol)), c1 = cell_of(b + Vec3::Constant(tol));
    for (long long i = c0[0]; i <= c1[0]; ++i)
      for (long long j = c0[1]; j <= c1[1]; ++j)
        for (long long k = c0[2]; k <= c1[2]; ++k) grid[{i, j, k}].push_back(q);
  }
  for (int I = 0; I < nn; ++I) {
    if (!boundary[I]) continue;
    const auto it = grid.find(cell_of(m.points[I]));
    if (it == grid.end()) continue;
    for (int q : it->second) {
      const auto& c = m.quads[q];
      if (std::find(c.begin(), c.end(), I) != c.end()) continue;
      const Vec3& x = m.points[I];
      const double d = std::min(distance_to_triangle(x, m.points[c[0]], m.points[c[1]], m.points[c[2]]),
                                distance_to_triangle(x, m.points[c[0]], m.points[c[2]], m.points[c[3]]));
      if (d > tol) continue;
      if (out.nodes == 0) out.first_node = I, out.first_quad = q;
      ++out.nodes;
      break;
    }
  }
  return out;
}

std::string SurfaceConversionReport::summary() const {
  std::ostringstream s;
  if (triangles_split)
    s << triangles_in << " triangles" << (quads_split ? " and " + std::to_string(quads_in) + " quads" : std::string())
      << " split into " << quads_out << " quads" << (quads_split ? " (a mixed mesh: every quad into four, so it stays conforming)" : "");
  else
    s << quads_out << " quads as read";
  if (flipped > 0) {
    s << "; " << flipped << " quads turned to agree with their neighbours (";
    if (turned_share >= kLoudTurnedShare) s << "WARNING: ";
    s << std::lround(100.0 * turned_share) << " % of the area of a piece; each piece keeps the side most of its area "
      << "was wound to)";
  }
  s << "; directors " << (exact_normals ? "from the surface's own normals" : "averaged over each smooth piece");
  if (junction_edges > 0) s << "; " << junction_edges << " element edges where three or more faces meet (a T: fold nodes there)";
  if (folds > 0) s << "; " << folds << " fold nodes (6 DoF) where pieces meet at a crease";
  return s.str();
}

std::string SurfaceConversionReport::turned_warning() const {
  if (flipped == 0 || turned_share < kLoudTurnedShare) return {};
  return std::to_string(flipped) + " quads, " + std::to_string(std::lround(100.0 * turned_share)) +
         " % of the area of one piece of the surface, were wound the other way and were turned to agree with their "
         "neighbours: the piece's directors face the side most of its area was wound to, and a pressure pushes along "
         "them; if that is the wrong side, set part.flip_director = true";
}

bool shell_mesh_from_surface(const ImportedSurface& in, const SurfaceConversionOptions& options, ShellMesh& out,
                             std::string* error, SurfaceConversionReport* report) {
  const std::string file = who(in);
  const int np = static_cast<int>(in.points.size());
  const bool exact = !in.corner_normals.empty();
  if (exact && in.corner_normals.size() != in.elements.size())
    return fail(error, file + ": the reader gave normals for " + std::to_string(in.corner_normals.size()) + " of " +
                           std::to_string(in.elements.size()) + " elements");
  for (std::size_t p = 0; p < in.points.size(); ++p)
    if (!in.points[p].allFinite() || in.points[p].cwiseAbs().maxCoeff() > 1e150)
      return fail(error, file + ": node " + std::to_string(p) + " has a coordinate that is not a finite number below 1e150");

  // ---- which elements: all, or one surface group's ------------------------------------------
  std::vector<int> chosen;
  if (options.only_group.empty()) {
    chosen.resize(in.elements.size());
    for (std::size_t e = 0; e < in.elements.size(); ++e) chosen[e] = static_cast<int>(e);
  } else {
    const ImportedGroup* g = nullptr;
    std::string surfaces;
    for (const ImportedGroup& c : in.groups) {
      if (c.dimension != 2) continue;
      surfaces += (surfaces.empty() ? "" : ", ") + c.name;
      if (c.name == options.only_group) g = &c;
    }
    if (!g)
      return fail(error, file + " has no surface group called '" + options.only_group + "' (" +
                             (surfaces.empty() ? std::string("it has no surface groups") : "its surface groups: " + surfaces) + ")");
    chosen = g->elements;
    std::sort(chosen.begin(), chosen.end());
    chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  }
  if (chosen.empty()) return fail(error, file + " contains no surface elements (a shell mesh needs quads or triangles)");

  // ---- elements checked: nodes exist, no corner twice -----------------------------------------
  int triangles = 0, quads = 0, first_triangle = -1;
  for (int e : chosen) {
    if (e < 0 || e >= static_cast<int>(in.elements.size()))
      return fail(error, file + ": a group names element " + std::to_string(e) + ", which does not exist");
    const ImportedElement& el = in.elements[static_cast<std::size_t>(e)];
    const int k = corners(el);
    (k == 3 ? triangles : quads)++;
    if (k == 3 && first_triangle < 0) first_triangle = e;
    for (int a = 0; a < k; ++a) {
      if (el.nodes[a] < 0 || el.nodes[a] >= np)
        return fail(error, file + ": " + element_name(in, e) + " names node " + std::to_string(el.nodes[a]) +
                               ", which does not exist");
      for (int b = a + 1; b < k; ++b)
        if (el.nodes[a] == el.nodes[b])
          return fail(error, file + ": " + element_name(in, e) + " uses one node twice (a collapsed element)");
    }
  }
  if (triangles > 0 && options.triangles == TriangleHandling::refuse)
    return fail(error, file + " holds " + std::to_string(triangles) + " triangles (and " + std::to_string(quads) +
                           " quads; the first triangle is " + element_name(in, first_triangle) +
                           "); the shell element is a 4-node quad: set part.triangles = \"split\" (each triangle into "
                           "three quads) or \"recombine\" (Gmsh joins them into quads)");

  // ---- (S1)-(S3) the quads: as read, or split --------------------------------------------------
  // points of the shell mesh: the file's, then edge midpoints and element centres when splitting
  std::vector<Vec3> points = in.points;
  std::vector<std::array<int, 4>> qs;
  std::vector<int> source;                         // element of each quad
  std::vector<std::array<Vec3, 4>> exact_normals;  // per quad corner, when the reader gave them
  std::map<std::pair<int, int>, int> midpoint;     // edge -> its midpoint node
  const bool split = triangles > 0;
  const bool split_quads = split && quads > 0;
  const auto mid = [&](int a, int b) {
    const auto key = edge_key(a, b);
    const auto it = midpoint.find(key);
    if (it != midpoint.end()) return it->second;
    const int id = static_cast<int>(points.size());
    points.push_back(0.5 * (points[a] + points[b]));  // (S1) the straight edge's midpoint
    midpoint.emplace(key, id);
    return id;
  };
  for (int e : chosen) {
    const ImportedElement& el = in.elements[static_cast<std::size_t>(e)];
    const int k = corners(el);
    std::array<Vec3, 4> n;
    for (int a = 0; a < 4; ++a) n[a] = exact ? in.corner_normals[static_cast<std::size_t>(e)][a] : Vec3::UnitZ();
    if (!split || (k == 4 && !split_quads)) {
      qs.push_back(el.nodes);
      source.push_back(e);
      exact_normals.push_back(n);
      continue;
    }
    // (S2) a triangle: three quads through its centroid; (S3) a quad: four through its centre
    const int centre = static_cast<int>(points.size());
    Vec3 c = Vec3::Zero(), nc = Vec3::Zero();
    for (int a = 0; a < k; ++a) c += points[el.nodes[a]], nc += n[a];
    points.push_back(c / k);
    std::array<int, 4> m;
    for (int a = 0; a < k; ++a) m[a] = mid(el.nodes[a], el.nodes[(a + 1) % k]);
    for (int a = 0; a < k; ++a) {
      const int prev = (a + k - 1) % k;
      qs.push_back({el.nodes[a], m[a], centre, m[prev]});
      source.push_back(e);
      const Vec3 nm_a = (n[a] + n[(a + 1) % k]).normalized(), nm_p = (n[prev] + n[a]).normalized();
      exact_normals.push_back({n[a], nm_a, nc.normalized(), nm_p});
    }
  }
  if (exact)
    for (const auto& c : exact_normals)
      for (const Vec3& v : c)
        if (!v.allFinite() || !(v.norm() > 0.5))
          return fail(error, file + ": the mesher gave a zero or non-finite surface normal");

  // ---- (S7)-(S8) orientation: each piece on the side most of its area was wound to -------------
  ShellMesh m;
  m.points = points;
  m.quads = qs;
  std::string why;
  ShellMesh oriented = m;
  OrientationOptions orientation;
  orientation.junction_edges = true;  // a T of faces: the faces that continue each other agree
  orientation.continuation_angle_deg = options.crease_angle_deg;
  OrientationReport turned;
  if (!orient_consistently(oriented, &why, orientation, &turned))
    return fail(error, file + ": " + why + " (numbers: quads in the order made from the file's elements)");
  for (std::size_t q = 0; q < qs.size(); ++q)
    if (oriented.quads[q] != qs[q]) std::swap(exact_normals[q][1], exact_normals[q][3]);
  m.quads = std::move(oriented.quads);

  // drop nodes no quad uses (a group's part of the file, or stray file nodes), number by first use
  std::vector<int> new_id(points.size(), -1);
  std::vector<Vec3> kept;
  for (auto& q : m.quads)
    for (int& k : q) {
      if (new_id[k] < 0) new_id[k] = static_cast<int>(kept.size()), kept.push_back(points[k]);
      k = new_id[k];
    }
  m.points = std::move(kept);
  const int nn = m.node_count(), nq = m.quad_count();

  // ---- (S4)-(S5) directors and fold nodes ------------------------------------------------------
  m.corner_normals.assign(nq, {});
  m.normals.assign(nn, Vec3::Zero());
  m.fold.assign(nn, 0);
  // (S5) the nodes of an edge where three or more faces meet (a T) are fold nodes, whatever
  // their directors
  std::map<std::pair<int, int>, int> edge_uses;
  for (const auto& q : m.quads)
    for (int k = 0; k < 4; ++k) ++edge_uses[edge_key(q[k], q[(k + 1) % 4])];
  int junction_edges = 0;
  for (const auto& [edge, uses] : edge_uses)
    if (uses > 2) ++junction_edges, m.fold[edge.first] = m.fold[edge.second] = 1;
  if (exact) {
    // the surface's own normal, turned to the quad's side; a node whose corners disagree lies on
    // a crease between CAD faces: a fold node, each quad keeping its face's normal
    for (int q = 0; q < nq; ++q) {
      const Vec3 g = vector_area(m.points, m.quads[q], 4);
      for (int k = 0; k < 4; ++k) {
        Vec3 v = exact_normals[q][k].normalized();
        if (v.dot(g) < 0) v = -v;
        m.corner_normals[q][k] = v;
      }
    }
    std::vector<Vec3> first(nn, Vec3::Zero()), sum(nn, Vec3::Zero());
    for (int q = 0; q < nq; ++q)
      for (int k = 0; k < 4; ++k) {
        const int I = m.quads[q][k];
        const Vec3& v = m.corner_normals[q][k];
        if (first[I].isZero()) first[I] = v;
        else if (angle_between(first[I], v) > 1e-5) m.fold[I] = 1;
        sum[I] += v;
      }
    for (int I = 0; I < nn; ++I) m.normals[I] = m.fold[I] ? first[I] : sum[I].normalized();
  } else {
    // smooth pieces: quads joined across edges where their normals turn less than the crease angle
    const double crease = options.crease_angle_deg * std::numbers::pi / 180.0;
    std::vector<Vec3> qn(nq);
    for (int q = 0; q < nq; ++q) qn[q] = vector_area(m.points, m.quads[q], 4);
    std::map<std::pair<int, int>, std::vector<int>> edge_quads;
    for (int q = 0; q < nq; ++q)
      for (int k = 0; k < 4; ++k) edge_quads[edge_key(m.quads[q][k], m.quads[q][(k + 1) % 4])].push_back(q);
    std::vector<int> piece(nq, -1);
    int pieces = 0;
    for (int start = 0; start < nq; ++start) {
      if (piece[start] >= 0) continue;
      std::vector<int> stack{start};
      piece[start] = pieces;
      while (!stack.empty()) {
        const int q = stack.back();
        stack.pop_back();
        for (int k = 0; k < 4; ++k)
          for (int r : edge_quads[edge_key(m.quads[q][k], m.quads[q][(k + 1) % 4])])
            if (piece[r] < 0 && angle_between(qn[q], qn[r]) < crease) piece[r] = pieces, stack.push_back(r);
      }
      ++pieces;
    }
    // (S4) area-weighted normal of each node within each piece
    std::map<std::pair<int, int>, Vec3> piece_normal;  // (node, piece)
    for (int q = 0; q < nq; ++q)
      for (int k = 0; k < 4; ++k)  // try_emplace starts each sum at zero (operator[] leaves an Eigen vector uninitialized)
        piece_normal.try_emplace({m.quads[q][k], piece[q]}, Vec3::Zero()).first->second += qn[q];
    std::vector<int> first_piece(nn, -1);
    for (const auto& [key, v] : piece_normal) {
      const int I = key.first;
      if (first_piece[I] < 0) first_piece[I] = key.second, m.normals[I] = v.normalized();
      else if (angle_between(m.normals[I], v) > 1e-5) m.fold[I] = 1;  // (S5)
    }
    for (int q = 0; q < nq; ++q)
      for (int k = 0; k < 4; ++k) {
        const int I = m.quads[q][k];
        m.corner_normals[q][k] = m.fold[I] ? piece_normal[{I, piece[q]}].normalized() : m.normals[I];
      }
  }
  compute_frames(m, options.frame_reference);
  complete_layout(m, options.patch_name);

  // ---- (S6) groups in the shell mesh's numbers -------------------------------------------------
  std::vector<int> quad_of_element_first(in.elements.size(), -1), quads_of_element(in.elements.size(), 0);
  for (std::size_t q = 0; q < source.size(); ++q) {
    const int e = source[q];
    if (quad_of_element_first[e] < 0) quad_of_element_first[e] = static_cast<int>(q);
    ++quads_of_element[e];
  }
  std::map<std::pair<int, int>, int> file_edge_uses;  // after a split: edges of the chosen elements, by file nodes
  std::vector<char> on_boundary(points.size(), 0);     // ... and the file nodes on a boundary edge
  if (split) {
    for (int e : chosen) {
      const ImportedElement& el = in.elements[static_cast<std::size_t>(e)];
      const int k = corners(el);
      for (int a = 0; a < k; ++a) ++file_edge_uses[edge_key(el.nodes[a], el.nodes[(a + 1) % k])];
    }
    for (const auto& [edge, uses] : file_edge_uses)
      if (uses == 1) on_boundary[edge.first] = on_boundary[edge.second] = 1;
  }
  for (const ImportedGroup& g : in.groups) {
    const std::string origin = g.origin.empty() ? "" : " (" + g.origin + ")";
    if (g.nodes.empty() && g.elements.empty())
      return fail(error, file + ": group '" + g.name + "'" + origin + " is empty: it names no node and no element");
    MeshGroup out_group;
    out_group.name = g.name;
    out_group.dimension = g.dimension;
    out_group.origin = g.origin;
    std::vector<int> nodes;
    for (int p : g.nodes) {
      if (p < 0 || p >= np)
        return fail(error, file + ": group '" + g.name + "'" + origin + " names node " + std::to_string(p) + ", which does not exist");
      if (new_id[p] >= 0) nodes.push_back(new_id[p]);
    }
    for (int e : g.elements) {
      if (e < 0 || e >= static_cast<int>(in.elements.size()))
        return fail(error, file + ": group '" + g.name + "'" + origin + " names element " + std::to_string(e) + ", which does not exist");
      for (int q = quad_of_element_first[e]; q >= 0 && q < quad_of_element_first[e] + quads_of_element[e]; ++q) {
        out_group.quads.push_back(q);
        for (int k : m.quads[q]) nodes.push_back(k);
      }
    }
    if (split) {
      // midpoints of the edges the group holds: its curve's segments when the file has them;
      // otherwise edges with both ends in the group (only boundary edges when every node of the
      // group lies on the boundary, so a support along an edge does not reach across a corner)
      std::vector<char> in_group(points.size(), 0);
      for (int p : g.nodes) in_group[p] = 1;
      bool all_on_boundary = true;
      for (int p : g.nodes) all_on_boundary = all_on_boundary && on_boundary[p];
      if (!g.segments.empty()) {
        for (const auto& s : g.segments) {
          const auto it = midpoint.find(edge_key(s[0], s[1]));
          if (it != midpoint.end() && new_id[it->second] >= 0) nodes.push_back(new_id[it->second]);
        }
      } else if (g.dimension != 2) {
        for (const auto& [edge, mid_node] : midpoint) {
          if (!in_group[edge.first] || !in_group[edge.second] || new_id[mid_node] < 0) continue;
          const auto uses = file_edge_uses.find(edge);
          if (all_on_boundary && (uses == file_edge_uses.end() || uses->second != 1)) continue;
          nodes.push_back(new_id[mid_node]);
        }
      }
    }
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    std::sort(out_group.quads.begin(), out_group.quads.end());
    out_group.nodes = std::move(nodes);
    // a group of another part of the file (only_group) has nothing here: not this part's name
    if (out_group.nodes.empty()) {
      if (!options.only_group.empty()) continue;
      return fail(error, file + ": group '" + g.name + "'" + origin + " selects no node of the surface mesh");
    }
    // one name, one group: an Abaqus *NSET and *ELSET of one name (tools write both) are united
    const int existing = m.find_group(g.name);
    if (existing >= 0) {
      MeshGroup& same = m.groups[static_cast<std::size_t>(existing)];
      same.dimension = std::max(same.dimension, out_group.dimension);
      same.origin += " and " + out_group.origin;
      same.nodes.insert(same.nodes.end(), out_group.nodes.begin(), out_group.nodes.end());
      same.quads.insert(same.quads.end(), out_group.quads.begin(), out_group.quads.end());
      for (std::vector<int>* v : {&same.nodes, &same.quads}) {
        std::sort(v->begin(), v->end());
        v->erase(std::unique(v->begin(), v->end()), v->end());
      }
      continue;
    }
    m.groups.push_back(std::move(out_group));
  }

  // an edge of three or more quads is a T the orientation above joined, not an error here
  MeshCheck check = validate(m);
  std::erase_if(check.issues, [](const MeshIssue& i) { return i.kind == IssueKind::non_manifold_edge; });
  if (!check.ok()) {
    std::string summary = check.summary();
    if (!summary.empty() && summary.back() == '\n') summary.pop_back();
    return fail(error, file + " is not a valid shell mesh (numbers: quads in the order made from the file's elements, "
                              "nodes in order of first use):\n" + summary);
  }
  if (report) {
    report->quads_in = quads;
    report->triangles_in = triangles;
    report->quads_out = nq;
    report->triangles_split = split;
    report->quads_split = split_quads;
    report->flipped = turned.flipped;
    report->turned_share = turned.flipped > 0 ? turned.largest_turned_share : 0.0;
    report->junction_edges = junction_edges;
    report->folds = m.fold_count();
    report->exact_normals = exact;
  }
  out = std::move(m);
  return true;
}

}  // namespace ff::mesh
