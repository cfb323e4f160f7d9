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

/// The structured nu x nv patch of `map` (nodes uniformly spaced in u and v).
ShellMesh parametric_patch(const std::string& name, const std::string& description, int nu, int nv,
                           const SurfaceMap& map);

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
};
ShellMesh cylindrical_patch(const CylinderPatch& spec, int n_phi, int n_axial, const std::string& name = "cylinder");

/// Sphere patch: center + R*(sin(theta)cos(phi) r0 + sin(theta)sin(phi) (pole x r0) +
/// cos(theta) pole), polar angle theta in [theta0, theta1] measured from the pole, azimuth phi
/// in [phi0, phi1]. u = theta (n_theta elements), v = phi (n_phi elements). The patch must not
/// touch a pole (0 < theta0 < theta1 < pi): quads there would collapse to triangles.
/// Normal: radial, outward unless !outward.
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
};
ShellMesh annular_sector(const AnnularSector& spec, int n_r, int n_phi, const std::string& name = "annulus");

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
// The shell examples of Zhang, Liu, Zhang & Liu (2022, seeds/000) and their sources
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
/// moment at x = 12), y in [0, 1]; patch "strip", u along x. Seed mesh: 20 x 2.
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
/// u = phi (n_phi), v = z (n_axial). Normal outward. Seed: "24 x 16".
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
/// (seed 000 §5.5 after Simo, Fox & Rifai 1990): two strips of width 30 whose CENTRE LINES are
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
