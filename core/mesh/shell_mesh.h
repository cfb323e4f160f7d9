#pragma once
/// \file shell_mesh.h
/// The reference (undeformed) mid-surface mesh of a shell: nodes, 4-node quads, directors and
/// initial nodal frames. Plain value type; everything is in the world frame W and in the
/// length unit of the scene. Generators (generators.h) and the assimp importer
/// (app/io/mesh_import.h) produce it; the shell element and the Model consume it.
///
/// Conventions (see also core/mesh/README.md):
/// - quads[q] = {a, b, c, d} runs counter-clockwise about the director: the geometric normal
///   (x_c - x_a) x (x_d - x_b) points to the same side as the corner directors.
/// - normals[I] is the unit director of node I. Analytic generators store the exact surface
///   normal; imported meshes store the area-weighted average of the adjacent quad normals.
/// - corner_normals[q][k] is the director that quad q uses at its corner k. It equals
///   normals[quads[q][k]] everywhere except at fold nodes.
/// - Fold nodes (fold[I] != 0) sit on an edge where patches meet at a kink (e.g. a 90 deg fold).
///   There the director is not unique: normals[I] is the normal of the first patch that
///   contributed the node, and each quad keeps its own director in corner_normals. The element
///   code must give fold nodes 6 DoF (drilling included) and rotate every corner director with
///   the node rotation: d_qk = R_I * R0_I^T * corner_normals[q][k].
/// - frames[I] = R0_I = [e1 e2 e3] maps node-frame components to W; e3 = normals[I],
///   e1 = the frame reference direction projected onto the tangent plane (falls back to the
///   global axis least aligned with the normal when the reference is nearly parallel to it),
///   e2 = e3 x e1.

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ff::mesh {

/// A structured (parametric) piece of the mesh: a (nu+1) x (nv+1) node grid.
struct Patch {
  std::string name;         ///< e.g. "plate", "leg1"; unique within a mesh
  std::string description;  ///< geometry in words, e.g. "cylinder R=4.953 ..."
  int nu = 0;               ///< elements along the first parameter u (0: not structured)
  int nv = 0;               ///< elements along the second parameter v
  std::vector<int> grid;    ///< node ids, grid[j*(nu+1)+i] at (u_i, v_j); empty if unstructured
  int first_quad = 0;       ///< quads [first_quad, first_quad+quad_count) belong to this patch
  int quad_count = 0;
  /// Readable names of the edges u=0, u=1, v=0, v=1 given by the generator (e.g. "inner",
  /// "rim", "start_angle"); "" where it gives none. Scenes select edges by these or by "u=0".
  std::array<std::string, 4> edge_names;

  bool structured() const { return nu > 0 && nv > 0 && !grid.empty(); }
  int node(int i, int j) const { return grid[static_cast<std::size_t>(j) * (nu + 1) + i]; }
};

/// A named set the mesh file (or CAD model) defines: a Gmsh physical group, an Abaqus *NSET or
/// *ELSET. Scenes select it by name (select = "group"). Node and quad ids are those of the mesh
/// it belongs to, ascending, without repeats.
struct MeshGroup {
  std::string name;
  int dimension = 0;        ///< 0 points, 1 curves (edges), 2 surfaces (quads), as the file states it
  std::vector<int> nodes;   ///< every node of the group (for a surface group: its quads' corners)
  std::vector<int> quads;   ///< dimension 2: the group's quads; empty otherwise
  std::string origin;       ///< where it came from in words, e.g. "Gmsh physical curve 3 in roof.msh"
};

struct ShellMesh {
  std::vector<Eigen::Vector3d> points;                        ///< p_WI, reference positions
  std::vector<std::array<int, 4>> quads;                      ///< CCW about the director
  std::vector<Eigen::Vector3d> normals;                       ///< unit director per node
  std::vector<std::array<Eigen::Vector3d, 4>> corner_normals; ///< director per quad corner
  std::vector<Eigen::Matrix3d> frames;                        ///< R0_I = [e1 e2 e3] per node
  std::vector<std::uint8_t> fold;                             ///< 1 at fold nodes (6 DoF)
  std::vector<int> quad_patch;                                ///< patch index per quad
  std::vector<Patch> patches;
  std::vector<MeshGroup> groups;                               ///< named sets from the mesh file
  Eigen::Vector3d frame_reference = Eigen::Vector3d::UnitX();  ///< reference for e1

  int node_count() const { return static_cast<int>(points.size()); }
  int quad_count() const { return static_cast<int>(quads.size()); }
  int fold_count() const;
  /// Index of the patch called `name`, or -1.
  int find_patch(const std::string& name) const;
  /// Index of the group called `name`, or -1.
  int find_group(const std::string& name) const;
};

// ---- geometry of one quad (bilinear interpolation of its four corners) ----

/// Area of the bilinear surface of quad q (2x2 Gauss integration of |x_xi x x_eta|).
double quad_area(const ShellMesh& mesh, int q);
/// Unit geometric normal of quad q at its centre, (x_c - x_a) x (x_d - x_b) normalized.
Eigen::Vector3d quad_normal(const ShellMesh& mesh, int q);
/// Sum of quad_area over all quads.
double total_area(const ShellMesh& mesh);
/// Shortest quad edge length (0 for a mesh without quads).
double min_edge_length(const ShellMesh& mesh);
/// Longest quad edge length.
double max_edge_length(const ShellMesh& mesh);
/// Mean length of the mesh's edges (each edge once, however many quads share it); 0 without quads.
/// With a group: of the edges with at least one end among the group's nodes (the size the mesh
/// reached there), and *edges says how many.
double mean_edge_length(const ShellMesh& mesh, const MeshGroup* group = nullptr, int* edges = nullptr);

// ---- derived data ----

/// normals[I] = normalized sum over adjacent quads of the quad's vector area; corner_normals
/// are set to the node normals and fold flags cleared. For imported (faceted) meshes.
void compute_area_weighted_normals(ShellMesh& mesh);
/// Fills corner_normals from the node normals (no folds).
void corner_normals_from_nodes(ShellMesh& mesh);
/// One initial frame for a unit normal n: e3 = n, e1 = reference projected onto the tangent
/// plane (or the fallback axis when |reference x n| < 1e-3 |reference|), e2 = e3 x e1.
Eigen::Matrix3d frame_from_normal(const Eigen::Vector3d& n, const Eigen::Vector3d& reference);
/// frames[I] = frame_from_normal(normals[I], reference); stores reference in frame_reference.
void compute_frames(ShellMesh& mesh, const Eigen::Vector3d& reference = Eigen::Vector3d::UnitX());
/// Resizes fold / quad_patch and adds a single unstructured patch if there is none, so a mesh
/// built from points + quads + normals satisfies the layout validate() expects.
void complete_layout(ShellMesh& mesh, const std::string& patch_name = "surface");

struct OrientationOptions {
  /// Accept edges of three or more quads (a T where a stiffener meets a panel, a cross): at such an
  /// edge two quads whose surfaces continue each other (turning less than continuation_angle_deg
  /// across it; the smallest turns paired first) are oriented as across an ordinary edge, and a
  /// quad left unpaired starts a piece of its own. false: such an edge is refused.
  bool junction_edges = false;
  double continuation_angle_deg = 30.0;
};

/// What orient_consistently did.
struct OrientationReport {
  int pieces = 0;              ///< sets of quads whose orientations depend on each other
  int flipped = 0;             ///< quads turned
  double area = 0.0;           ///< the whole mesh's area
  double flipped_area = 0.0;   ///< the turned quads' area
  /// the largest share of one piece's area that was turned (at most one half: the majority stays)
  double largest_turned_share = 0.0;
};

/// Flips quads so that every interior edge is traversed in opposite directions by its two
/// quads. Within each piece of quads joined that way, the side the larger area was already wound
/// to stays (ties: the side of the piece's first quad), so one reversed element cannot turn the
/// rest. Returns false and explains in *why when the surface is not orientable or has an edge of
/// three or more quads that options do not accept. Does not touch normals (corner normals are
/// swapped with their corners).
bool orient_consistently(ShellMesh& mesh, std::string* why = nullptr, const OrientationOptions& options = {},
                         OrientationReport* report = nullptr);

// ---- validation ----

enum class IssueKind {
  layout,                    ///< array sizes disagree, index out of range, repeated corner
  non_finite,                ///< NaN/inf coordinate or normal
  bad_normal,                ///< normal not of unit length
  degenerate_quad,           ///< (near) zero area or (near) zero-length edge
  inverted_quad,             ///< a corner turns clockwise about the corner director
  normal_mismatch,           ///< quad geometric normal opposes a corner director
  unused_node,               ///< node referenced by no quad
  duplicate_quad,            ///< two quads on the same four nodes
  inconsistent_orientation,  ///< an interior edge traversed in the same direction twice
  non_manifold_edge,         ///< an edge shared by more than two quads
  bad_frame,                 ///< frame not orthonormal / e3 != normal
};

const char* to_string(IssueKind kind);

struct MeshIssue {
  IssueKind kind;
  std::string message;  ///< complete sentence naming the quad/node/edge
  int quad = -1;
  int node = -1;
};

struct MeshCheck {
  std::vector<MeshIssue> issues;
  bool ok() const { return issues.empty(); }
  int count(IssueKind kind) const;
  /// Up to max_lines messages, one per line, then "... and N more".
  std::string summary(int max_lines = 10) const;
};

/// Checks the invariants documented above. Relative tolerances are scaled by the longest edge.
MeshCheck validate(const ShellMesh& mesh);

}  // namespace ff::mesh
