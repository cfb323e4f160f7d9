#pragma once
/// \file imported_surface.h
/// A surface mesh as a file or a mesher hands it over (nodes, 3- and 4-node elements, the surface
/// entity of each element, named groups), and its conversion into a ShellMesh. The readers
/// (app/io: Gmsh for .msh and CAD, the Abaqus .inp reader, assimp for OBJ/PLY/STL triangles)
/// only fill an ImportedSurface; everything a shell needs beyond that is decided here, once:
/// - triangles are refused, or split into quads (each triangle into three through its centroid
///   and edge midpoints; in a mesh that also has quads, every quad into four as well, so the
///   mesh stays conforming): imported_surface.md (S1)-(S3);
/// - orientation is made consistent, each piece keeping the side most of its area was wound to;
///   an edge of three or more elements (a T) joins the elements that continue each other and is
///   a fold;
/// - directors: the exact surface normals when the mesher gives them (CAD), else averaged per
///   smooth piece (elements joined across edges where they turn less than the crease angle);
///   a node where pieces with different normals meet is a fold node (6 DoF): (S4)-(S5);
/// - named groups carried to the shell mesh's node and quad numbers (new midpoint nodes
///   included where the group holds the edge they split): (S6).

#include <Eigen/Dense>
#include <array>
#include <string>
#include <vector>

#include "core/mesh/shell_mesh.h"

namespace ff::mesh {

struct ImportedElement {
  std::array<int, 4> nodes{-1, -1, -1, -1};  ///< indices into ImportedSurface::points; nodes[3] = -1: a triangle
  int entity = 0;                            ///< the surface it lies on (CAD face, Gmsh entity, element set)
  std::string where;                         ///< how an error names it, e.g. "element 12 (line 40)"
  bool triangle() const { return nodes[3] < 0; }
};

struct ImportedGroup {
  std::string name;
  int dimension = 0;                        ///< 0 points, 1 curves, 2 surfaces
  std::vector<int> nodes;                   ///< indices into ImportedSurface::points
  std::vector<int> elements;                ///< dimension 2: indices into ImportedSurface::elements
  std::vector<std::array<int, 2>> segments; ///< dimension 1: the curve's edges when the file has them
  std::string origin;                       ///< e.g. "Gmsh physical curve 3", "*NSET at line 40"
};

struct ImportedSurface {
  std::string format;  ///< e.g. "Gmsh MSH 4.1", "STEP meshed by Gmsh", "Abaqus INP"
  std::string file;    ///< the file name, for descriptions and messages
  std::vector<Eigen::Vector3d> points;
  std::vector<ImportedElement> elements;
  /// optional: the exact surface normal at every element corner (a CAD surface's own normal);
  /// empty: directors are averaged from the elements
  std::vector<std::array<Eigen::Vector3d, 4>> corner_normals;
  std::vector<ImportedGroup> groups;
  std::vector<std::string> notes;  ///< what the reader or mesher did, for the part's description
};

enum class TriangleHandling { refuse, split };

struct SurfaceConversionOptions {
  TriangleHandling triangles = TriangleHandling::refuse;
  /// averaged directors: elements that turn more than this [deg] across a shared edge belong to
  /// different smooth pieces (a crease), and the nodes between them are fold nodes
  double crease_angle_deg = 30.0;
  Eigen::Vector3d frame_reference = Eigen::Vector3d::UnitX();
  std::string patch_name = "surface";
  /// keep only the elements of this surface group (dimension 2); "" = every element
  std::string only_group;
};

/// A turned share from this on is said loudly (a warning, not only a note): the side a piece's
/// directors face was then decided by a majority of at most three to one.
constexpr double kLoudTurnedShare = 0.25;

/// What the conversion did, for `check` and the summary.
struct SurfaceConversionReport {
  int quads_in = 0, triangles_in = 0;  ///< elements read
  int quads_out = 0;                   ///< shell quads made
  bool triangles_split = false;        ///< each triangle became three quads
  bool quads_split = false;            ///< ... and each quad four (a mixed mesh)
  int flipped = 0;                     ///< quads turned to agree with their neighbours
  /// the largest share of one piece's area that was turned (a piece keeps the side most of its
  /// area was wound to, so at most one half)
  double turned_share = 0.0;
  int junction_edges = 0;              ///< mesh edges where three or more quads meet (a T)
  int folds = 0;                       ///< fold nodes (6 DoF)
  bool exact_normals = false;          ///< directors from the surface's own normals
  /// one line in words, e.g. "412 triangles split into 1236 quads; 0 flipped; 3 fold nodes"
  std::string summary() const;
  /// a sentence for the console when a piece's side was decided by a slim majority
  /// (turned_share >= kLoudTurnedShare), else ""
  std::string turned_warning() const;
};



/// Where a surface mesh touches itself without being joined: boundary nodes (on an edge of one
/// quad only) that lie on a quad they are not a corner of (at one of its nodes, on an edge or
/// inside it), within 1e-6 x the shortest element edge (a [[junction]]'s default tolerance).
/// Faces side by side, each with its own row of nodes along the common line, a stiffener whose
/// foot stands on a face without sharing its nodes, a slit. On a curved face a foot is found
/// only where it meets nodes (elsewhere the flat quads lie off the curved surface).
struct UnjoinedContacts {
  int nodes = 0;        ///< boundary nodes touching a quad they do not belong to
  int first_node = -1;  ///< the first of them (node number of the mesh)
  int first_quad = -1;  ///< and the quad it touches
};
UnjoinedContacts find_unjoined_contacts(const ShellMesh& mesh);

/// Builds `out` from `in`. Returns false with a complete sentence in *error (naming the file, the
/// element or group, and what to do) when: there are no elements; triangles are present and
/// options.triangles is refuse; an element names a node that does not exist or repeats one; a
/// group is empty or names nothing; only_group is not a surface group of the file; the surface
/// is not orientable; or validate() fails (edges of three or more elements excepted).
/// `out` is untouched on failure.
bool shell_mesh_from_surface(const ImportedSurface& in, const SurfaceConversionOptions& options, ShellMesh& out,
                             std::string* error, SurfaceConversionReport* report = nullptr);

}  // namespace ff::mesh
