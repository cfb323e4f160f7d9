#include "core/scene/mesh_generator_keys.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "core/mesh/generators.h"

namespace ff::scene {

namespace {

using Vec3 = Eigen::Vector3d;

// The keys each generator reads besides part.generator; any other generator key given with it is
// an error (a dimension that would silently do nothing).
const std::map<std::string, std::vector<std::string>>& generator_keys() {
  static const std::map<std::string, std::vector<std::string>> keys = {
      {"rectangular_plate", {"n1", "n2", "origin", "length", "width"}},
      {"l_plate", {"n1", "n2", "origin", "length", "length2", "width"}},
      {"folded_plate", {"n1", "n2", "n3", "origin", "length", "length2", "width", "fold_angle"}},
      {"cylinder",
       {"n1", "n2", "origin", "axis", "reference", "radius", "length", "start_angle", "end_angle", "slit"}},
      {"cut_cylinder", {"n1", "n2", "origin", "radius", "length", "start_angle", "end_angle", "end_slope"}},
      {"annulus",
       {"n1", "n2", "origin", "axis", "reference", "radius", "inner_radius", "start_angle", "end_angle", "slit"}},
      {"spherical_cap",
       {"n1", "n2", "origin", "axis", "reference", "radius", "polar_start", "polar_end", "start_angle",
        "end_angle"}},
      {"file",
       {"file", "weld_tolerance", "triangles", "crease_angle", "group", "mesh_size", "local_size_groups",
        "local_sizes", "mesh_time_limit", "keep_faces_apart", "mesh_pattern"}},
  };
  return keys;
}
// the dimensions a generator cannot do without (no silent default)
const std::map<std::string, std::vector<std::string>>& required_keys() {
  static const std::map<std::string, std::vector<std::string>> keys = {
      {"rectangular_plate", {"length", "width"}},
      {"l_plate", {"length", "width"}},
      {"folded_plate", {"length", "length2", "width"}},
      {"cylinder", {"radius", "length"}},
      {"cut_cylinder", {"radius", "length"}},
      {"annulus", {"radius"}},
      {"spherical_cap", {"radius", "polar_end"}},
  };
  return keys;
}
// every key of the table that belongs to some generator
const std::vector<std::string> kDimensionKeys = {"n1",     "n2",          "n3",                     "origin",
                                                 "axis",   "reference",   "length",      "length2",   "width",
                                                 "radius", "inner_radius", "start_angle", "end_angle", "polar_start",
                                                 "polar_end", "fold_angle", "slit", "weld_tolerance", "end_slope",
                                                 "triangles", "crease_angle", "group", "mesh_size",
                                                 "local_size_groups", "local_sizes", "mesh_time_limit",
                                                 "keep_faces_apart", "mesh_pattern"};

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }  // exact for 90 -> pi/2

Vec3 vec(const std::vector<double>& v) { return Vec3(v[0], v[1], v[2]); }

void check_keys(const Document& d, std::size_t i, const std::string& gen) {
  const std::vector<std::string>& own = generator_keys().at(gen);
  std::string own_list;
  for (const std::string& k : own) own_list += (own_list.empty() ? "" : ", ") + k;
  for (const std::string& k : kDimensionKeys)
    if (d.present("part." + k, i) && std::find(own.begin(), own.end(), k) == own.end())
      throw SceneError({d.issue("part." + k, i, "part." + k + " does not belong to generator = \"" + gen + "\" (its keys: " +
                                                 (own_list.empty() ? std::string("part.file") : own_list) + ")")});
  if (gen != "file" && d.present("part.file", i))
    throw SceneError({d.issue("part.file", i, "part.file belongs to generator = \"file\"; generator = \"" + gen +
                                               "\" builds its own mesh")});
  const auto req = required_keys().find(gen);
  if (req != required_keys().end())
    for (const std::string& k : req->second)
      if (!d.present("part." + k, i))
        throw SceneError({d.issue("part.generator", i, "generator = \"" + gen + "\" needs part." + k + " (" +
                                                        (k == "polar_end" ? "the polar angle of the rim in degrees, e.g. 90 "
                                                                            "for a hemisphere"
                                                                          : "a dimension in the scene's length unit") +
                                                        ")")});
}

int count(const Document& d, std::size_t i, const char* key) { return static_cast<int>(d.integer(std::string("part.") + key, i)); }

std::string name_or(const Document& d, std::size_t i, const char* fallback) {
  const std::string& n = d.string("part.name", i);
  return n.empty() ? std::string(fallback) : n;
}

// azimuth range [start, end] in degrees, 0 < end - start <= 360; slit only on a full turn
std::pair<double, double> azimuth(const Document& d, std::size_t i, bool slit_allowed) {
  const double a0 = d.number("part.start_angle", i), a1 = d.number("part.end_angle", i);
  const double span = std::abs(a1 - a0);
  // a reversed range would be swept backwards: the edges named start_angle and end_angle (a
  // slit's two lips) would trade places silently
  if (a1 < a0)
    throw SceneError({d.issue(d.present("part.end_angle", i) ? "part.end_angle" : "part.start_angle", i,
                              "the azimuth range [start_angle, end_angle] = [" + d.value_text("part.start_angle", i) + ", " +
                                  d.value_text("part.end_angle", i) + "] deg runs backwards; end_angle must exceed "
                                  "start_angle (the surface is swept from start_angle towards end_angle, "
                                  "right-handed about part.axis)")});
  if (!(span > 0) || span > 360.0 * (1 + 1e-12))
    throw SceneError({d.issue(d.present("part.end_angle", i) ? "part.end_angle" : "part.start_angle", i,
                              "the azimuth range [start_angle, end_angle] = [" + d.value_text("part.start_angle", i) + ", " +
                                  d.value_text("part.end_angle", i) + "] deg must span more than 0 and at most 360 degrees")});
  if (slit_allowed && d.boolean("part.slit", i) && std::abs(span - 360.0) > 1e-9)
    throw SceneError({d.issue("part.slit", i, "a slit is the seam of a closed 360 degree surface kept open; this one spans " +
                                               d.value_text("part.end_angle", i) + " - " + d.value_text("part.start_angle", i) +
                                               " degrees, so its two straight edges are apart already")});
  return {radians(a0), radians(a1)};
}

// Lengths a generator takes: far from both ends of the double range, since the element forms
// products of three lengths (det J ~ L^2 h) and squared distances; 1e100 cubed is 1e300, still
// below the largest double (1.8e308), and 1e-100 cubed stays above the smallest normal one.
constexpr double kLargestLength = 1e100, kSmallestLength = 1e-100;
// An element whose sides differ by more than this factor is refused: its stiffness terms span the
// square of the ratio (1e8 of the 16 digits a double carries), and the ratios beyond it (a length
// or an angle range of 1e-12 beside unit ones) ended as "singular matrix" at run time.
constexpr double kLargestAspect = 1e4;
// Largest azimuth one element may span: at 180 degrees its corners lie in one plane with the
// axis (or the centre) and its directors lie in that plane, so the quad carries no shell; a
// full turn therefore needs at least 3 elements.
constexpr double kLargestElementAzimuth = 120.0;

std::string g(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

// every length key and the origin inside [kSmallestLength, kLargestLength]
void check_length_range(const Document& d, std::size_t i) {
  for (const char* k : {"length", "length2", "width", "radius", "inner_radius"}) {
    const std::string key = std::string("part.") + k;
    if (!d.present(key, i)) continue;
    const double v = d.number(key, i);
    if (v == 0.0 && key == "part.inner_radius") continue;  // a disk
    if (!(v <= kLargestLength) || !(v >= kSmallestLength))
      throw SceneError({d.issue(key, i, key + " = " + g(v) + " is outside the lengths a shell mesh can use, [" +
                                         g(kSmallestLength) + ", " + g(kLargestLength) +
                                         "]: the elements multiply three lengths, which must stay inside double "
                                         "precision; choose a length unit that keeps the scene's lengths near 1")});
  }
  for (double x : d.numbers("part.origin", i))
    if (!(std::abs(x) <= kLargestLength))
      throw SceneError({d.issue("part.origin", i, "a coordinate of part.origin (" + g(x) + ") lies beyond " +
                                                   g(kLargestLength) + ", outside the lengths a shell mesh can use")});
}

// One element's two sides (an approximate length each, from the keys) and the key that made each.
struct ElementSide {
  double length;
  std::string key, what;
};

void check_aspect(const Document& d, std::size_t i, const ElementSide& a, const ElementSide& b) {
  if (!(a.length > 0) || !(b.length > 0)) return;  // refused elsewhere, with its own reason
  const ElementSide& shorter = a.length < b.length ? a : b;
  const ElementSide& longer = a.length < b.length ? b : a;
  if (!(longer.length > kLargestAspect * shorter.length)) return;
  throw SceneError({d.issue(shorter.key, i, "the elements would be " + g(shorter.length) + " " + shorter.what + " but " +
                                             g(longer.length) + " " + longer.what + ", " + g(longer.length / shorter.length) +
                                             " times longer; an element's sides may differ by at most " +
                                             g(kLargestAspect) + " times (beyond that its stiffness cannot be solved in "
                                             "double precision); change " + shorter.key +
                                             " or the element counts")});
}

// An arc side of `radius` x `span` [rad] over n elements: the angle range is at fault when a
// full turn at this radius would have been long enough against `other`, else the radius.
ElementSide arc_side(double radius, const char* radius_key, double span, int n, const ElementSide& other,
                     const std::string& what) {
  const bool turn_would_do = radius * 2.0 * std::numbers::pi / n * kLargestAspect >= other.length;
  return {radius * span / n, turn_would_do ? "part.end_angle" : radius_key, what};
}

// an element may span at most kLargestElementAzimuth of azimuth
void check_azimuth_count(const Document& d, std::size_t i, const char* count_key) {
  const double span = std::abs(d.number("part.end_angle", i) - d.number("part.start_angle", i));
  const long long n = d.integer(std::string("part.") + count_key, i);
  if (span / static_cast<double>(n) <= kLargestElementAzimuth * (1 + 1e-12)) return;
  const long long needed = static_cast<long long>(std::ceil(span / kLargestElementAzimuth - 1e-12));
  throw SceneError({d.issue(std::string("part.") + count_key, i,
                            "part." + std::string(count_key) + " = " + std::to_string(n) + " element(s) around " + g(span) +
                                " degrees of azimuth span " + g(span / n) + " degrees each; an element may span at most " +
                                g(kLargestElementAzimuth) + " (at 180 its corners and directors lie in one plane "
                                "through the axis, and the stiffness is singular): use at least " +
                                std::to_string(needed))});
}

// the element shapes a generator's keys give, before anything is built
void check_element_shapes(const Document& d, std::size_t i, const std::string& gen) {
  check_length_range(d, i);
  const int n1 = count(d, i, "n1"), n2 = count(d, i, "n2");
  const double deg = std::numbers::pi / 180.0;
  if (gen == "rectangular_plate") {
    check_aspect(d, i, {d.number("part.length", i) / n1, "part.length", "along x (part.length / part.n1)"},
                 {d.number("part.width", i) / n2, "part.width", "along y (part.width / part.n2)"});
  } else if (gen == "l_plate" || gen == "folded_plate") {
    const double w = d.number("part.width", i);
    const bool l = gen == "l_plate";
    const ElementSide across{w / n2, "part.width", "across the width (part.width / part.n2)"};
    const int n3 = l ? n1 : (count(d, i, "n3") > 0 ? count(d, i, "n3") : n1);
    const std::string key2 = d.present("part.length2", i) || !l ? "part.length2" : "part.length";
    const double leg1 = d.number("part.length", i), leg2 = d.present("part.length2", i) ? d.number("part.length2", i) : leg1;
    check_aspect(d, i, {(l ? leg1 - w / 2 : leg1) / n1, "part.length", "along the first leg"}, across);
    check_aspect(d, i, {(l ? leg2 - w / 2 : leg2) / n3, key2, "along the second leg"}, across);
  } else if (gen == "cylinder") {
    const ElementSide axial{d.number("part.length", i) / n2, "part.length", "along the axis (part.length / part.n2)"};
    const double span = std::abs(d.number("part.end_angle", i) - d.number("part.start_angle", i)) * deg;
    check_aspect(d, i, arc_side(d.number("part.radius", i), "part.radius", span, n1, axial, "around (radius x angle / part.n1)"),
                 axial);
    check_azimuth_count(d, i, "n1");
  } else if (gen == "annulus") {
    const double r = d.number("part.radius", i), ri = d.number("part.inner_radius", i);
    const double span = std::abs(d.number("part.end_angle", i) - d.number("part.start_angle", i)) * deg;
    if (ri > 0 && ri < r) {
      const ElementSide radial{(r - ri) / n1, "part.inner_radius", "across the ring ((radius - inner_radius) / part.n1)"};
      check_aspect(d, i, arc_side(r, "part.radius", span, n2, radial, "around the rim (radius x angle / part.n2)"), radial);
      check_aspect(d, i, arc_side(ri, "part.inner_radius", span, n2, radial, "around the hole (inner_radius x angle / part.n2)"),
                   radial);
    }
    if (ri > 0 || d.boolean("part.slit", i)) check_azimuth_count(d, i, "n2");
  } else if (gen == "spherical_cap") {
    const double r = d.number("part.radius", i), t0 = d.number("part.polar_start", i) * deg, t1 = d.number("part.polar_end", i) * deg;
    const double span = std::abs(d.number("part.end_angle", i) - d.number("part.start_angle", i)) * deg;
    if (t0 > 0 && t1 > t0) {
      const ElementSide meridian{r * (t1 - t0) / n1, "part.polar_end", "along the meridian (radius x polar range / part.n1)"};
      for (const auto& [t, key] : {std::pair{t0, "part.polar_start"}, std::pair{t1, "part.polar_end"}}) {
        ElementSide around = arc_side(r * std::sin(t), "part.radius", span, n2, meridian,
                                      "along the parallel at polar angle " + g(t / deg) + " deg");
        if (around.key == "part.radius") around.key = key;  // a parallel this short is the polar angle's doing
        check_aspect(d, i, around, meridian);
      }
      check_azimuth_count(d, i, "n2");
    }
  }
}

void check_polar_range(const Document& d, std::size_t i) {
  // the generator refuses a theta within 1e-9 rad of a pole (quads collapse there): say so at the key
  const double pole = 1e-9 * 180.0 / std::numbers::pi;
  const double t0 = d.number("part.polar_start", i), t1 = d.number("part.polar_end", i);
  if (t0 > 0 && t0 <= pole)
    throw SceneError({d.issue("part.polar_start", i, "a polar hole of " + g(t0) + " deg is a point, where quads collapse "
                                                  "to triangles; use 0 (a cap closed at the pole) or a hole above " +
                                                  g(pole) + " deg")});
  if (t1 >= 180.0 - pole)
    throw SceneError({d.issue("part.polar_end", i, "a rim at " + g(t1) + " deg is the opposite pole, where quads collapse "
                                                "to triangles; keep it below " + g(180.0 - pole) + " deg")});
}

Vec3 checked_direction(const Document& d, std::size_t i, const char* key) {
  const Vec3 v = vec(d.numbers(std::string("part.") + key, i));
  if (!(v.norm() > 0)) throw SceneError({d.issue(std::string("part.") + key, i, "the direction is the zero vector")});
  return v;
}

void check_reference(const Document& d, std::size_t i, const Vec3& axis) {
  const Vec3 r = checked_direction(d, i, "reference");
  if (r.cross(axis).norm() < 1e-9 * r.norm() * axis.norm())
    throw SceneError({d.issue(d.present("part.reference", i) ? "part.reference" : "part.axis", i,
                              "part.reference (the direction of azimuth 0) is parallel to part.axis; give one across it")});
}

// cut_cylinder: x = x_axis + R cos phi, z = z_axis + R sin phi, phi from start_angle to end_angle
// along u; y from the plane y = end_slope x + origin y along v over part.length (the bodies of the
// double pendulum; the director is the outward radial direction)
mesh::ShellMesh cut_cylinder(const Document& d, std::size_t i) {
  const int n1 = count(d, i, "n1"), n2 = count(d, i, "n2");
  const Vec3 origin = vec(d.numbers("part.origin", i));
  const double R = d.number("part.radius", i), p0 = radians(d.number("part.start_angle", i)),
               p1 = radians(d.number("part.end_angle", i)), L = d.number("part.length", i),
               slope = d.number("part.end_slope", i), y0 = origin.y();
  const double span_deg = std::abs(d.number("part.end_angle", i) - d.number("part.start_angle", i));
  if (!(span_deg > 1e-9) || span_deg > 360.0 * (1 + 1e-12))
    throw SceneError({d.issue(d.present("part.end_angle", i) ? "part.end_angle" : "part.start_angle", i,
                              "the arc from start_angle to end_angle must span more than 0 and at most 360 degrees")});
  if (span_deg / n1 > kLargestElementAzimuth * (1 + 1e-12))
    throw SceneError({d.issue("part.n1", i, "part.n1 = " + std::to_string(n1) + " element(s) over the arc span " +
                                                g(span_deg / n1) + " degrees each; an element may span at most " +
                                                g(kLargestElementAzimuth) + " (at 180 the stiffness is singular)")});
  const double cx = origin.x(), cz = origin.z();
  mesh::ShellMesh m = mesh::parametric_patch(
      name_or(d, i, "cylinder"), "cylinder R=" + std::to_string(R) + " cut by planes y = " + std::to_string(slope) + " x + const",
      n1, n2, [=](double u, double v) {
        const double phi = p0 + u * (p1 - p0);
        const Vec3 radial(std::cos(phi), 0.0, std::sin(phi));
        const double x = cx + R * radial.x(), z = cz + R * radial.z();
        return mesh::SurfacePoint{Vec3(x, slope * x + y0 + v * L, z), radial};
      });
  m.patches[0].edge_names = {"start_angle", "end_angle", "bottom", "top"};
  return m;
}

mesh::ShellMesh build(const Document& d, std::size_t i, const std::string& gen) {
  const int n1 = count(d, i, "n1"), n2 = count(d, i, "n2");
  const Vec3 origin = vec(d.numbers("part.origin", i));
  if (gen == "rectangular_plate")
    return mesh::axis_aligned_plate(d.number("part.length", i), d.number("part.width", i), origin, n1, n2, name_or(d, i, "plate"));
  if (gen == "l_plate") {
    mesh::LPlate s;
    s.leg1 = d.number("part.length", i);
    s.leg2 = d.present("part.length2", i) ? d.number("part.length2", i) : s.leg1;
    s.width = d.number("part.width", i);
    s.origin = origin;
    for (const char* k : {"length", "length2"})
      if (d.present(std::string("part.") + k, i) && !(d.number(std::string("part.") + k, i) > s.width / 2))
        throw SceneError({d.issue(std::string("part.") + k, i, "a leg's centre line runs to the centre of the corner square, "
                                                              "so it must be longer than half the width (" +
                                                                  d.value_text("part.width", i) + " / 2)")});
    return mesh::l_plate(s, n1, n2);
  }
  if (gen == "folded_plate") {
    mesh::FoldedPlate s;
    s.a = d.number("part.length", i);
    s.b = d.number("part.length2", i);
    s.width = d.number("part.width", i);
    s.fold_angle = radians(d.number("part.fold_angle", i));
    s.origin = origin;
    const int n3 = count(d, i, "n3") > 0 ? count(d, i, "n3") : n1;
    return mesh::folded_plate(s, n1, n3, n2);
  }
  if (gen == "cut_cylinder") return cut_cylinder(d, i);
  const Vec3 axis = checked_direction(d, i, "axis");
  check_reference(d, i, axis);
  const Vec3 reference = vec(d.numbers("part.reference", i));
  if (gen == "cylinder") {
    mesh::CylinderPatch s;
    s.radius = d.number("part.radius", i);
    s.origin = origin;
    s.axis = axis;
    s.radial0 = reference;
    std::tie(s.phi0, s.phi1) = azimuth(d, i, true);
    s.s0 = 0.0;
    s.s1 = d.number("part.length", i);
    s.slit = d.boolean("part.slit", i);
    return mesh::cylindrical_patch(s, n1, n2, name_or(d, i, "cylinder"));
  }
  if (gen == "annulus") {
    mesh::AnnularSector s;
    s.r_outer = d.number("part.radius", i);
    s.r_inner = d.number("part.inner_radius", i);
    if (!(s.r_inner < s.r_outer))
      throw SceneError({d.issue("part.inner_radius", i, "the inner radius must be smaller than part.radius (" +
                                                         d.value_text("part.radius", i) + ")")});
    s.center = origin;
    s.axis = axis;
    s.radial0 = reference;
    std::tie(s.phi0, s.phi1) = azimuth(d, i, true);
    s.slit = d.boolean("part.slit", i);
    if (s.slit && s.r_inner == 0.0)
      throw SceneError({d.issue("part.slit", i, "a slit disk needs a hole (part.inner_radius > 0): the slit would end at "
                                             "the centre, where quads collapse")});
    return mesh::annulus(s, n1, n2, name_or(d, i, "annulus"));
  }
  // spherical_cap
  mesh::SpherePatch s;
  s.radius = d.number("part.radius", i);
  s.center = origin;
  s.pole = axis;
  s.radial0 = reference;
  s.theta0 = radians(d.number("part.polar_start", i));
  s.theta1 = radians(d.number("part.polar_end", i));
  if (!(d.number("part.polar_start", i) < d.number("part.polar_end", i)))
    throw SceneError({d.issue("part.polar_end", i, "the rim's polar angle must exceed part.polar_start (" +
                                                    d.value_text("part.polar_start", i) + " deg)")});
  check_polar_range(d, i);
  std::tie(s.phi0, s.phi1) = azimuth(d, i, false);
  return mesh::spherical_cap(s, n1, n2, name_or(d, i, "cap"));
}

}  // namespace

std::string generator_grid_directions(const std::string& generator) {
  static const std::map<std::string, std::string> directions = {
      {"rectangular_plate", "u along x (from edge x_min to x_max), v along y (from y_min to y_max)"},
      {"l_plate",
       "u along each arm, from arm1's free end towards arm2's (along x in arm1 and the corner, along y in arm2), v "
       "across the width"},
      {"folded_plate", "u along each leg, from leg1's end over the fold to leg2's end, v along the fold (y)"},
      {"cylinder", "u around the arc (from edge start_angle to end_angle), v along the axis (from bottom to top)"},
      {"cut_cylinder", "u around the arc (from edge start_angle to end_angle), v along the axis y (from bottom to top)"},
      {"annulus",
       "u radial (from edge inner, or core without a hole, to outer), v around (from start_angle to end_angle); in the "
       "core square of a disk without a hole, the square's own grid"},
      {"spherical_cap",
       "u along the meridian (from edge hole, or core without a hole, to rim), v around the azimuth (from start_angle "
       "to end_angle); in the core square of a cap without a hole, the square's own grid"},
  };
  const auto it = directions.find(generator);
  return it == directions.end() ? std::string() : it->second;
}

void declare_part_keys(Schema& s) {
  s.table_array("part",
          "a shell part of the structure. A generator builds its mid-surface from the dimensions below (lengths in "
          "the scene's unit, angles in degrees; every generator names its patches and their edges for select = "
          "\"patch_edge\", docs/guide/writing-a-scene.md shows them), or generator = \"file\" reads a quad mesh. "
          "Parts meet only where a [[junction]] joins them (shared nodes) or a [[joint]] connects them. Azimuth: "
          "the angle phi about part.axis, right-handed, from part.reference (its part across the axis). Edge names "
          "per generator (patch: u=0, u=1, v=0, v=1): rectangular_plate (patch part.name): x_min, x_max, y_min, "
          "y_max; l_plate: arm1: end, corner, outer, inner; corner: arm1, outer2, outer1, arm2; arm2: corner, end, "
          "outer, inner; folded_plate: leg1: end, fold, y_min, y_max; leg2: fold, end, y_min, y_max; cylinder and "
          "cut_cylinder: start_angle, end_angle, bottom, top; annulus: inner, outer, start_angle, end_angle "
          "(without a hole: patches <name>_core and <name> with edges core, outer); spherical_cap: hole, rim, "
          "start_angle, end_angle (without a hole: patches <name>_core and <name> with edges core, rim)",
          1, 64)
      .choice("part.generator",
              "rectangular_plate: a plate in z = origin z; l_plate: a flat L of two strips; folded_plate: two plates "
              "meeting at a fold; cylinder: a cylindrical panel or closed cylinder; annulus: an annular or disk "
              "sector, closed, or slit; spherical_cap: a spherical cap or hemisphere, with or without a polar hole; "
              "cut_cylinder: a cylinder about an axis along y cut by two parallel planes y = end_slope x + const; "
              "file: a quad mesh file (part.file)",
              {"rectangular_plate", "l_plate", "folded_plate", "cylinder", "cut_cylinder", "annulus", "spherical_cap", "file"},
              std::nullopt)
      .integer("part.n1",
               "elements along the first direction: plate along x; l_plate along each arm; folded_plate along leg1; "
               "cylinder around (over the azimuth range); annulus and spherical_cap from the hole (or the core) to the "
               "rim",
               16, IntRange::closed(1, 1024))
      .integer("part.n2",
               "elements along the second direction: plate along y; l_plate and folded_plate across the width; cylinder "
               "along the axis; annulus and spherical_cap along the rim (without a hole a multiple of 2, 4 or 8 for 90, "
               "180 or 360 degrees)",
               16, IntRange::closed(1, 1024))
      .integer("part.n3", "folded_plate: elements along leg2; 0 = as many as part.n1", 0, IntRange::closed(0, 1024))
      .string("part.name",
              "the part's name ([[junction]], [[joint]] and the selectors' patch use it); for rectangular_plate, "
              "cylinder, cut_cylinder, annulus, spherical_cap also the name of its patch (select = \"patch_edge\"). "
              "\"\" = the generator's default: plate, cylinder, annulus, cap (l_plate and folded_plate name their "
              "patches arm1/corner/arm2 and leg1/leg2)",
              std::string{})
      .string("part.material", "the [[material]] it is made of, by name; \"\" = the scene's only material",
              std::string{})
      .string("part.layup",
              "the [[layup]] it is made of, by name (a laminated section), instead of part.material; \"\" = none",
              std::string{})
      .choice("part.fibre_reference",
              "the direction ply angles are measured from (projected on each element's surface; also the x1 axis of "
              "the part's stresses): u or v, the generator's u or v grid direction at each element's centre (the "
              "edge names list which is which: u runs from edge u=0 to u=1); for generator = file, u is each "
              "element's edge from its first corner to its second and v to its fourth, so a file part of orthotropic plies needs \"vector\"; vector: "
              "part.fibre_vector. No default for a part of orthotropic plies (refused without it: u and v are other "
              "directions on every generator); u for isotropic ones",
              {"u", "v", "vector"}, "u")
      .number_list("part.fibre_vector",
                   "fibre_reference = \"vector\" (required there, refused otherwise): the world vector ply angles are "
                   "measured from, projected on each element's surface; refused where it is parallel to an "
                   "element's normal",
                   std::vector<double>{}, {}, 0, 3)
      .boolean("part.flip_director",
               "turn the part's directors (and the sense of its quads) to the other side of its surface, so that it "
               "matches a part it is joined to: a junction needs both parts' directors on the same side",
               false)
      .number_list("part.origin",
                   "rectangular_plate: the corner (x_min, y_min) in the plane z = origin z; l_plate: the outer corner "
                   "of arm1's end (its end is x = origin x, its outer edge y = origin y); folded_plate: the corner of "
                   "leg1's end (end x = origin x, leg1 in z = origin z); cylinder: the point of the axis at the bottom "
                   "edge; cut_cylinder: [x of the axis, y where the first end plane crosses x = 0, z of the axis]; annulus: "
                   "the centre; spherical_cap: the sphere's centre",
                   std::vector<double>{0, 0, 0}, {}, 3, 3)
      .number_list("part.axis",
                   "cylinder: the axis direction (bottom at origin, top at origin + length axis); annulus: the plane "
                   "normal (the director); spherical_cap: from the centre to the pole (polar angle 0)",
                   std::vector<double>{0, 0, 1}, {}, 3, 3)
      .number_list("part.reference",
                   "cylinder, annulus, spherical_cap: the direction of azimuth 0 (only its part across part.axis counts)",
                   std::vector<double>{1, 0, 0}, {}, 3, 3)
      .number("part.length",
              "rectangular_plate (required): length along x; l_plate (required): centre-line length of arm1 along x, from "
              "its end to the centre of the corner square; folded_plate (required): length of leg1 along x, from its "
              "end to the fold line; cylinder, cut_cylinder (required): length along the axis",
              1.0, Range::positive())
      .number("part.length2",
              "l_plate: centre-line length of arm2 along y (default: part.length); folded_plate (required): length of "
              "leg2 from the fold line to its end",
              1.0, Range::positive())
      .number("part.width",
              "rectangular_plate (required): width along y; l_plate (required): width of both strips; folded_plate "
              "(required): width of both legs along y (the fold line)",
              1.0, Range::positive())
      .number("part.radius", "cylinder, cut_cylinder, spherical_cap (required): the radius; annulus (required): the outer radius", 1.0,
              Range::positive())
      .number("part.inner_radius", "annulus: the inner radius; 0 = a disk (no hole)", 0.0, Range::non_negative())
      .number("part.start_angle",
              "cylinder, annulus, spherical_cap: azimuth where the surface starts; cut_cylinder: the angle phi in "
              "the xz plane where it starts (x = x_axis + R cos phi, z = z_axis + R sin phi; it may exceed "
              "end_angle: the arc runs from start_angle to end_angle)",
              0.0, {}, "deg")
      .number("part.end_angle",
              "cylinder, annulus, spherical_cap: azimuth where it ends, above start_angle; a 360 degree range "
              "closes the surface (its seam nodes are merged) unless part.slit; cut_cylinder: the angle phi where "
              "it ends",
              360.0, {}, "deg")
      .boolean("part.slit",
               "cylinder, annulus over 360 degrees: keep the seam open as two coincident lips (separate nodes: edges "
               "start_angle and end_angle)",
               false)
      .number("part.polar_start",
              "spherical_cap: polar angle (from the pole, part.axis) of the hole's edge; 0 = closed at the pole (a "
              "pole-free core + ring mesh)",
              0.0, Range::right_open(0.0, 180.0), "deg")
      .number("part.polar_end", "spherical_cap (required): polar angle of the rim (90 = hemisphere)", 90.0,
              Range::open(0.0, 180.0), "deg")
      .number("part.end_slope", "cut_cylinder: dy/dx of both end planes (the tangent of their angle to the xz "
              "plane); the planes are y = end_slope x + origin y and that plus part.length", 0.0)
      .number("part.fold_angle",
              "folded_plate: how far leg2 turns up (towards +z) from leg1's continuation: 0 = flat, 90 = upright",
              90.0, Range::open(-180.0, 180.0), "deg")
      .string("part.file",
              "generator = file: a mesh (Gmsh .msh, Abaqus .inp, OBJ, PLY, STL) or a CAD part meshed by Gmsh "
              "(STEP .step/.stp, IGES .iges/.igs, BREP .brep, Gmsh script .geo), relative to the scene file",
              std::string{})
      .choice("part.triangles",
              "generator = file: what becomes of triangles: split (each into three quads through its centroid and "
              "edge midpoints; in a mesh with quads too, every quad into four), recombine (Gmsh joins them into "
              "quads; .msh files), refuse",
              {"split", "recombine", "refuse"}, "split")
      .number("part.crease_angle",
              "generator = file, directors averaged from the elements: neighbours that turn more than this across "
              "their edge are separate smooth pieces, and the nodes between them fold nodes (6 DoF)",
              30.0, Range::open(0.0, 180.0), "deg")
      .string("part.group",
              "generator = file: only the elements of this surface group of the file (a Gmsh physical surface, an "
              "Abaqus *ELSET); \"\" = every element. Parts from one file joined by a [[junction]] can have "
              "materials of their own",
              std::string{})
      .number("part.mesh_size",
              "generator = file, CAD or .geo: the element size Gmsh meshes at, given to every point of the geometry "
              "and as the largest edge (required for STEP, IGES and BREP; 0 = a .geo script's own sizes)",
              0.0, Range::non_negative(), "length")
      .string_list("part.local_size_groups",
                   "generator = file, CAD or .geo: named groups of the file meshed finer, each at the size in "
                   "part.local_sizes at the same position",
                   std::vector<std::string>{})
      .number_list("part.local_sizes", "generator = file: the element size at each of part.local_size_groups",
                   std::vector<double>{}, Range::positive())
      .number("part.mesh_time_limit",
              "generator = file, Gmsh files: the time Gmsh may take to read or mesh the file before it is stopped",
              300.0, Range::positive(), "s")
      .boolean("part.keep_faces_apart",
               "generator = file: the file's faces that touch are meant to be apart (a slit, a lap that is not "
               "bonded): CAD faces are not joined where they touch, and a surface that touches itself without "
               "sharing nodes there is accepted; false: touching CAD faces are joined (OpenCASCADE's fragment), and "
               "what still touches without being joined is refused",
               false)
      .choice("part.mesh_pattern",
              "generator = file, CAD or .geo with part.mesh_size: mapped: each face bounded by four curves is meshed "
              "as a structured grid (Gmsh's transfinite meshing; meshes at neighbouring sizes then converge "
              "monotonically, so coarser twins estimate the error), unless a point or curve is embedded in it or a "
              "local size touches it, and the other faces free; free: every face by Frontal-Delaunay with Blossom "
              "recombination",
              {"mapped", "free"}, "mapped")
      .number("part.weld_tolerance",
              "generator = file: join vertices closer than this length (0: every vertex of the file is a node of its "
              "own, so a slit written with separate vertices stays open)",
              0.0, Range::non_negative(), "length");
  for (const char* k : {"origin", "length", "length2", "width", "radius", "inner_radius"})
    s.unit_of(std::string("part.") + k, "length");
  // each dimension belongs to the generators that read it (the window lists and keeps only those)
  std::vector<std::string> conditional = kDimensionKeys;
  conditional.push_back("file");
  for (const std::string& k : conditional) {
    std::vector<std::string> owners;
    for (const auto& [gen, keys] : generator_keys())
      if (std::find(keys.begin(), keys.end(), k) != keys.end()) owners.push_back(gen);
    s.applies_when("part." + k, "part.generator", owners);
  }
}

std::vector<std::string> generator_required_keys(const std::string& generator) {
  const auto it = required_keys().find(generator);
  return it == required_keys().end() ? std::vector<std::string>{} : it->second;
}

std::vector<std::string> generator_count_keys(const std::string& generator) {
  std::vector<std::string> out;
  const auto it = generator_keys().find(generator);
  if (it == generator_keys().end()) return out;
  for (const std::string& key : it->second)
    if (key == "n1" || key == "n2" || key == "n3") out.push_back(key);
  return out;
}

bool mesh_from_file(const Document& d, std::size_t i) {
  const std::string& gen = d.string("part.generator", i);
  // generator = "file" without part.file: the reader's "needs part.file" comes first
  if (gen == "file" && d.string("part.file", i).empty()) return true;
  check_keys(d, i, gen);
  return gen == "file";
}

void check_thickness_against_radius(const Document& d, std::size_t i, double h, const std::string& thickness_key,
                                    std::size_t t) {
  const std::string& gen = d.string("part.generator", i);
  if (gen != "cylinder" && gen != "cut_cylinder" && gen != "spherical_cap") return;
  const double r = d.number("part.radius", i);
  if (h < r) return;
  const bool cylinder = gen != "spherical_cap";
  const std::string m = "a shell " + g(h) + " thick on a " + (cylinder ? "cylinder" : "sphere") +
                        " of radius " + g(r) + " is thicker than its radius of curvature (its inner face would lie at " +
                        g(r - h / 2) + " from the " + (cylinder ? "axis" : "centre") +
                        "); a shell must be thinner than its radius: lower " + thickness_key + " or raise part.radius";
  // either key may be the one to change: both lines are named
  throw SceneError({d.issue(thickness_key, t, m), d.issue("part.radius", i, m)});
}

namespace {
// nodes of generator `gen` with these counts (mesh::*_node_count, the generators' own merging);
// keys the generator would refuse (an O-grid span that is not 90, 180 or 360 degrees) count as
// an open patch, and the generator then refuses them
long long node_count(const Document& d, std::size_t i, const std::string& gen, int n1, int n2, int n3) {
  const auto span_is = [&](double degrees) {
    return std::abs(std::abs(d.number("part.end_angle", i) - d.number("part.start_angle", i)) - degrees) <= 1e-9 * 360.0;
  };
  const auto o_grid = [&](int n_ring, int n_rim) {
    for (int q : {1, 2, 4})
      if (span_is(90.0 * q) && n_rim % (2 * q) == 0) return mesh::polar_o_grid_node_count(n_ring, n_rim, q);
    return mesh::patch_node_count(n_ring, n_rim);
  };
  // a 360 degree seam is merged (assemble() within a fraction of the shortest edge); with a single
  // element around, that edge joins the seam's two lips and has no length, and nothing merges
  const bool full_turn = span_is(360.0);
  if (gen == "rectangular_plate") return mesh::patch_node_count(n1, n2);
  if (gen == "l_plate") return mesh::l_plate_node_count(n1, n2);
  if (gen == "folded_plate") return mesh::folded_plate_node_count(n1, n3 > 0 ? n3 : n1, n2);
  if (gen == "cylinder") return mesh::patch_node_count(n1, n2, full_turn && !d.boolean("part.slit", i) && n1 > 1, false);
  if (gen == "cut_cylinder") return mesh::patch_node_count(n1, n2, full_turn && n1 > 1, false);
  if (gen == "annulus") {
    if (d.number("part.inner_radius", i) == 0.0 && !d.boolean("part.slit", i)) return o_grid(n1, n2);
    return mesh::patch_node_count(n1, n2, false, full_turn && !d.boolean("part.slit", i) && n2 > 1);
  }
  if (gen == "spherical_cap") {
    if (d.number("part.polar_start", i) == 0.0) return o_grid(n1, n2);
    return mesh::patch_node_count(n1, n2, false, full_turn && n2 > 1);
  }
  return 0;
}
}  // namespace

GeneratedMeshSize generated_mesh_size(const Document& d, std::size_t i) {
  const std::string& gen = d.string("part.generator", i);
  const int n1 = count(d, i, "n1"), n2 = count(d, i, "n2"), n3 = count(d, i, "n3");
  GeneratedMeshSize size;
  size.nodes = node_count(d, i, gen, n1, n2, n3);
  size.key = "part.generator";
  long long smallest = size.nodes;
  const std::vector<std::string> keys = gen == "folded_plate" ? std::vector<std::string>{"n1", "n2", "n3"}
                                                              : std::vector<std::string>{"n1", "n2"};
  for (const std::string& k : keys) {
    if (!d.present("part." + k, i)) continue;
    // n3 = 0 follows n1, so n1 then sizes both legs
    const long long without = node_count(d, i, gen, k == "n1" ? 1 : n1, k == "n2" ? 1 : n2, k == "n3" ? 1 : n3);
    if (size.key == "part.generator" || without < smallest) smallest = without, size.key = "part." + k;
  }
  return size;
}

mesh::ShellMesh generate_mesh(const Document& d, std::size_t i) {
  const std::string& gen = d.string("part.generator", i);
  check_keys(d, i, gen);
  // ranges first (their own messages), then the element shapes they give, at the key at fault
  if (gen == "cylinder" || gen == "annulus" || gen == "spherical_cap") azimuth(d, i, gen != "spherical_cap");
  if (gen == "spherical_cap") check_polar_range(d, i);
  check_element_shapes(d, i, gen);
  try {
    return build(d, i, gen);
  } catch (const std::invalid_argument& e) {
    throw SceneError({d.issue("part.generator", i, e.what())});
  }
}

}  // namespace ff::scene
