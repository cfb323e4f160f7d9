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

// The keys each generator reads besides mesh.generator; any other generator key given with it is
// an error (a dimension that would silently do nothing).
const std::map<std::string, std::vector<std::string>>& generator_keys() {
  static const std::map<std::string, std::vector<std::string>> keys = {
      {"rectangular_plate", {"n1", "n2", "name", "origin", "length", "width"}},
      {"l_plate", {"n1", "n2", "origin", "length", "length2", "width"}},
      {"folded_plate", {"n1", "n2", "n3", "origin", "length", "length2", "width", "fold_angle"}},
      {"cylinder",
       {"n1", "n2", "name", "origin", "axis", "reference", "radius", "length", "start_angle", "end_angle", "slit"}},
      {"annulus",
       {"n1", "n2", "name", "origin", "axis", "reference", "radius", "inner_radius", "start_angle", "end_angle", "slit"}},
      {"spherical_cap",
       {"n1", "n2", "name", "origin", "axis", "reference", "radius", "polar_start", "polar_end", "start_angle",
        "end_angle"}},
      {"file", {"file", "weld_tolerance"}},
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
      {"annulus", {"radius"}},
      {"spherical_cap", {"radius", "polar_end"}},
  };
  return keys;
}
// every key of the table that belongs to some generator
const std::vector<std::string> kDimensionKeys = {"n1",     "n2",          "n3",          "name",      "origin",
                                                 "axis",   "reference",   "length",      "length2",   "width",
                                                 "radius", "inner_radius", "start_angle", "end_angle", "polar_start",
                                                 "polar_end", "fold_angle", "slit", "weld_tolerance"};

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }  // exact for 90 -> pi/2

Vec3 vec(const std::vector<double>& v) { return Vec3(v[0], v[1], v[2]); }

void check_keys(const Document& d, const std::string& gen) {
  const std::vector<std::string>& own = generator_keys().at(gen);
  std::string own_list;
  for (const std::string& k : own) own_list += (own_list.empty() ? "" : ", ") + k;
  for (const std::string& k : kDimensionKeys)
    if (d.present("mesh." + k) && std::find(own.begin(), own.end(), k) == own.end())
      throw SceneError({d.issue("mesh." + k, "mesh." + k + " does not belong to generator = \"" + gen + "\" (its keys: " +
                                                 (own_list.empty() ? std::string("mesh.file") : own_list) + ")")});
  if (gen != "file" && d.present("mesh.file"))
    throw SceneError({d.issue("mesh.file", "mesh.file belongs to generator = \"file\"; generator = \"" + gen +
                                               "\" builds its own mesh")});
  const auto req = required_keys().find(gen);
  if (req != required_keys().end())
    for (const std::string& k : req->second)
      if (!d.present("mesh." + k))
        throw SceneError({d.issue("mesh.generator", "generator = \"" + gen + "\" needs mesh." + k + " (" +
                                                        (k == "polar_end" ? "the polar angle of the rim in degrees, e.g. 90 "
                                                                            "for a hemisphere"
                                                                          : "a dimension in the scene's length unit") +
                                                        ")")});
}

int count(const Document& d, const char* key) { return static_cast<int>(d.integer(std::string("mesh.") + key)); }

std::string name_or(const Document& d, const char* fallback) {
  const std::string& n = d.string("mesh.name");
  return n.empty() ? std::string(fallback) : n;
}

// azimuth range [start, end] in degrees, 0 < end - start <= 360; slit only on a full turn
std::pair<double, double> azimuth(const Document& d, bool slit_allowed) {
  const double a0 = d.number("mesh.start_angle"), a1 = d.number("mesh.end_angle");
  const double span = std::abs(a1 - a0);
  // a reversed range would be swept backwards: the edges named start_angle and end_angle (a
  // slit's two lips) would trade places silently
  if (a1 < a0)
    throw SceneError({d.issue(d.present("mesh.end_angle") ? "mesh.end_angle" : "mesh.start_angle",
                              "the azimuth range [start_angle, end_angle] = [" + d.value_text("mesh.start_angle") + ", " +
                                  d.value_text("mesh.end_angle") + "] deg runs backwards; end_angle must exceed "
                                  "start_angle (the surface is swept from start_angle towards end_angle, "
                                  "right-handed about mesh.axis)")});
  if (!(span > 0) || span > 360.0 * (1 + 1e-12))
    throw SceneError({d.issue(d.present("mesh.end_angle") ? "mesh.end_angle" : "mesh.start_angle",
                              "the azimuth range [start_angle, end_angle] = [" + d.value_text("mesh.start_angle") + ", " +
                                  d.value_text("mesh.end_angle") + "] deg must span more than 0 and at most 360 degrees")});
  if (slit_allowed && d.boolean("mesh.slit") && std::abs(span - 360.0) > 1e-9)
    throw SceneError({d.issue("mesh.slit", "a slit is the seam of a closed 360 degree surface kept open; this one spans " +
                                               d.value_text("mesh.end_angle") + " - " + d.value_text("mesh.start_angle") +
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
void check_length_range(const Document& d) {
  for (const char* k : {"length", "length2", "width", "radius", "inner_radius"}) {
    const std::string key = std::string("mesh.") + k;
    if (!d.present(key)) continue;
    const double v = d.number(key);
    if (v == 0.0 && key == "mesh.inner_radius") continue;  // a disk
    if (!(v <= kLargestLength) || !(v >= kSmallestLength))
      throw SceneError({d.issue(key, key + " = " + g(v) + " is outside the lengths a shell mesh can use, [" +
                                         g(kSmallestLength) + ", " + g(kLargestLength) +
                                         "]: the elements multiply three lengths, which must stay inside double "
                                         "precision; choose a length unit that keeps the scene's lengths near 1")});
  }
  for (double x : d.numbers("mesh.origin"))
    if (!(std::abs(x) <= kLargestLength))
      throw SceneError({d.issue("mesh.origin", "a coordinate of mesh.origin (" + g(x) + ") lies beyond " +
                                                   g(kLargestLength) + ", outside the lengths a shell mesh can use")});
}

// One element's two sides (an approximate length each, from the keys) and the key that made each.
struct ElementSide {
  double length;
  std::string key, what;
};

void check_aspect(const Document& d, const ElementSide& a, const ElementSide& b) {
  if (!(a.length > 0) || !(b.length > 0)) return;  // refused elsewhere, with its own reason
  const ElementSide& shorter = a.length < b.length ? a : b;
  const ElementSide& longer = a.length < b.length ? b : a;
  if (!(longer.length > kLargestAspect * shorter.length)) return;
  throw SceneError({d.issue(shorter.key, "the elements would be " + g(shorter.length) + " " + shorter.what + " but " +
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
  return {radius * span / n, turn_would_do ? "mesh.end_angle" : radius_key, what};
}

// an element may span at most kLargestElementAzimuth of azimuth
void check_azimuth_count(const Document& d, const char* count_key) {
  const double span = std::abs(d.number("mesh.end_angle") - d.number("mesh.start_angle"));
  const long long n = d.integer(std::string("mesh.") + count_key);
  if (span / static_cast<double>(n) <= kLargestElementAzimuth * (1 + 1e-12)) return;
  const long long needed = static_cast<long long>(std::ceil(span / kLargestElementAzimuth - 1e-12));
  throw SceneError({d.issue(std::string("mesh.") + count_key,
                            "mesh." + std::string(count_key) + " = " + std::to_string(n) + " element(s) around " + g(span) +
                                " degrees of azimuth span " + g(span / n) + " degrees each; an element may span at most " +
                                g(kLargestElementAzimuth) + " (at 180 its corners and directors lie in one plane "
                                "through the axis, and the stiffness is singular): use at least " +
                                std::to_string(needed))});
}

// the element shapes a generator's keys give, before anything is built
void check_element_shapes(const Document& d, const std::string& gen) {
  check_length_range(d);
  const int n1 = count(d, "n1"), n2 = count(d, "n2");
  const double deg = std::numbers::pi / 180.0;
  if (gen == "rectangular_plate") {
    check_aspect(d, {d.number("mesh.length") / n1, "mesh.length", "along x (mesh.length / mesh.n1)"},
                 {d.number("mesh.width") / n2, "mesh.width", "along y (mesh.width / mesh.n2)"});
  } else if (gen == "l_plate" || gen == "folded_plate") {
    const double w = d.number("mesh.width");
    const bool l = gen == "l_plate";
    const ElementSide across{w / n2, "mesh.width", "across the width (mesh.width / mesh.n2)"};
    const int n3 = l ? n1 : (count(d, "n3") > 0 ? count(d, "n3") : n1);
    const std::string key2 = d.present("mesh.length2") || !l ? "mesh.length2" : "mesh.length";
    const double leg1 = d.number("mesh.length"), leg2 = d.present("mesh.length2") ? d.number("mesh.length2") : leg1;
    check_aspect(d, {(l ? leg1 - w / 2 : leg1) / n1, "mesh.length", "along the first leg"}, across);
    check_aspect(d, {(l ? leg2 - w / 2 : leg2) / n3, key2, "along the second leg"}, across);
  } else if (gen == "cylinder") {
    const ElementSide axial{d.number("mesh.length") / n2, "mesh.length", "along the axis (mesh.length / mesh.n2)"};
    const double span = std::abs(d.number("mesh.end_angle") - d.number("mesh.start_angle")) * deg;
    check_aspect(d, arc_side(d.number("mesh.radius"), "mesh.radius", span, n1, axial, "around (radius x angle / mesh.n1)"),
                 axial);
    check_azimuth_count(d, "n1");
  } else if (gen == "annulus") {
    const double r = d.number("mesh.radius"), ri = d.number("mesh.inner_radius");
    const double span = std::abs(d.number("mesh.end_angle") - d.number("mesh.start_angle")) * deg;
    if (ri > 0 && ri < r) {
      const ElementSide radial{(r - ri) / n1, "mesh.inner_radius", "across the ring ((radius - inner_radius) / mesh.n1)"};
      check_aspect(d, arc_side(r, "mesh.radius", span, n2, radial, "around the rim (radius x angle / mesh.n2)"), radial);
      check_aspect(d, arc_side(ri, "mesh.inner_radius", span, n2, radial, "around the hole (inner_radius x angle / mesh.n2)"),
                   radial);
    }
    if (ri > 0 || d.boolean("mesh.slit")) check_azimuth_count(d, "n2");
  } else if (gen == "spherical_cap") {
    const double r = d.number("mesh.radius"), t0 = d.number("mesh.polar_start") * deg, t1 = d.number("mesh.polar_end") * deg;
    const double span = std::abs(d.number("mesh.end_angle") - d.number("mesh.start_angle")) * deg;
    if (t0 > 0 && t1 > t0) {
      const ElementSide meridian{r * (t1 - t0) / n1, "mesh.polar_end", "along the meridian (radius x polar range / mesh.n1)"};
      for (const auto& [t, key] : {std::pair{t0, "mesh.polar_start"}, std::pair{t1, "mesh.polar_end"}}) {
        ElementSide around = arc_side(r * std::sin(t), "mesh.radius", span, n2, meridian,
                                      "along the parallel at polar angle " + g(t / deg) + " deg");
        if (around.key == "mesh.radius") around.key = key;  // a parallel this short is the polar angle's doing
        check_aspect(d, around, meridian);
      }
      check_azimuth_count(d, "n2");
    }
  }
}

void check_polar_range(const Document& d) {
  // the generator refuses a theta within 1e-9 rad of a pole (quads collapse there): say so at the key
  const double pole = 1e-9 * 180.0 / std::numbers::pi;
  const double t0 = d.number("mesh.polar_start"), t1 = d.number("mesh.polar_end");
  if (t0 > 0 && t0 <= pole)
    throw SceneError({d.issue("mesh.polar_start", "a polar hole of " + g(t0) + " deg is a point, where quads collapse "
                                                  "to triangles; use 0 (a cap closed at the pole) or a hole above " +
                                                  g(pole) + " deg")});
  if (t1 >= 180.0 - pole)
    throw SceneError({d.issue("mesh.polar_end", "a rim at " + g(t1) + " deg is the opposite pole, where quads collapse "
                                                "to triangles; keep it below " + g(180.0 - pole) + " deg")});
}

Vec3 checked_direction(const Document& d, const char* key) {
  const Vec3 v = vec(d.numbers(std::string("mesh.") + key));
  if (!(v.norm() > 0)) throw SceneError({d.issue(std::string("mesh.") + key, "the direction is the zero vector")});
  return v;
}

void check_reference(const Document& d, const Vec3& axis) {
  const Vec3 r = checked_direction(d, "reference");
  if (r.cross(axis).norm() < 1e-9 * r.norm() * axis.norm())
    throw SceneError({d.issue(d.present("mesh.reference") ? "mesh.reference" : "mesh.axis",
                              "mesh.reference (the direction of azimuth 0) is parallel to mesh.axis; give one across it")});
}

mesh::ShellMesh build(const Document& d, const std::string& gen) {
  const int n1 = count(d, "n1"), n2 = count(d, "n2");
  const Vec3 origin = vec(d.numbers("mesh.origin"));
  if (gen == "rectangular_plate")
    return mesh::axis_aligned_plate(d.number("mesh.length"), d.number("mesh.width"), origin, n1, n2, name_or(d, "plate"));
  if (gen == "l_plate") {
    mesh::LPlate s;
    s.leg1 = d.number("mesh.length");
    s.leg2 = d.present("mesh.length2") ? d.number("mesh.length2") : s.leg1;
    s.width = d.number("mesh.width");
    s.origin = origin;
    for (const char* k : {"length", "length2"})
      if (d.present(std::string("mesh.") + k) && !(d.number(std::string("mesh.") + k) > s.width / 2))
        throw SceneError({d.issue(std::string("mesh.") + k, "a leg's centre line runs to the centre of the corner square, "
                                                              "so it must be longer than half the width (" +
                                                                  d.value_text("mesh.width") + " / 2)")});
    return mesh::l_plate(s, n1, n2);
  }
  if (gen == "folded_plate") {
    mesh::FoldedPlate s;
    s.a = d.number("mesh.length");
    s.b = d.number("mesh.length2");
    s.width = d.number("mesh.width");
    s.fold_angle = radians(d.number("mesh.fold_angle"));
    s.origin = origin;
    const int n3 = count(d, "n3") > 0 ? count(d, "n3") : n1;
    return mesh::folded_plate(s, n1, n3, n2);
  }
  const Vec3 axis = checked_direction(d, "axis");
  check_reference(d, axis);
  const Vec3 reference = vec(d.numbers("mesh.reference"));
  if (gen == "cylinder") {
    mesh::CylinderPatch s;
    s.radius = d.number("mesh.radius");
    s.origin = origin;
    s.axis = axis;
    s.radial0 = reference;
    std::tie(s.phi0, s.phi1) = azimuth(d, true);
    s.s0 = 0.0;
    s.s1 = d.number("mesh.length");
    s.slit = d.boolean("mesh.slit");
    return mesh::cylindrical_patch(s, n1, n2, name_or(d, "cylinder"));
  }
  if (gen == "annulus") {
    mesh::AnnularSector s;
    s.r_outer = d.number("mesh.radius");
    s.r_inner = d.number("mesh.inner_radius");
    if (!(s.r_inner < s.r_outer))
      throw SceneError({d.issue("mesh.inner_radius", "the inner radius must be smaller than mesh.radius (" +
                                                         d.value_text("mesh.radius") + ")")});
    s.center = origin;
    s.axis = axis;
    s.radial0 = reference;
    std::tie(s.phi0, s.phi1) = azimuth(d, true);
    s.slit = d.boolean("mesh.slit");
    if (s.slit && s.r_inner == 0.0)
      throw SceneError({d.issue("mesh.slit", "a slit disk needs a hole (mesh.inner_radius > 0): the slit would end at "
                                             "the centre, where quads collapse")});
    return mesh::annulus(s, n1, n2, name_or(d, "annulus"));
  }
  // spherical_cap
  mesh::SpherePatch s;
  s.radius = d.number("mesh.radius");
  s.center = origin;
  s.pole = axis;
  s.radial0 = reference;
  s.theta0 = radians(d.number("mesh.polar_start"));
  s.theta1 = radians(d.number("mesh.polar_end"));
  if (!(d.number("mesh.polar_start") < d.number("mesh.polar_end")))
    throw SceneError({d.issue("mesh.polar_end", "the rim's polar angle must exceed mesh.polar_start (" +
                                                    d.value_text("mesh.polar_start") + " deg)")});
  check_polar_range(d);
  std::tie(s.phi0, s.phi1) = azimuth(d, false);
  return mesh::spherical_cap(s, n1, n2, name_or(d, "cap"));
}

}  // namespace

void declare_mesh_keys(Schema& s) {
  s.table("mesh",
          "the shell mid-surface. A generator builds it from the dimensions below (lengths in the scene's unit, angles "
          "in degrees; every generator names its patches and their edges for select = \"patch_edge\", docs/guide/"
          "writing-your-own-scene.md shows them), or generator = \"file\" reads a quad mesh. Azimuth: the angle "
          "phi about mesh.axis, right-handed, from mesh.reference (its part across the axis). Edge names per "
          "generator (patch: u=0, u=1, v=0, v=1): rectangular_plate (patch mesh.name): x_min, x_max, y_min, y_max; "
          "l_plate: arm1: end, corner, outer, inner; corner: arm1, outer2, outer1, arm2; arm2: corner, end, outer, "
          "inner; folded_plate: leg1: end, fold, y_min, y_max; leg2: fold, end, y_min, y_max; "
          "cylinder: start_angle, end_angle, bottom, top; annulus: inner, outer, start_angle, end_angle (without a "
          "hole: patches <name>_core and <name> with edges core, outer); spherical_cap: hole, rim, start_angle, "
          "end_angle (without a hole: patches <name>_core and <name> with edges core, rim)",
          true)
      .choice("mesh.generator",
              "rectangular_plate: a plate in z = origin z; l_plate: a flat L of two strips; folded_plate: two plates "
              "meeting at a fold; cylinder: a cylindrical panel or closed cylinder; annulus: an annular or disk "
              "sector, closed, or slit; spherical_cap: a spherical cap or hemisphere, with or without a polar hole; "
              "file: a quad mesh file (mesh.file)",
              {"rectangular_plate", "l_plate", "folded_plate", "cylinder", "annulus", "spherical_cap", "file"},
              std::nullopt)
      .integer("mesh.n1",
               "elements along the first direction: plate along x; l_plate along each arm; folded_plate along leg1; "
               "cylinder around (over the azimuth range); annulus and spherical_cap from the hole (or the core) to the "
               "rim",
               16, IntRange::closed(1, 1024))
      .integer("mesh.n2",
               "elements along the second direction: plate along y; l_plate and folded_plate across the width; cylinder "
               "along the axis; annulus and spherical_cap along the rim (without a hole a multiple of 2, 4 or 8 for 90, "
               "180 or 360 degrees)",
               16, IntRange::closed(1, 1024))
      .integer("mesh.n3", "folded_plate: elements along leg2; 0 = as many as mesh.n1", 0, IntRange::closed(0, 1024))
      .string("mesh.name",
              "rectangular_plate, cylinder, annulus, spherical_cap: name of the patch (for select = \"patch_edge\"); "
              "\"\" = the generator's default: plate, cylinder, annulus, cap",
              std::string{})
      .number_list("mesh.origin",
                   "rectangular_plate: the corner (x_min, y_min) in the plane z = origin z; l_plate: the outer corner "
                   "of arm1's end (its end is x = origin x, its outer edge y = origin y); folded_plate: the corner of "
                   "leg1's end (end x = origin x, leg1 in z = origin z); cylinder: the point of the axis at the bottom "
                   "edge; annulus: the centre; spherical_cap: the sphere's centre",
                   std::vector<double>{0, 0, 0}, {}, 3, 3)
      .number_list("mesh.axis",
                   "cylinder: the axis direction (bottom at origin, top at origin + length axis); annulus: the plane "
                   "normal (the director); spherical_cap: from the centre to the pole (polar angle 0)",
                   std::vector<double>{0, 0, 1}, {}, 3, 3)
      .number_list("mesh.reference",
                   "cylinder, annulus, spherical_cap: the direction of azimuth 0 (only its part across mesh.axis counts)",
                   std::vector<double>{1, 0, 0}, {}, 3, 3)
      .number("mesh.length",
              "rectangular_plate (required): length along x; l_plate (required): centre-line length of arm1 along x, from "
              "its end to the centre of the corner square; folded_plate (required): length of leg1 along x, from its "
              "end to the fold line; cylinder (required): length along the axis",
              1.0, Range::positive())
      .number("mesh.length2",
              "l_plate: centre-line length of arm2 along y (default: mesh.length); folded_plate (required): length of "
              "leg2 from the fold line to its end",
              1.0, Range::positive())
      .number("mesh.width",
              "rectangular_plate (required): width along y; l_plate (required): width of both strips; folded_plate "
              "(required): width of both legs along y (the fold line)",
              1.0, Range::positive())
      .number("mesh.radius", "cylinder, spherical_cap (required): the radius; annulus (required): the outer radius", 1.0,
              Range::positive())
      .number("mesh.inner_radius", "annulus: the inner radius; 0 = a disk (no hole)", 0.0, Range::non_negative())
      .number("mesh.start_angle", "cylinder, annulus, spherical_cap: azimuth where the surface starts", 0.0, {}, "deg")
      .number("mesh.end_angle",
              "cylinder, annulus, spherical_cap: azimuth where it ends, above start_angle; a 360 degree range "
              "closes the surface (its seam nodes are merged) unless mesh.slit",
              360.0, {}, "deg")
      .boolean("mesh.slit",
               "cylinder, annulus over 360 degrees: keep the seam open as two coincident lips (separate nodes: edges "
               "start_angle and end_angle)",
               false)
      .number("mesh.polar_start",
              "spherical_cap: polar angle (from the pole, mesh.axis) of the hole's edge; 0 = closed at the pole (a "
              "pole-free core + ring mesh)",
              0.0, Range::right_open(0.0, 180.0), "deg")
      .number("mesh.polar_end", "spherical_cap (required): polar angle of the rim (90 = hemisphere)", 90.0,
              Range::open(0.0, 180.0), "deg")
      .number("mesh.fold_angle",
              "folded_plate: how far leg2 turns up (towards +z) from leg1's continuation: 0 = flat, 90 = upright",
              90.0, Range::open(-180.0, 180.0), "deg")
      .string("mesh.file", "generator = file: OBJ or PLY quad mesh, relative to the scene file", std::string{})
      .number("mesh.weld_tolerance",
              "generator = file: join vertices closer than this length (0: every vertex of the file is a node of its "
              "own, so a slit written with separate vertices stays open)",
              0.0, Range::non_negative(), "length");
}

bool mesh_from_file(const Document& d) {
  const std::string& gen = d.string("mesh.generator");
  // generator = "file" without mesh.file: the reader's "needs mesh.file" comes first
  if (gen == "file" && d.string("mesh.file").empty()) return true;
  check_keys(d, gen);
  return gen == "file";
}

void check_thickness_against_radius(const Document& d, const std::string& thickness_key) {
  const std::string& gen = d.string("mesh.generator");
  if (gen != "cylinder" && gen != "spherical_cap") return;
  const double h = d.number(thickness_key), r = d.number("mesh.radius");
  if (h < r) return;
  const std::string m = "a shell " + g(h) + " thick on a " + (gen == "cylinder" ? "cylinder" : "sphere") +
                        " of radius " + g(r) + " is thicker than its radius of curvature (its inner face would lie at " +
                        g(r - h / 2) + " from the " + (gen == "cylinder" ? "axis" : "centre") +
                        "); a shell must be thinner than its radius: lower " + thickness_key + " or raise mesh.radius";
  // either key may be the one to change: both lines are named
  throw SceneError({d.issue(thickness_key, m), d.issue("mesh.radius", m)});
}

namespace {
// nodes of generator `gen` with these counts (mesh::*_node_count, the generators' own merging);
// keys the generator would refuse (an O-grid span that is not 90, 180 or 360 degrees) count as
// an open patch, and the generator then refuses them
long long node_count(const Document& d, const std::string& gen, int n1, int n2, int n3) {
  const auto span_is = [&](double degrees) {
    return std::abs(std::abs(d.number("mesh.end_angle") - d.number("mesh.start_angle")) - degrees) <= 1e-9 * 360.0;
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
  if (gen == "cylinder") return mesh::patch_node_count(n1, n2, full_turn && !d.boolean("mesh.slit") && n1 > 1, false);
  if (gen == "annulus") {
    if (d.number("mesh.inner_radius") == 0.0 && !d.boolean("mesh.slit")) return o_grid(n1, n2);
    return mesh::patch_node_count(n1, n2, false, full_turn && !d.boolean("mesh.slit") && n2 > 1);
  }
  if (gen == "spherical_cap") {
    if (d.number("mesh.polar_start") == 0.0) return o_grid(n1, n2);
    return mesh::patch_node_count(n1, n2, false, full_turn && n2 > 1);
  }
  return 0;
}
}  // namespace

GeneratedMeshSize generated_mesh_size(const Document& d) {
  const std::string& gen = d.string("mesh.generator");
  const int n1 = count(d, "n1"), n2 = count(d, "n2"), n3 = count(d, "n3");
  GeneratedMeshSize size;
  size.nodes = node_count(d, gen, n1, n2, n3);
  size.key = "mesh.generator";
  long long smallest = size.nodes;
  const std::vector<std::string> keys = gen == "folded_plate" ? std::vector<std::string>{"n1", "n2", "n3"}
                                                              : std::vector<std::string>{"n1", "n2"};
  for (const std::string& k : keys) {
    if (!d.present("mesh." + k)) continue;
    // n3 = 0 follows n1, so n1 then sizes both legs
    const long long without = node_count(d, gen, k == "n1" ? 1 : n1, k == "n2" ? 1 : n2, k == "n3" ? 1 : n3);
    if (size.key == "mesh.generator" || without < smallest) smallest = without, size.key = "mesh." + k;
  }
  return size;
}

mesh::ShellMesh generate_mesh(const Document& d) {
  const std::string& gen = d.string("mesh.generator");
  check_keys(d, gen);
  // ranges first (their own messages), then the element shapes they give, at the key at fault
  if (gen == "cylinder" || gen == "annulus" || gen == "spherical_cap") azimuth(d, gen != "spherical_cap");
  if (gen == "spherical_cap") check_polar_range(d);
  check_element_shapes(d, gen);
  try {
    return build(d, gen);
  } catch (const std::invalid_argument& e) {
    throw SceneError({d.issue("mesh.generator", e.what())});
  }
}

}  // namespace ff::scene
