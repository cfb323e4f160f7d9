#pragma once
/// \file node_sets.h
/// Geometric node selection, so a scene can name the clamped edge, the symmetry planes and the
/// load points of a benchmark without code. Every function returns a NodeSet: node ids sorted
/// ascending without repeats. An empty set is a valid result; the caller decides whether it is
/// an error and reports it with empty_selection_message(), which says in words what was asked
/// and where the mesh lies.
///
/// Tolerances: a negative tolerance (the default, kAutoTolerance) means 1e-3 times the
/// shortest quad edge of the mesh, which accepts round-off from the generators and the
/// importer but never reaches the next row of nodes.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/mesh/shell_mesh.h"

namespace ff::mesh {

using NodeSet = std::vector<int>;

inline constexpr double kAutoTolerance = -1.0;

/// The tolerance a selector uses on `mesh` for a requested `tol` (see the file comment).
double resolve_tolerance(const ShellMesh& mesh, double tol);

/// Boundary of a structured patch in its parameters: "u=0", "u=1", "v=0", "v=1".
enum class PatchEdge { u_min, u_max, v_min, v_max };
const char* to_string(PatchEdge edge);
/// Accepts "u=0", "u=1", "v=0", "v=1" (also "u0", "u1", "v0", "v1"); nullopt otherwise.
std::optional<PatchEdge> parse_patch_edge(std::string_view text);

/// The edge of patch `patch` that `text` names: "u=0", "u=1", "v=0", "v=1" (as parse_patch_edge)
/// or one of the patch's edge_names (e.g. "rim", "start_angle"). Throws std::invalid_argument
/// naming the patch's accepted names when it names none, or when there is no such patch.
PatchEdge resolve_patch_edge(const ShellMesh& mesh, const std::string& patch, std::string_view text);

/// Nodes with |(x - point) . n| <= tol, n = normal / |normal|.
NodeSet nodes_on_plane(const ShellMesh& mesh, const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
                       double tol = kAutoTolerance);
/// Nodes with lo - tol <= x <= hi + tol componentwise.
NodeSet nodes_in_box(const ShellMesh& mesh, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                     double tol = kAutoTolerance);
/// Nodes with |x - center| <= radius + tol.
NodeSet nodes_in_sphere(const ShellMesh& mesh, const Eigen::Vector3d& center, double radius,
                        double tol = kAutoTolerance);
/// The single node closest to `point` (lowest id on a tie); empty only for an empty mesh.
NodeSet nearest_node(const ShellMesh& mesh, const Eigen::Vector3d& point);
/// Nodes every quad of which lies toward `side` from the node: (centroid - x) . side > 0 for each
/// quad the node belongs to. Coincident nodes on the two lips of a slit belong to quads on opposite
/// sides, so this is how a selection tells them apart (an interior node has quads on both sides and
/// is never facing). Throws std::invalid_argument for a zero or non-finite `side`.
NodeSet nodes_facing(const ShellMesh& mesh, const Eigen::Vector3d& side);
/// Grid nodes of patch `patch` on `edge`. Throws std::invalid_argument when there is no such
/// patch or it has no parametric grid (imported meshes), naming the patches that exist.
NodeSet patch_edge_nodes(const ShellMesh& mesh, const std::string& patch, PatchEdge edge);
/// All nodes of a patch (structured or not).
NodeSet patch_nodes(const ShellMesh& mesh, const std::string& patch);

NodeSet set_union(const NodeSet& a, const NodeSet& b);
NodeSet set_intersection(const NodeSet& a, const NodeSet& b);
NodeSet set_difference(const NodeSet& a, const NodeSet& b);

/// A node-set description as a scene stores it: a predicate or a boolean combination.
class NodeSelector {
 public:
  enum class Kind { all, ids, plane, box, sphere, nearest, patch, patch_edge, union_of, intersection_of, difference, facing };

  static NodeSelector all();
  static NodeSelector ids(std::vector<int> ids);
  static NodeSelector plane(const Eigen::Vector3d& point, const Eigen::Vector3d& normal, double tol = kAutoTolerance);
  static NodeSelector box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double tol = kAutoTolerance);
  static NodeSelector sphere(const Eigen::Vector3d& center, double radius, double tol = kAutoTolerance);
  static NodeSelector nearest(const Eigen::Vector3d& point);
  static NodeSelector patch(const std::string& name);
  static NodeSelector patch_edge(const std::string& name, PatchEdge edge);
  static NodeSelector union_of(std::vector<NodeSelector> parts);
  static NodeSelector intersection_of(std::vector<NodeSelector> parts);
  /// Nodes of a that are not in b.
  static NodeSelector difference(NodeSelector a, NodeSelector b);
  /// The nodes of `base` that are facing `side` (nodes_facing); a nearest `base` takes the nearest
  /// of the facing nodes, so one lip of a slit can be picked by a point on the seam.
  static NodeSelector facing(NodeSelector base, const Eigen::Vector3d& side);

  Kind kind() const { return kind_; }
  /// The selected nodes (may throw std::invalid_argument for an unknown patch or a node id
  /// outside the mesh: those are errors in the request, not empty results).
  NodeSet select(const ShellMesh& mesh) const;
  /// The request in words, e.g. "nodes within 0.001 of the plane through (0, 0, 0) with
  /// normal (1, 0, 0)"; "auto" stands for kAutoTolerance.
  std::string describe() const;

 private:
  Kind kind_ = Kind::all;
  Eigen::Vector3d a_ = Eigen::Vector3d::Zero(), b_ = Eigen::Vector3d::Zero();
  double value_ = 0.0, tol_ = kAutoTolerance;
  std::string name_;
  PatchEdge edge_ = PatchEdge::u_min;
  std::vector<int> ids_;
  std::vector<NodeSelector> children_;
};

/// "node set '<set_name>' is empty: <describe()>; the mesh (<n> nodes) spans x in [..], ...".
std::string empty_selection_message(const std::string& set_name, const NodeSelector& selector,
                                    const ShellMesh& mesh);

}  // namespace ff::mesh
