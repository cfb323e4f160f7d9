#pragma once
/// \file generators.h
/// Structured quad meshes of analytic surfaces with exact directors, assemblies of patches
/// sharing edges (coincident nodes merged, folds flagged), and the geometries of the shell
/// benchmarks. Lengths in the scene's unit, angles in radians. Every function throws
/// std::invalid_argument with a plain explanation when its arguments describe no valid mesh.
///
/// Numbering of one patch with nu x nv elements: node (i, j) at parameters (u_i, v_j) is
/// grid[j*(nu+1) + i]; quad (i, j) has corners (i,j), (i+1,j), (i+1,j+1), (i,j+1), or the
/// reverse when x_u x x_v points against the requested normal, so quads always run
/// counter-clockwise about the director (shell_mesh.h). Node ids equal grid ids for a single
/// patch without coincident nodes (a closed 360 degree cylinder merges its seam).

#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include "core/mesh/shell_mesh.h"

namespace ff::mesh {

/// A point of a parametric surface with its unit normal.
struct SurfacePoint {
  Eigen::Vector3d x;  ///< position p_W
  Eigen::Vector3d n;  ///< unit normal (the director the mesh will store)
};
/// Surface map over the unit square (u, v) in [0, 1]^2.
using SurfaceMap = std::function<SurfacePoint(double u, double v)>;

/// The structured nu x nv patch of `map` (nodes uniformly spaced in u and v). A closed patch
/// (360 degree cylinder or annulus) merges its coincident seam nodes unless !merge_seam, which
/// keeps the two lips of the seam as separate nodes (a slit).
ShellMesh parametric_patch(const std::string& name, const std::string& description, int nu, int nv,
                           const SurfaceMap& map, bool merge_seam = true);

/// Rectangle origin + s*e_a + t*e_b, s in [0, a], t in [0, b]; normal e_a x e_b.
/// u runs along e_a (n_a elements), v along e_b (n_b elements).
struct RectangularPlate {
  double a = 1.0;                                     ///< length along e_a
  double b = 1.0;                                     ///< width along e_b
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();   ///< corner (s, t) = (0, 0)
  Eigen::Vector3d e_a = Eigen::Vector3d::UnitX();     ///< unit, orthogonal to e_b
  Eigen::Vector3d e_b = Eigen::Vector3d::UnitY();
};
ShellMesh rectangular_plate(const RectangularPlate& spec, int n_a, int n_b, const std::string& name = "plate");
/// Plate of length a along x and width b along y in z = 0, normal +z.
ShellMesh rectangular_plate(double a, double b, int n_a, int n_b, const std::string& name = "plate");
/// Plate [x0, x0 + a] x [y0, y0 + b] in the plane z = z0 (origin = (x0, y0, z0)), normal +z, with
/// the edge names "x_min" (u=0), "x_max" (u=1), "y_min" (v=0), "y_max" (v=1).
ShellMesh axis_aligned_plate(double a, double b, const Eigen::Vector3d& origin, int n_a, int n_b,
                             const std::string& name = "plate");

/// Cylinder patch: origin + s*axis + R*(cos(phi)*r0 + sin(phi)*(axis x r0)),
/// phi in [phi0, phi1] (right-handed about axis), s in [s0, s1]. u = phi (n_phi elements),
/// v = s (n_axial elements). Normal: radial, outward (away from the axis) unless !outward.
struct CylinderPatch {
  double radius = 1.0;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();   ///< point of the axis at s = 0
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();    ///< axis direction (normalized here)
  Eigen::Vector3d radial0 = Eigen::Vector3d::UnitX(); ///< direction of phi = 0 (orthogonalized)
  double phi0 = 0.0, phi1 = std::numbers::pi / 2;     ///< |phi1 - phi0| <= 2 pi
  double s0 = 0.0, s1 = 1.0;                          ///< axial range
  bool outward = true;
  bool slit = false;  ///< a 360 degree cylinder keeps its seam as two lips (separate nodes)
};
/// Edge names: "start_angle" (u=0), "end_angle" (u=1), "bottom" (v=0, s = s0), "top" (v=1).
ShellMesh cylindrical_patch(const CylinderPatch& spec, int n_phi, int n_axial, const std::string& name = "cylinder");

/// Sphere patch: center + R*(sin(theta)cos(phi) r0 + sin(theta)sin(phi) (pole x r0) +
/// cos(theta) pole), polar angle theta in [theta0, theta1] measured from the pole, azimuth phi
/// in [phi0, phi1]. u = theta (n_theta elements), v = phi (n_phi elements). The patch must not
/// touch a pole (0 < theta0 < theta1 < pi): quads there would collapse to triangles.
/// Normal: radial, outward unless !outward. Edge names: "hole" (u=0), "rim" (u=1), "start_angle"
/// (v=0), "end_angle" (v=1).
struct SpherePatch {
  double radius = 1.0;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d pole = Eigen::Vector3d::UnitZ();    ///< theta = 0 direction
  Eigen::Vector3d radial0 = Eigen::Vector3d::UnitX(); ///< phi = 0 direction (orthogonalized)
  double theta0 = std::numbers::pi / 10, theta1 = std::numbers::pi / 2;
  double phi0 = 0.0, phi1 = std::numbers::pi / 2;
  bool outward = true;
};
ShellMesh spherical_patch(const SpherePatch& spec, int n_theta, int n_phi, const std::string& name = "sphere");

/// Flat annular sector: center + r*(cos(phi) r0 + sin(phi) (axis x r0)), r in [r0, r1] with
/// r0 > 0, phi in [phi0, phi1]. u = r (n_r elements), v = phi (n_phi elements). Normal: axis.
struct AnnularSector {
  double r_inner = 0.5, r_outer = 1.0;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();    ///< plane normal
  Eigen::Vector3d radial0 = Eigen::Vector3d::UnitX(); ///< phi = 0 direction (orthogonalized)
  double phi0 = 0.0, phi1 = std::numbers::pi / 2;
  bool slit = false;  ///< a 360 degree annulus keeps its seam as two lips (separate nodes)
};
/// Edge names: "inner" (u=0), "outer" (u=1), "start_angle" (v=0), "end_angle" (v=1).
ShellMesh annular_sector(const AnnularSector& spec, int n_r, int n_phi, const std::string& name = "annulus");

/// Surface of a polar map: the point at normalized radius rho in [0, 1] (0 = the pole or centre,
/// 1 = the rim) and azimuth phi [rad].
using PolarMap = std::function<SurfacePoint(double rho, double phi)>;

/// A pole-free quad mesh of the polar region rho <= 1, phi in [phi0, phi1] (an "O-grid", see
/// README.md §O-grid): in the flat (rho cos, rho sin) plane a core rectangle of half-width a
/// around the pole, patch "<name>_core", and a ring patch "<name>" between the rectangle's
/// outline and the rim, u from the outline (u=0, edge "core") to the rim (u=1, edge "rim_name"),
/// v along the azimuth; both are mapped through `map`. |phi1 - phi0| must be 90, 180 or 360
/// degrees (the core is a quarter, half or whole square) and n_rim a multiple of 2, 4 or 8
/// respectively; n_ring elements run from the core to the rim. a = m / (m + n_ring) with m =
/// the core's elements per half-side, clamped to [0.25, 0.6], so core and ring quads match.
ShellMesh polar_o_grid(const std::string& name, const std::string& description, const std::string& rim_name,
                       double phi0, double phi1, int n_ring, int n_rim, const PolarMap& map);

/// An annular sector when r_inner > 0, a disk or disk sector when r_inner = 0 (polar_o_grid:
/// patches "<name>_core" and "<name>", rim edge "outer"; the phi span must then be 90, 180 or
/// 360 degrees). n_r = elements across (ring), n_phi = elements along the rim.
ShellMesh annulus(const AnnularSector& spec, int n_r, int n_phi, const std::string& name = "annulus");

/// spherical_patch when theta0 > 0; a cap closed at the pole when theta0 = 0 (polar_o_grid with
/// rho = theta / theta1: patches "<name>_core" and "<name>", rim edge "rim"; the phi span must be
/// 90, 180 or 360 degrees). theta1 < pi.
ShellMesh spherical_cap(const SpherePatch& spec, int n_theta, int n_phi, const std::string& name = "cap");

/// Two plates joined along a straight fold line: "leg1" origin + s e_x + t e_y, s in [0, a],
/// t in [0, width], normal +z; "leg2" origin + a e_x + s d + t e_y, s in [0, b], with
/// d = (cos alpha, 0, sin alpha): alpha = fold_angle turns leg2 up from leg1's continuation
/// (0 = flat, 90 deg = upright along +z). Normal of leg2 d x e_y, continuous over the fold. The
/// merged fold nodes are flagged (for alpha != 0) and keep leg1's normal. Edge names: leg1 "end"
/// (u=0, x = origin x), "fold" (u=1); leg2 "fold" (u=0), "end" (u=1); both "y_min" (v=0), "y_max".
struct FoldedPlate {
  double a = 1.0, b = 1.0, width = 1.0;
  double fold_angle = std::numbers::pi / 2;  ///< |fold_angle| < pi
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
};
ShellMesh folded_plate(const FoldedPlate& spec, int n_a, int n_b, int n_width);

/// A flat L-shaped plate in the plane z = origin z: two strips of the same width whose centre
/// lines are leg1 (along +x) and leg2 (along +y) long, measured from each free end to the centre
/// of the width x width corner square. With origin o: "arm1" x in o.x + [0, leg1 - w/2],
/// y in o.y + [0, w]; "corner" x in o.x + [leg1 - w/2, leg1 + w/2], y in o.y + [0, w]; "arm2"
/// x in o.x + [leg1 - w/2, leg1 + w/2], y in o.y + [w, leg2 + w/2]. Normal +z. Arms have
/// n_arm x n_width elements, the corner n_width x n_width. Edge names: arms "end" (free end),
/// "corner" (joint), "outer" (y = o.y for arm1, x = o.x + leg1 + w/2 for arm2), "inner";
/// corner "arm1", "arm2", "outer1" (y = o.y), "outer2" (x = o.x + leg1 + w/2).
struct LPlate {
  double leg1 = 240.0, leg2 = 240.0, width = 30.0;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
};
ShellMesh l_plate(const LPlate& spec, int n_arm, int n_width);

// ---- node counts, before building ---------------------------------------------------------
// What the generators above will build, counted from the element counts alone, so that a mesh
// that cannot fit in memory is refused before it is built (core/scene's memory guard). Each is
// the generator's node_count() exactly (tests/unit/test_mesh_generators.cpp compares them over
// ranges of counts, angles and options).

/// A structured nu x nv patch (parametric_patch); `closed_u` / `closed_v`: its seam in that
/// direction is merged (a 360 degree cylinder, annulus or sphere), one column of nodes fewer.
long long patch_node_count(int nu, int nv, bool closed_u = false, bool closed_v = false);
/// polar_o_grid with n_ring x n_rim over 90 * quadrants degrees (1, 2 or 4; n_rim a multiple of
/// 2 * quadrants): the core square and the ring, sharing the core's outline.
long long polar_o_grid_node_count(int n_ring, int n_rim, int quadrants);
/// l_plate: two arms of n_arm x n_width and the n_width x n_width corner, sharing two edges.
long long l_plate_node_count(int n_arm, int n_width);
/// folded_plate: legs of n_a x n_width and n_b x n_width sharing the fold line.
long long folded_plate_node_count(int n_a, int n_b, int n_width);

/// How assemble() joins patches.
struct AssemblyOptions {
  /// nodes closer than merge_tolerance * (shortest edge of all parts) become one node
  double merge_tolerance = 1e-6;
  /// merged nodes whose directors differ by more than this angle [rad] are fold nodes
  double fold_angle = 1e-6;
  Eigen::Vector3d frame_reference = Eigen::Vector3d::UnitX();
};

/// Concatenates the parts (in order) and merges coincident nodes. The first occurrence of a
/// node keeps its id order and its director; a merged node whose directors differ by more than
/// fold_angle gets fold = 1, and every quad keeps its own director in corner_normals (see
/// shell_mesh.h for what the element code must do there). Patches keep their grids (remapped
/// to merged ids); a repeated patch name gets a suffix "_2", "_3", ... Frames are recomputed
/// with options.frame_reference.
ShellMesh assemble(const std::vector<ShellMesh>& parts, const AssemblyOptions& options = {});

// ---- benchmark geometries ------------------------------------------------------------------
// The shell examples of the shell paper (Zhang, Liu, Zhang & Liu 2022) and their sources
// (Sze, Liu & Lo 2004, "Popular benchmark problems for geometric nonlinear analysis of
// shells", Finite Elem. Anal. Des. 40:1551-1569; Simo, Fox & Rifai 1990, CMAME 79:21-70).
// Each records its symmetry planes and load points in its comment; core/mesh/README.md has the
// full table with sources.
namespace bench {
inline constexpr double kStripLength = 12.0, kStripWidth = 1.0;
inline constexpr double kHemisphereRadius = 10.0;
inline constexpr double kHemisphereHole = 18.0 * std::numbers::pi / 180.0;  ///< polar half-angle
inline constexpr double kCylinderLength = 10.35, kCylinderRadius = 4.953;
inline constexpr double kRoofRadius = 2540.0;
inline constexpr double kRoofHalfLength = 254.0;  ///< "L" of Sze et al.: the roof is 2L = 508 long
inline constexpr double kRoofHalfAngle = 0.1;     ///< "theta": the roof spans 2 theta = 0.2 rad
inline constexpr double kLPlateLeg = 240.0, kLPlateWidth = 30.0;  // centre-line leg, strip width
}  // namespace bench

/// Example 1, end-moment roll-up: strip 12 x 1 in z = 0, x in [0, 12] (clamped at x = 0,
/// moment at x = 12), y in [0, 1]; patch "strip", u along x. The shell paper's mesh: 20 x 2.
ShellMesh cantilever_strip(int n_length = 20, int n_width = 2);

/// Example 2, hemisphere R = 10 with an 18 deg polar hole, quarter model: theta in
/// [18 deg, 90 deg] from +z, phi in [0, 90 deg] from +x to +y; equator at z = 0. Symmetry
/// planes y = 0 (edge v=0) and x = 0 (edge v=1); load points A = (10, 0, 0) and B = (0, 10, 0).
/// Patch "hemisphere", u = theta, v = phi. Normal outward.
ShellMesh hemisphere_quarter(int n_theta, int n_phi);

/// Example 3, pull-out of an open-ended cylinder, 1/8 model: axis z, R = 4.953, full length
/// 10.35; the octant z in [0, 10.35/2] (z = 0 is the mid-length plane), phi in [0, 90 deg] from
/// +x to +y. Symmetry planes z = 0 (edge v=0), y = 0 (edge u=0), x = 0 (edge u=1); free end
/// z = 5.175 (edge v=1); the pull-out load acts at (R, 0, 0) along +x. Patch "cylinder",
/// u = phi (n_phi), v = z (n_axial). Normal outward. The shell paper: "24 x 16".
ShellMesh open_cylinder_octant(int n_phi, int n_axial);

/// Example 4, hinged cylindrical roof (Sze et al. 2004: R = 2540, L = 254, theta = 0.1 rad; the
/// whole roof is 2L = 508 long and spans 2 theta = 0.2 rad), quarter model: axis along x,
/// x in [0, 254]; crown line y = 0, z = 0 (the centre of curvature is (x, 0, -2540)); arc from
/// the crown to the hinged straight edge at y = 2540 sin(0.1) = 253.58. Symmetry planes x = 0
/// and y = 0, free curved edge x = 254, central load at (0, 0, 0) (a quarter of it on the
/// model). Patch "roof": u = phi running from the hinged edge (u=0) to the crown (u=1),
/// v = x (v=0 at x = 0). Normal outward (+z at the crown).
ShellMesh hinged_roof_quarter(int n_arc, int n_axial);

/// Example 5, the right-angle frame of Argyris et al. (1979) modelled as a FLAT L-shaped plate
/// (the shell paper §5.5 after Simo, Fox & Rifai 1990): two strips of width 30 whose CENTRE LINES are
/// 240 long, measured from the clamped end / loaded end to the centre of the 30 x 30 corner
/// square, as in the beam data of the benchmark (L = 240, section 30 x 0.6). The L lies in the
/// plate's plane z = 0, so there is no fold. Patches "arm1" (x in [0, 225], y in [0, 30], clamped
/// end x = 0), "corner" ([225, 255] x [0, 30]) and "arm2" (x in [225, 255], y in [30, 255],
/// loaded end y = 255 with its mid-point at (240, 255, 0)). Arms have n_arm x n_width elements,
/// the corner n_width x n_width. Normal +z.
ShellMesh l_plate_simo_fox_rifai(int n_arm, int n_width);

/// Two rectangular plates meeting at a 90 deg fold (a right-angle bent strip): "leg1" in
/// z = 0, x in [0, a], y in [0, width], normal +z; "leg2" in the plane x = a, z in [0, b],
/// y in [0, width], normal -x (continuous with leg1 through the fold). The width + 1 nodes on
/// the fold line x = a, z = 0 are merged and flagged fold; they keep leg1's normal +z.
ShellMesh right_angle_folded_plate(double a, double b, double width, int n_a, int n_b, int n_width);

}  // namespace ff::mesh
