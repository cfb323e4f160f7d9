#include "core/scene/structure_parts.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <numeric>
#include <sstream>
#include <unordered_map>

#include "core/scene/mesh_file.h"
#include "core/scene/mesh_generator_keys.h"
#include "core/shell/shell_model.h"

namespace ff::scene {

namespace fs = std::filesystem;

void declare_structure_keys(Schema& s) {
  s.table_array("material",
                "what the parts are made of: St. Venant-Kirchhoff, plane stress (sigma33 = 0), small strain and "
                "large rotation; isotropic (youngs_modulus, poisson_ratio) or orthotropic (e1, e2, g12, g13, g23, "
                "nu12: a ply, axis 1 along the fibre); with thickness, the shell's whole section, or without, a ply "
                "of a [[layup]] (one form for every part and every analysis)",
                1, 64)
      .string("material.name", "its name, for part.material and layup.plies; \"\" is allowed when the scene has one material",
              std::string{})
      // "0 = not given": the two forms exclude each other, so neither can be required by the schema
      .number("material.youngs_modulus", "E, isotropic (required unless the orthotropic e1 ... nu12 are given; 0 = not given); "
              "every modulus lies in [1e-100, 1e100]",
              0.0, Range::non_negative())
      .number("material.poisson_ratio", "nu, isotropic (not with e1 ... nu12)", 0.3, Range::right_open(0.0, 0.5))
      .number("material.e1", "orthotropic: E1, the modulus along the fibre (give all of e1, e2, g12, g13, g23, nu12; 0 = not given); "
              "the five moduli within a factor 1e6 of each other",
              0.0, Range::non_negative())
      .number("material.e2", "orthotropic: E2, the modulus across the fibre in the ply's plane (0 = not given)", 0.0,
              Range::non_negative())
      .number("material.g12", "orthotropic: G12, the in-plane shear modulus (0 = not given)", 0.0, Range::non_negative())
      .number("material.g13", "orthotropic: G13, the transverse shear modulus in the fibre's plane (0 = not given)", 0.0,
              Range::non_negative())
      .number("material.g23", "orthotropic: G23, the transverse shear modulus across the fibre (0 = not given)", 0.0,
              Range::non_negative())
      .number("material.nu12",
              "orthotropic: nu12, strain across over strain along the fibre; nu21 = nu12 e2 / e1, and 1 - nu12 nu21 must "
              "be > 0 (a stable ply)",
              0.0)
      .number("material.strength_xt", "Tsai-Wu failure index: tensile strength along the fibre (give all five strengths or none; 0 = not given)",
              0.0, Range::non_negative())
      .number("material.strength_xc", "Tsai-Wu: compressive strength along the fibre, a positive number (0 = not given)", 0.0,
              Range::non_negative())
      .number("material.strength_yt", "Tsai-Wu: tensile strength across the fibre (0 = not given)", 0.0, Range::non_negative())
      .number("material.strength_yc", "Tsai-Wu: compressive strength across the fibre, a positive number (0 = not given)", 0.0,
              Range::non_negative())
      .number("material.strength_s12", "Tsai-Wu: in-plane shear strength (0 = not given)", 0.0, Range::non_negative())
      .number("material.thickness",
              "h0, the shell's thickness: required for a material a part is made of (part.material); not given for a "
              "ply of a [[layup]], whose ply_thicknesses set it (0 = not given). Between 1e-6 x the part's longest "
              "element edge and the part's size",
              0.0, Range::non_negative())
      .number("material.shear_factor", "transverse shear correction factor", 5.0 / 6.0, Range::left_open(0.0, 1.0))
      .number("material.drilling_factor", "effect drilling: c in the drilling penalty gamma = c G h0", 1e-3,
              Range::left_open(0.0, 1e3))
      .number("material.density",
              "mass per unit volume rho; a dynamic analysis needs it, and a static one with the effect gravity "
              "(0 = not given)",
              0.0, Range::non_negative());
  s.table_array("layup",
                "a laminated section: plies of [[material]]s stacked from the bottom (the directors' negative side) up, "
                "each with its thickness and its fibre angle from the part's part.fibre_reference (core/shell/laminate.md)",
                0, 64)
      .string("layup.name", "its name, for part.layup (not a material's name)", std::nullopt)
      .string_list("layup.plies", "the material of each ply, by name, bottom ply first (at most 64 plies)", std::nullopt)
      .number_list("layup.ply_thicknesses", "each ply's thickness (> 0), in the order of layup.plies; the section's "
                   "thickness is their sum",
                   std::nullopt, {}, 0, SIZE_MAX, "length")
      .number_list("layup.ply_angles",
                   "each ply's fibre angle, in the order of layup.plies: from the part's fibre reference direction to "
                   "the fibre, right-handed about the director; within one turn either way (an angle beyond it, "
                   "720 or 1e300, is a slip, not a direction)",
                   std::nullopt, Range::closed(-360.0, 360.0), 0, SIZE_MAX, "deg")
      .number("layup.shear_factor", "transverse shear correction factor of the section (laminate.md (L9))", 5.0 / 6.0,
              Range::left_open(0.0, 1.0))
      .number("layup.drilling_factor", "effect drilling: c in the drilling penalty gamma = c G h0", 1e-3,
              Range::left_open(0.0, 1e3));
  declare_part_keys(s);
  s.table_array("junction",
                "parts that share their nodes where their edges coincide (a T, a stiffener, two panels meeting at a "
                "line): coincident nodes of the listed parts become one node, with 6 DoF where the parts' directors "
                "differ (a fold)",
                0, 64)
      .string_list("junction.parts", "the names of the parts joined (two or more)", std::nullopt)
      .number("junction.tolerance",
              "nodes of different parts closer than this are one node; 0 = automatic (1e-6 x the shortest element "
              "edge of the joined parts)",
              0.0, Range::non_negative(), "length");
  // a structure is written in any consistent units: these say which kind of quantity each is
  for (const char* k : {"youngs_modulus", "e1", "e2", "g12", "g13", "g23", "strength_xt", "strength_xc", "strength_yt",
                        "strength_yc", "strength_s12"})
    s.unit_of(std::string("material.") + k, "force/length^2");
  s.unit_of("material.thickness", "length").unit_of("material.density", "mass/length^3");
  s.unit_of("layup.ply_thicknesses", "length").unit_of("layup.ply_angles", "deg");
}

int Structure::find(const std::string& name) const {
  for (std::size_t p = 0; p < parts.size(); ++p)
    if (parts[p].name == name) return static_cast<int>(p);
  return -1;
}

int Structure::first_quad(int p) const {
  int q = 0;
  for (int k = 0; k < p; ++k) q += parts[k].mesh.quad_count();
  return q;
}

namespace {

std::string g(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

// the name a part goes by: part.name, else the generator's default patch name (one-part scenes
// written before parts had names keep selecting patch "plate", "cylinder", ...)
std::string part_name(const Document& d, std::size_t i, const mesh::ShellMesh* m) {
  const std::string& n = d.string("part.name", i);
  if (!n.empty()) return n;
  if (m && m->patches.size() == 1) return m->patches[0].name;
  return d.string("part.generator", i) + std::to_string(i + 1);
}

// the most nodes whose run fits in `bytes` by the scene's memory estimate (shell::estimated_peak_bytes,
// 5 DoF per node: the least a mesh of that size needs); 0 when the limit is unknown
double most_nodes_within(double bytes) {
  if (!(bytes > 0)) return 0.0;
  long long lo = 0, hi = std::numeric_limits<int>::max();
  while (lo < hi) {  // the largest n with estimated_peak_bytes(n) <= bytes
    const long long mid = lo + (hi - lo + 1) / 2;
    if (shell::estimated_peak_bytes(static_cast<int>(mid), 0.0) <= bytes) lo = mid;
    else hi = mid - 1;
  }
  return static_cast<double>(std::max(lo, 1LL));  // 0 would mean "no bound"
}

// what part i asks of its file
MeshFileRequest file_request(const Document& d, std::size_t i, const std::string& scene_path, const SceneContext& ctx) {
  MeshFileRequest r;
  r.most_nodes = most_nodes_within(ctx.memory_limit_bytes);
  r.path = (fs::path(scene_path).parent_path() / d.string("part.file", i)).string();
  r.weld_tolerance = d.number("part.weld_tolerance", i);
  r.triangles = d.string("part.triangles", i);
  r.crease_angle_deg = d.number("part.crease_angle", i);
  r.group = d.string("part.group", i);
  r.mesh_size = d.number("part.mesh_size", i);
  r.local_size_groups = d.strings("part.local_size_groups", i);
  r.local_sizes = d.numbers("part.local_sizes", i);
  r.time_limit_seconds = d.number("part.mesh_time_limit", i);
  r.keep_faces_apart = d.boolean("part.keep_faces_apart", i);
  r.mesh_pattern = d.string("part.mesh_pattern", i);
  if (r.local_size_groups.size() != r.local_sizes.size())
    throw SceneError({d.issue("part.local_sizes", i,
                              "part.local_sizes has " + std::to_string(r.local_sizes.size()) + " sizes for " +
                                  std::to_string(r.local_size_groups.size()) +
                                  " groups in part.local_size_groups: give one size per group, in the same order")});
  // part.mesh_size caps every element: a local size above it could not be reached
  for (std::size_t k = 0; k < r.local_sizes.size(); ++k)
    if (r.mesh_size > 0 && r.local_sizes[k] > r.mesh_size)
      throw SceneError({d.issue("part.local_sizes", i,
                                "part.local_sizes asks " + g(r.local_sizes[k]) + " at group '" + r.local_size_groups[k] +
                                    "', above part.mesh_size = " + g(r.mesh_size) + ", which caps every element: a "
                                    "local size is finer than the rest")});
  return r;
}

mesh::ShellMesh read_part_file(const Document& d, std::size_t i, const std::string& scene_path, const SceneContext& ctx) {
  const std::string& file = d.string("part.file", i);
  if (file.empty())
    throw SceneError({d.issue("part.generator", i, "generator = \"file\" needs part.file (a mesh or CAD file, "
                                                   "relative to the scene file)")});
  if (!ctx.mesh_reader)
    throw SceneError({d.issue("part.file", i, "this program reads no mesh files (no reader was passed to the scene "
                                              "loader; the flexframe executable passes its assimp importer)")});
  mesh::ShellMesh m;
  MeshFileError error;
  std::vector<std::string> warnings;
  const MeshFileRequest request = file_request(d, i, scene_path, ctx);
  if (!ctx.mesh_reader(request, m, &error, &warnings))
    throw SceneError({d.issue(error.key.empty() ? "part.file" : error.key, i, error.message)});
  if (ctx.warnings)
    for (const std::string& w : warnings) ctx.warnings->push_back(d.issue("part.file", i, w).to_string());
  return m;
}

// directors to the other side: every director and corner director negated, every quad's corner
// order reversed (so it still runs counter-clockwise about its director), frames rebuilt
void flip_directors(mesh::ShellMesh& m) {
  for (Eigen::Vector3d& n : m.normals) n = -n;
  for (auto& c : m.corner_normals) {
    for (Eigen::Vector3d& n : c) n = -n;
    std::swap(c[1], c[3]);
  }
  for (auto& q : m.quads) std::swap(q[1], q[3]);
  mesh::compute_frames(m, m.frame_reference);
}

// union-find over joined node ids
int root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Moduli the element can compute with: its stiffness multiplies a modulus by lengths and strains
// (the lengths kept inside [1e-100, 1e100], mesh_generator_keys.cpp), so a modulus beyond these
// bounds overflows or underflows there (1e308 and 1e-320 ended as "non-finite residual"); no
// material in any consistent unit system comes near them.
constexpr double kSmallestModulus = 1e-100, kLargestModulus = 1e100;
// One ply's moduli within this factor of each other: its stiffness matrix spans their ratio (a
// ratio of 1e6 still leaves 10 of the 16 digits of a double), and real plies stay far inside it
// (high-modulus carbon: E1 / G23 ~ 300)
constexpr double kLargestModulusRatio = 1e6;

// The thinnest ply as a fraction of its section (the thinnest real plies, about 0.02 mm, are
// 1e-3 of a laminate 20 mm thick)
constexpr double kThinnestPly = 1e-6;

// refuses a modulus (material.<name> of entry k) outside [kSmallestModulus, kLargestModulus]
void check_modulus_range(const Document& d, std::size_t k, const std::string& name) {
  const std::string key = "material." + name;
  const double v = d.number(key, k);
  if (!(v >= kSmallestModulus) || !(v <= kLargestModulus))
    throw SceneError({d.issue(key, k, key + " = " + g(v) + " is outside the moduli an element can compute with, [" +
                                          g(kSmallestModulus) + ", " + g(kLargestModulus) +
                                          "]: its stiffness multiplies the modulus by lengths and strains, which must "
                                          "stay inside double precision; give it in the scene's units (e.g. 2.1e11 for "
                                          "steel in Pa, 2.1e5 in N/mm^2)")});
}

// [[material]] k as a ply (laminate.md (L1)-(L2)), thickness and angle left to its use: the
// orthotropic constants checked for a stable ply, an isotropic material as the case E1 = E2 = E,
// G = E / (2 (1 + nu)); Tsai-Wu strengths when given
shell::Ply read_material_ply(const Document& d, std::size_t k) {
  static const char* const kOrthotropic[] = {"e1", "e2", "g12", "g13", "g23", "nu12"};
  static const char* const kStrengths[] = {"strength_xt", "strength_xc", "strength_yt", "strength_yc", "strength_s12"};
  auto key = [](const char* name) { return std::string("material.") + name; };
  // all of a set or none: a partial set is refused at the first key missing from it
  auto all_or_none = [&](const auto& set, const std::string& what) {
    const char* given = nullptr;
    for (const char* name : set)
      if (d.present(key(name), k)) given = name;
    if (!given) return false;
    for (const char* name : set)
      if (!d.present(key(name), k)) {
        std::string list;
        for (const char* n : set) list += (list.empty() ? "" : ", ") + std::string(n);
        throw SceneError({d.issue(key(name), k, what + " needs all of " + list + ": material." + given + " is given, " +
                                                    key(name) + " is missing")});
      }
    return true;
  };
  shell::Ply ply;
  if (all_or_none(kOrthotropic, "an orthotropic material")) {
    for (const char* iso : {"youngs_modulus", "poisson_ratio"})
      if (d.present(key(iso), k))
        throw SceneError({d.issue(key(iso), k, "material." + std::string(iso) + " belongs to an isotropic material; this "
                                                "one is orthotropic (e1, e2, g12, g13, g23, nu12): give one form, not both")});
    static const char* const kModuli[] = {"e1", "e2", "g12", "g13", "g23"};
    for (const char* modulus : kModuli) {
      if (!(d.number(key(modulus), k) > 0))
        throw SceneError({d.issue(key(modulus), k, key(modulus) + " must be > 0: a ply whose modulus is zero has no "
                                                   "stiffness there (laminate.md (L2))")});
      check_modulus_range(d, k, modulus);
    }
    // the moduli within kLargestModulusRatio of each other; refused at the one furthest (in ratio)
    // from their median, the likely slip
    std::vector<std::pair<double, const char*>> moduli;
    for (const char* modulus : kModuli) moduli.emplace_back(d.number(key(modulus), k), modulus);
    std::sort(moduli.begin(), moduli.end());
    const double median = moduli[2].first;
    if (moduli.back().first > kLargestModulusRatio * moduli.front().first) {
      const auto& odd = moduli.back().first / median > median / moduli.front().first ? moduli.back() : moduli.front();
      throw SceneError({d.issue(key(odd.second), k,
                                key(odd.second) + " = " + g(odd.first) + " is " +
                                    g(std::max(odd.first / median, median / odd.first)) + " times " +
                                    (odd.first > median ? "the" : "below the") + " median modulus of the ply (" +
                                    g(median) + "), and its largest and smallest moduli differ by more than the " +
                                    g(kLargestModulusRatio) + " an element's stiffness can span with the precision "
                                    "left for the solution; no real ply comes near it (a unit slip?)")});
    }
    ply.e1 = d.number("material.e1", k), ply.e2 = d.number("material.e2", k);
    ply.g12 = d.number("material.g12", k), ply.g13 = d.number("material.g13", k), ply.g23 = d.number("material.g23", k);
    ply.nu12 = d.number("material.nu12", k);
    // (L2): the plane-stress compliance is positive definite exactly when 1 - nu12 nu21 > 0
    const double nu21 = ply.nu12 * ply.e2 / ply.e1, margin = 1.0 - ply.nu12 * nu21;
    if (!(margin > 0))
      throw SceneError({d.issue("material.nu12", k,
                                "the material is unstable (its strain energy is not positive; laminate.md (L2)): nu12 = " +
                                    g(ply.nu12) + ", nu21 = nu12 e2 / e1 = " + g(nu21) + ", 1 - nu12 nu21 = " + g(margin) +
                                    " must be > 0, i.e. |nu12| < sqrt(e1 / e2) = " + g(std::sqrt(ply.e1 / ply.e2)))});
  } else {
    if (!d.present("material.youngs_modulus", k))
      throw SceneError({d.issue("material.youngs_modulus", k,
                                "a material needs its elastic constants: youngs_modulus (and poisson_ratio, default 0.3) "
                                "for an isotropic one, or e1, e2, g12, g13, g23, nu12 for an orthotropic ply")});
    const double E = d.number("material.youngs_modulus", k), nu = d.number("material.poisson_ratio", k);
    if (!(E > 0)) throw SceneError({d.issue("material.youngs_modulus", k, "youngs_modulus must be > 0")});
    check_modulus_range(d, k, "youngs_modulus");
    ply.e1 = ply.e2 = E;
    ply.g12 = ply.g13 = ply.g23 = E / (2.0 * (1.0 + nu));
    ply.nu12 = nu;
  }
  if (all_or_none(kStrengths, "a Tsai-Wu failure index")) {
    for (std::size_t c = 0; c < 5; ++c) {
      ply.strength[c] = d.number(key(kStrengths[c]), k);
      if (!(ply.strength[c] > 0))
        throw SceneError({d.issue(key(kStrengths[c]), k, key(kStrengths[c]) + " must be > 0 (a strength is a magnitude; "
                                                         "compressive ones too)")});
    }
  }
  if (d.present("material.thickness", k) && !(d.number("material.thickness", k) > 0))
    throw SceneError({d.issue("material.thickness", k, "a thickness must be > 0")});
  ply.density = d.number("material.density", k);
  return ply;
}

// an isotropic ply: the same for every angle and reference direction
bool isotropic(const shell::Ply& p) {
  return p.e1 == p.e2 && p.g12 == p.g13 && p.g13 == p.g23 && p.g12 == p.e1 / (2.0 * (1.0 + p.nu12));
}

// Angles written in radians by mistake: every |angle| <= 2 pi, one at least non-zero, and one
// non-zero angle at least not a whole number of degrees ([0, 1.5708, 0]). Whole small numbers
// ([0, 1, 0], [0, 5, -5]) are plausible degrees and pass silently; radians are then rare.
void warn_radian_angles(const Document& d, std::size_t l, const std::vector<double>& angles, const SceneContext& ctx) {
  bool small = true, nonzero = false, fractional = false;
  for (double a : angles) {
    small = small && std::abs(a) <= 2.0 * std::numbers::pi;
    nonzero = nonzero || a != 0.0;
    fractional = fractional || (a != 0.0 && a != std::round(a));
  }
  if (!(small && nonzero && fractional) || !ctx.warnings) return;
  std::string list;
  double example = 0.0;  // the first angle that is not a whole number of degrees
  for (double a : angles) {
    list += (list.empty() ? "" : ", ") + g(a);
    if (example == 0.0 && a != std::round(a)) example = a;
  }
  ctx.warnings->push_back(d.issue("layup.ply_angles", l,
                                  "ply angles [" + list + "] are read in degrees, but look like radians (all within 2 pi, "
                                  "some not whole degrees): " + g(example) + " rad would be " +
                                      g(example * 180.0 / std::numbers::pi) + " deg; write degrees (90, not 1.5708)")
                              .to_string());
}

// [[layup]] entries: sections appended to s.materials after the [[material]] entries
void read_layups(const Document& d, Structure& s, const std::vector<shell::Ply>& material_ply, const SceneContext& ctx) {
  const std::size_t nm = s.materials_in_file;
  for (std::size_t l = 0; l < d.count("layup"); ++l) {
    StructureMaterial m;
    m.layup = static_cast<int>(l);
    m.name = d.string("layup.name", l);
    for (const StructureMaterial& other : s.materials)
      if (other.name == m.name)
        throw SceneError({d.issue("layup.name", l, std::string(other.layup < 0 ? "a material" : "another layup") +
                                                       " is called '" + m.name + "': a layup needs a name of its own")});
    const std::vector<std::string> names = d.strings("layup.plies", l);
    const std::vector<double> thicknesses = d.numbers("layup.ply_thicknesses", l), angles = d.numbers("layup.ply_angles", l);
    if (names.empty()) throw SceneError({d.issue("layup.plies", l, "a layup needs at least one ply")});
    if (names.size() > static_cast<std::size_t>(shell::kMaxPlies))
      throw SceneError({d.issue("layup.plies", l, "a layup has at most " + std::to_string(shell::kMaxPlies) + " plies; this one has " +
                                                      std::to_string(names.size()))});
    for (const auto& [key, count] : {std::pair<const char*, std::size_t>{"layup.ply_thicknesses", thicknesses.size()},
                                     {"layup.ply_angles", angles.size()}})
      if (count != names.size())
        throw SceneError({d.issue(key, l, std::string(key) + " has " + std::to_string(count) + " entries for the " +
                                              std::to_string(names.size()) + " plies of layup.plies: give one per ply, in "
                                              "the same order (bottom ply first)")});
    std::vector<shell::Ply> plies;
    double thickness = 0.0, mass = 0.0;
    for (std::size_t j = 0; j < names.size(); ++j) {
      int k = -1;
      for (std::size_t c = 0; c < nm; ++c)
        if (s.materials[c].name == names[j]) k = static_cast<int>(c);
      if (k < 0)
        throw SceneError({d.issue("layup.plies", l, "ply " + std::to_string(j + 1) + " of layup '" + m.name +
                                                        "': no [[material]] is called '" + names[j] + "'")});
      if (d.present("material.thickness", k))
        throw SceneError({d.issue("material.thickness", k,
                                  "material '" + names[j] + "' is a ply of layup '" + m.name + "', whose " +
                                      "layup.ply_thicknesses set its thickness: leave thickness out of the material")});
      if (!(thicknesses[j] > 0))
        throw SceneError({d.issue("layup.ply_thicknesses", l,
                                  "entry " + std::to_string(j + 1) + " (ply '" + names[j] + "', counting from 1 at the bottom) is " +
                                      g(thicknesses[j]) + ": every ply needs a thickness > 0")});
      shell::Ply ply = material_ply[k];
      ply.thickness = thicknesses[j];
      ply.angle = angles[j] * std::numbers::pi / 180.0;  // exact for 90 -> pi/2, as the generators' angles
      if (!(ply.density > 0) && m.ply_without_density < 0) m.ply_without_density = k;
      thickness += ply.thickness, mass += ply.density * ply.thickness;
      plies.push_back(ply);
    }
    if (!std::isfinite(thickness))
      throw SceneError({d.issue("layup.ply_thicknesses", l, "the plies' thicknesses add up to more than a double holds")});
    // a ply is a layer of the element's thickness coordinate [-1, 1] (laminate.md (L6)): one below
    // kThinnestPly of the section is lost in its round-off (1e-300 beside 4.2 ended "non-finite
    // residual" at the first step), and no laminate has one
    for (std::size_t j = 0; j < thicknesses.size(); ++j)
      if (thicknesses[j] < kThinnestPly * thickness)
        throw SceneError({d.issue("layup.ply_thicknesses", l,
                                  "entry " + std::to_string(j + 1) + " (ply '" + names[j] + "', counting from 1 at the "
                                  "bottom) is " + g(thicknesses[j]) + ", less than " + g(kThinnestPly) + " of the "
                                  "section's " + g(thickness) + ": a ply that thin is lost in the round-off of the "
                                  "element's thickness coordinate; leave it out of the layup")});
    warn_radian_angles(d, l, angles, ctx);
    // youngs_modulus and poisson_ratio of a laminated section only name it in messages: the
    // element takes the plies (laminate.md); they are the bottom ply's e1 and nu12
    m.section.youngs_modulus = plies.front().e1;
    m.section.poisson_ratio = plies.front().nu12;
    m.section.thickness = thickness;
    m.section.shear_factor = d.number("layup.shear_factor", l);
    m.section.plies = std::make_shared<const std::vector<shell::Ply>>(std::move(plies));
    m.drilling_factor = d.number("layup.drilling_factor", l);
    // the section's mass per area over its thickness (laminate.md (L10)'s translational term)
    m.density = mass / thickness;
    s.materials.push_back(std::move(m));
  }
}

// The direction part i's ply angles are measured from, per quad of its mesh (laminate.md
// section 2): part.fibre_reference u or v, the generator's grid direction at each quad's centre
// (from the patch grid, since a patch may run its quads' corners either way round), or for a file
// part the quad's edge from corner 0 to 1 (u) or 0 to 3 (v); vector: part.fibre_vector, refused
// where it is parallel to a quad's normal.
std::vector<Eigen::Vector3d> fibre_reference_directions(const Document& d, std::size_t i, const StructurePart& p,
                                                        const StructureMaterial& material) {
  const std::string& reference = d.string("part.fibre_reference", i);
  const mesh::ShellMesh& m = p.mesh;
  const int nq = m.quad_count();
  if (reference != "vector" && d.present("part.fibre_vector", i))
    throw SceneError({d.issue("part.fibre_vector", i, "part.fibre_vector belongs to fibre_reference = \"vector\"; this "
                                                      "part's fibre_reference = \"" + reference + "\" would ignore it")});
  bool orthotropic = false;
  if (material.section.plies)
    for (const shell::Ply& ply : *material.section.plies) orthotropic = orthotropic || !isotropic(ply);
  // no default for orthotropic plies: u or v of a generator is a different direction on each
  // surface (around a cylinder's arc, along a plate's x), and the wrong one swaps a [0/90/0]
  // layup into [90/0/90] without a word (docs/validation/laminates.md, the roof's two readings)
  if (orthotropic && !p.from_file && !d.present("part.fibre_reference", i)) {
    const std::string generator = d.string("part.generator", i);
    throw SceneError({d.issue(
        "part.fibre_reference", i,
        "part '" + p.name + "' is made of orthotropic plies (" +
            (material.layup >= 0 ? "layup '" + material.name + "'"
             : material.name.empty() ? std::string("the scene's material")
                                     : "material '" + material.name + "'") +
            "), whose angles are measured from a direction the part must choose; there is no "
            "default. On generator = \"" + generator + "\": " + generator_grid_directions(generator) +
            ". Give fibre_reference = \"u\" or \"v\" (0 degrees along that grid direction), or \"vector\" with "
            "part.fibre_vector = [x, y, z] (a world direction projected on each element)")});
  }
  if (p.from_file && orthotropic && reference != "vector")
    throw SceneError({d.issue("part.fibre_reference", i,
                              "a file part has no u and v grid (\"" + reference + "\" would be each element's own edge, "
                              "turning from element to element), and this part's plies are orthotropic: give "
                              "fibre_reference = \"vector\" and part.fibre_vector")});
  std::vector<Eigen::Vector3d> out(static_cast<std::size_t>(nq), Eigen::Vector3d::Zero());
  if (reference == "vector") {
    if (!d.present("part.fibre_vector", i))
      throw SceneError({d.issue("part.fibre_reference", i, "fibre_reference = \"vector\" needs part.fibre_vector = [x, y, z]")});
    const std::vector<double> v = d.numbers("part.fibre_vector", i);
    if (v.size() != 3)
      throw SceneError({d.issue("part.fibre_vector", i, "a vector has three components [x, y, z]; this one has " +
                                                        std::to_string(v.size()))});
    const Eigen::Vector3d r(v[0], v[1], v[2]);
    if (!(r.norm() > 0)) throw SceneError({d.issue("part.fibre_vector", i, "the direction is the zero vector")});
    for (int q = 0; q < nq; ++q) {
      const auto& c = m.quads[q];
      const Eigen::Vector3d n = (m.points[c[2]] - m.points[c[0]]).cross(m.points[c[3]] - m.points[c[1]]).normalized();
      if (r.cross(n).norm() < 1e-3 * r.norm()) {
        const Eigen::Vector3d x = 0.25 * (m.points[c[0]] + m.points[c[1]] + m.points[c[2]] + m.points[c[3]]);
        throw SceneError({d.issue("part.fibre_vector", i,
                                  "part.fibre_vector is parallel to the normal of quad " + std::to_string(q) + " of part '" +
                                      p.name + "' at (" + g(x.x()) + ", " + g(x.y()) + ", " + g(x.z()) +
                                      "): it has no direction in that element's surface to measure ply angles from; give "
                                      "a vector across the surface, or fibre_reference = \"u\" or \"v\"")});
      }
      out[q] = r;
    }
    return out;
  }
  const bool along_u = reference == "u";
  if (p.from_file) {
    for (int q = 0; q < nq; ++q) {
      const auto& c = m.quads[q];
      out[q] = (m.points[c[along_u ? 1 : 3]] - m.points[c[0]]).normalized();
    }
    return out;
  }
  // a generated patch's quad (i, j) is its quad first_quad + j nu + i, on grid nodes (i..i+1, j..j+1)
  std::vector<char> done(static_cast<std::size_t>(nq), 0);
  for (const mesh::Patch& patch : m.patches) {
    if (patch.nu <= 0 || patch.nv <= 0 || patch.quad_count != patch.nu * patch.nv ||
        patch.grid.size() != static_cast<std::size_t>((patch.nu + 1) * (patch.nv + 1)))
      continue;
    auto at = [&](int a, int b) { return m.points[patch.grid[static_cast<std::size_t>(b * (patch.nu + 1) + a)]]; };
    for (int b = 0; b < patch.nv; ++b)
      for (int a = 0; a < patch.nu; ++a) {
        const int q = patch.first_quad + b * patch.nu + a;
        // the mean of the two opposite edges: the grid direction at the quad's centre
        const Eigen::Vector3d dir = along_u ? (at(a + 1, b) - at(a, b)) + (at(a + 1, b + 1) - at(a, b + 1))
                                            : (at(a, b + 1) - at(a, b)) + (at(a + 1, b + 1) - at(a + 1, b));
        out[q] = dir.normalized();
        done[q] = 1;
      }
  }
  for (int q = 0; q < nq; ++q)
    if (!done[q])  // every generator's patches carry their grids (tests/unit/test_layup_input.cpp)
      throw std::logic_error("part '" + p.name + "': quad " + std::to_string(q) + " lies on no patch grid");
  return out;
}

}  // namespace

Issue thickness_issue(const Document& d, const Structure& s, int section, const std::string& message) {
  const StructureMaterial& m = s.materials.at(static_cast<std::size_t>(section));
  if (m.layup >= 0) return d.issue("layup.ply_thicknesses", static_cast<std::size_t>(m.layup), message);
  return d.issue("material.thickness", static_cast<std::size_t>(section), message);
}

namespace {
// where material k's density is or would be written
Issue material_density_issue(const Document& d, std::size_t k, const std::string& message) {
  return d.issue(d.present("material.density", k)          ? "material.density"
                 : d.present("material.youngs_modulus", k) ? "material.youngs_modulus"
                 : d.present("material.e1", k)             ? "material.e1"
                                                           : "material.density",
                 k, message);
}
}  // namespace

Issue density_issue(const Document& d, const Structure& s, int section, const std::string& message) {
  const StructureMaterial& m = s.materials.at(static_cast<std::size_t>(section));
  if (m.layup < 0) return material_density_issue(d, static_cast<std::size_t>(section), message);
  const int k = m.ply_without_density >= 0 ? m.ply_without_density : 0;
  return material_density_issue(d, static_cast<std::size_t>(k), message);
}

void require_density(const Document& d, const Structure& s, std::size_t p, const std::string& message) {
  const StructurePart& part = s.parts.at(p);
  const StructureMaterial& m = s.materials.at(static_cast<std::size_t>(part.material));
  if (m.layup < 0) {
    if (!(m.density > 0)) throw SceneError({density_issue(d, s, part.material, message)});
    return;
  }
  if (m.ply_without_density < 0) return;
  const std::string& ply = s.materials[static_cast<std::size_t>(m.ply_without_density)].name;
  throw SceneError({density_issue(d, s, part.material,
                                  message + " (part '" + part.name + "' is made of layup '" + m.name + "', whose ply material '" +
                                      ply + "' has no material.density: every ply needs one, the section's mass is their "
                                      "thickness-weighted sum)")});
}

StructureSize structure_size(const Document& d, const std::string& scene_path, const SceneContext& ctx) {
  StructureSize size;
  long long largest = -1;
  for (std::size_t i = 0; i < d.count("part"); ++i) {
    long long nodes = 0;
    std::string key = "part.file";
    if (!mesh_from_file(d, i)) {
      const GeneratedMeshSize g = generated_mesh_size(d, i);
      nodes = g.nodes, key = g.key;
    } else if (ctx.mesh_reader && !d.string("part.file", i).empty()) {
      mesh::ShellMesh m;
      MeshFileError error;
      if (ctx.mesh_reader(file_request(d, i, scene_path, ctx), m, &error, nullptr))
        nodes = m.node_count();
    }
    size.nodes += nodes;
    if (nodes > largest) largest = nodes, size.key = key, size.part = static_cast<int>(i);
  }
  return size;
}

double estimated_structure_bytes(const Document& d, const std::string& scene_path, const SceneContext& ctx) {
  const std::vector<std::string> fx = d.strings("scene.effects");
  const bool drilling = std::find(fx.begin(), fx.end(), "drilling") != fx.end();
  const long long nodes = structure_size(d, scene_path, ctx).nodes;
  return nodes > 0 ? shell::estimated_peak_bytes(static_cast<int>(std::min<long long>(nodes, std::numeric_limits<int>::max())),
                                                 drilling ? 1.0 : 0.0)
                   : 0.0;
}

namespace {
// An element more than this many times as long as its shell is thick: its bending stiffness (h^3)
// drowns in the round-off of its membrane stiffness (h), the ratio squared being beyond the digits
// a double keeps (16 x 16 elements of 0.0625 on a plate 1e-8 thick: "singular matrix" at the first
// step; 1e-7 thick still factorizes). No shell's elements come near it.
constexpr double kLargestSlenderness = 1e6;

// Refuses, at the key that sets its thickness, a section too thin for part p's elements
// (kLargestSlenderness) or thicker than the part is large (its bounding box's diagonal): no shell
void check_thickness_against_part(const Document& d, const Structure& s, const StructurePart& p) {
  if (p.mesh.points.empty()) return;  // a mesh without nodes is refused where it is read
  const double h = s.materials[static_cast<std::size_t>(p.material)].section.thickness;
  const double longest = mesh::max_edge_length(p.mesh);
  Eigen::Vector3d lo = p.mesh.points.front(), hi = lo;
  for (const Eigen::Vector3d& x : p.mesh.points) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double size = (hi - lo).norm();
  if (longest <= kLargestSlenderness * h && h <= size) return;
  throw SceneError({thickness_issue(
      d, s, p.material,
      "a section " + g(h) + " thick on part '" + p.name + "' (elements up to " + g(longest) + " long, the part " + g(size) +
          " across): " +
          (h > size ? std::string("a shell thicker than the part is large is no shell")
                    : "its elements are more than " + g(kLargestSlenderness) +
                          " times as long as it is thick, where the bending stiffness (h^3) is lost in the round-off "
                          "of the membrane stiffness (h)") +
          "; the thickness must lie in [" + g(longest / kLargestSlenderness) + ", " + g(size) +
          "] for this part (a thickness in the scene's length unit?)")});
}
// [[material]]: names unique, a nameless one only when it is the only one; returns each
// material as a ply (no thickness, angle 0) for the layups
std::vector<shell::Ply> read_materials(const Document& d, Structure& s) {
  const std::size_t nm = d.count("material");
  s.materials_in_file = nm;
  std::vector<shell::Ply> material_ply(nm);  // each material as a ply (no thickness, angle 0)
  for (std::size_t k = 0; k < nm; ++k) {
    StructureMaterial m;
    m.name = d.string("material.name", k);
    if (m.name.empty() && nm > 1)
      throw SceneError({d.issue("material.name", k, "the scene has " + std::to_string(nm) +
                                                        " materials: each needs a name for part.material to use")});
    for (const StructureMaterial& other : s.materials)
      if (other.name == m.name) throw SceneError({d.issue("material.name", k, "another material is called '" + m.name + "'")});
    material_ply[k] = read_material_ply(d, k);
    const shell::Ply& ply = material_ply[k];
    const bool orthotropic = d.present("material.e1", k);
    m.section.youngs_modulus = orthotropic ? ply.e1 : d.number("material.youngs_modulus", k);
    m.section.poisson_ratio = orthotropic ? ply.nu12 : d.number("material.poisson_ratio", k);
    m.section.thickness = d.number("material.thickness", k);  // 0 for a ply's material
    m.section.shear_factor = d.number("material.shear_factor", k);
    // an orthotropic material, or one with strengths (a failure index per ply), is a section of
    // one ply at angle 0; an isotropic one keeps the one-layer section (plies null) it always had
    if (orthotropic || d.present("material.strength_xt", k)) {
      shell::Ply whole = ply;
      whole.thickness = m.section.thickness;
      m.section.plies = std::make_shared<const std::vector<shell::Ply>>(1, whole);
    }
    m.drilling_factor = d.number("material.drilling_factor", k);
    m.density = d.number("material.density", k);
    // a density this small makes a mass matrix whose products underflow to zero (5e-324 gave a
    // zero pivot in the initial accelerations): not a material, a typo or a unit slip
    if (m.density > 0 && m.density < 1e-100)
      throw SceneError({d.issue("material.density", k,
                                "a density of " + g(m.density) + " is too small to make a mass matrix (its products with "
                                "the element's lengths underflow to zero); give it in the scene's units, e.g. 7850 for "
                                "steel in kg/m^3, or leave it out of a static analysis")});
    // and one this large overflows them (1e308 ended a modal analysis in a failed eigen decomposition)
    if (m.density > 1e100)
      throw SceneError({d.issue("material.density", k,
                                "a density of " + g(m.density) + " is too large to make a mass matrix (its products with "
                                "the element's lengths overflow); give it in the scene's units, e.g. 7850 for steel in "
                                "kg/m^3")});
    s.materials.push_back(m);
  }
  return material_ply;
}

// [[part]]: each part's section (a material or a layup, marked used), its mesh (generated or
// read), its name and directors; true when a part chose the reference of its fibre angles
bool read_parts(const Document& d, const std::string& scene_path, const SceneContext& ctx, Structure& s,
                std::vector<char>& material_used) {
  bool any_reference_key = false;
  const std::size_t nm = d.count("material"), nl = d.count("layup"), np = d.count("part");
  for (std::size_t i = 0; i < np; ++i) {
    StructurePart p;
    const std::string& material = d.string("part.material", i);
    const std::string& layup = d.string("part.layup", i);
    p.material = -1;
    if (d.present("part.layup", i)) {
      if (d.present("part.material", i))
        throw SceneError({d.issue("part.layup", i, "a part is made of one section: part.material = '" + material +
                                                       "' or part.layup = '" + layup + "', not both")});
      for (std::size_t l = 0; l < nl; ++l)
        if (s.materials[nm + l].name == layup) p.material = static_cast<int>(nm + l);
      if (p.material < 0) throw SceneError({d.issue("part.layup", i, "no [[layup]] is called '" + layup + "'")});
    } else if (material.empty()) {
      if (nm > 1)
        throw SceneError({d.issue("part.material", i, "the scene has " + std::to_string(nm) +
                                                          " materials: say which one this part is made of (part.material, "
                                                          "or part.layup for a laminated section)")});
      p.material = 0;
    } else {
      for (std::size_t k = 0; k < nm; ++k)
        if (s.materials[k].name == material) p.material = static_cast<int>(k);
      if (p.material < 0) throw SceneError({d.issue("part.material", i, "no [[material]] is called '" + material + "'")});
    }
    material_used[p.material] = 1;
    // a material a part is made of directly is the whole section: it needs its thickness
    if (p.material < static_cast<int>(nm) && !d.present("material.thickness", p.material))
      throw SceneError({d.issue("material.thickness", p.material,
                                "part " + std::to_string(i + 1) + " is made of material '" + s.materials[p.material].name +
                                    "' directly, so the material needs its thickness (or make the part of a [[layup]] "
                                    "of it with part.layup)")});
    const double thickness = s.materials[p.material].section.thickness;
    p.from_file = mesh_from_file(d, i);
    if (p.from_file) {
      try {
        p.mesh = read_part_file(d, i, scene_path, ctx);
      } catch (const std::invalid_argument& e) {
        throw SceneError({d.issue("part.generator", i, e.what())});
      }
    } else {
      p.mesh = generate_mesh(d, i);
      if (p.material < static_cast<int>(nm))
        check_thickness_against_radius(d, i, thickness, "material.thickness", static_cast<std::size_t>(p.material));
      else
        check_thickness_against_radius(d, i, thickness, "layup.ply_thicknesses", static_cast<std::size_t>(p.material) - nm);
    }
    p.name = part_name(d, i, &p.mesh);
    check_thickness_against_part(d, s, p);
    if (d.boolean("part.flip_director", i)) flip_directors(p.mesh);
    if (s.find(p.name) >= 0)
      throw SceneError({d.issue(d.present("part.name", i) ? "part.name" : "part.generator", i,
                                "another part is called '" + p.name + "'" +
                                    (d.present("part.name", i) ? "" : " (the generator's default name): give part.name"))});
    // a patch name selects nodes across the whole structure: one patch of one part per name
    for (const mesh::Patch& patch : p.mesh.patches)
      for (const StructurePart& other : s.parts)
        if (other.mesh.find_patch(patch.name) >= 0)
          throw SceneError({d.issue(d.present("part.name", i) ? "part.name" : "part.generator", i,
                                    "this part's patch '" + patch.name + "' has the name of a patch of part '" +
                                        other.name + "', so select = \"patch_edge\" could not tell them apart; " +
                                        (p.mesh.patches.size() > 1
                                             ? std::string("l_plate and folded_plate name their patches themselves "
                                                           "(arm1, corner, arm2; leg1, leg2), so a structure holds one "
                                                           "of each")
                                             : std::string("give the part a name of its own")))});
    p.reference_direction = fibre_reference_directions(d, i, p, s.materials[p.material]);
    any_reference_key = any_reference_key || d.present("part.fibre_reference", i) || d.present("part.fibre_vector", i);
    s.parts.push_back(std::move(p));
  }
  return any_reference_key;
}

}  // namespace

Structure read_structure(const Document& d, const std::string& scene_path, const SceneContext& ctx) {
  Structure s;
  const std::size_t nm = d.count("material");
  const std::vector<shell::Ply> material_ply = read_materials(d, s);
  read_layups(d, s, material_ply, ctx);
  const std::size_t nl = d.count("layup");
  std::vector<char> material_used(nm + nl, 0);
  const std::size_t np = d.count("part");
  const bool any_reference_key = read_parts(d, scene_path, ctx, s, material_used);
  // a material used only as a ply is used; a [[layup]] no part is made of is refused like a material
  for (std::size_t l = 0; l < nl; ++l)
    for (const std::string& ply : d.strings("layup.plies", l))
      for (std::size_t k = 0; k < nm; ++k)
        if (s.materials[k].name == ply && !material_used[k]) material_used[k] = 2;
  for (std::size_t k = 0; k < nm; ++k)
    if (!material_used[k])
      throw SceneError({d.issue(d.present("material.name", k)           ? "material.name"
                                : d.present("material.youngs_modulus", k) ? "material.youngs_modulus"
                                                                          : "material.e1",
                                k, "no part is made of material '" + s.materials[k].name + "'")});
  for (std::size_t l = 0; l < nl; ++l)
    if (!material_used[nm + l])
      throw SceneError({d.issue("layup.name", l, "no part is made of layup '" + s.materials[nm + l].name +
                                                     "' (part.layup names it)")});
  // per-quad reference directions only where they can matter: a laminated part, or a part that
  // chose its reference (its stresses' axes); otherwise every element keeps its own xi direction
  bool laminated = false;
  for (const StructurePart& p : s.parts) laminated = laminated || s.materials[p.material].section.plies != nullptr;
  if (laminated || any_reference_key)
    for (const StructurePart& p : s.parts)
      s.quad_reference_direction.insert(s.quad_reference_direction.end(), p.reference_direction.begin(),
                                        p.reference_direction.end());

  // every node of every part, in part order; a junction unites coincident nodes of its parts
  std::vector<int> offset;
  int total = 0;
  for (StructurePart& p : s.parts) offset.push_back(total), p.first_node = total, total += p.mesh.node_count();
  std::vector<int> parent(total);
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<int> first_junction(np, -1);
  for (std::size_t j = 0; j < d.count("junction"); ++j) {
    const std::vector<std::string> names = d.strings("junction.parts", j);
    if (names.size() < 2)
      throw SceneError({d.issue("junction.parts", j, "a junction joins two or more parts; it names " +
                                                         std::to_string(names.size()))});
    std::vector<int> members;
    for (const std::string& n : names) {
      const int p = s.find(n);
      if (p < 0) throw SceneError({d.issue("junction.parts", j, "no part is called '" + n + "'")});
      if (std::find(members.begin(), members.end(), p) != members.end())
        throw SceneError({d.issue("junction.parts", j, "part '" + n + "' is named twice")});
      members.push_back(p);
    }
    double h = std::numeric_limits<double>::infinity();
    for (int p : members) h = std::min(h, mesh::min_edge_length(s.parts[p].mesh));
    const double tol = d.number("junction.tolerance", j) > 0 ? d.number("junction.tolerance", j) : 1e-6 * h;
    // every pair of listed parts: coincident nodes united (a hash grid of cell tol)
    struct Key {
      long long x, y, z;
      bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
    };
    struct Hash {
      std::size_t operator()(const Key& k) const {
        return std::hash<long long>()(k.x * 73856093LL ^ k.y * 19349663LL ^ k.z * 83492791LL);
      }
    };
    auto cell = [&](const Eigen::Vector3d& x) {
      return Key{static_cast<long long>(std::floor(x.x() / tol)), static_cast<long long>(std::floor(x.y() / tol)),
                 static_cast<long long>(std::floor(x.z() / tol))};
    };
    std::unordered_map<Key, std::vector<int>, Hash> grid;  // joined ids of the parts before the current one
    int shared = 0;
    for (int p : members) {
      const mesh::ShellMesh& m = s.parts[p].mesh;
      for (int i = 0; i < m.node_count(); ++i) {
        const Key c = cell(m.points[i]);
        for (long long dx = -1; dx <= 1; ++dx)
          for (long long dy = -1; dy <= 1; ++dy)
            for (long long dz = -1; dz <= 1; ++dz) {
              const auto it = grid.find({c.x + dx, c.y + dy, c.z + dz});
              if (it == grid.end()) continue;
              for (int other : it->second) {
                int q = 0;
                while (q + 1 < static_cast<int>(np) && offset[q + 1] <= other) ++q;
                const double dist = (s.parts[q].mesh.points[other - offset[q]] - m.points[i]).norm();
                if (dist <= tol) {
                  const int a = root(parent, other), b = root(parent, offset[p] + i);
                  if (a != b) parent[std::max(a, b)] = std::min(a, b), ++shared;
                }
              }
            }
      }
      for (int i = 0; i < m.node_count(); ++i) grid[cell(m.points[i])].push_back(offset[p] + i);
    }
    if (shared == 0)
      throw SceneError({d.issue("junction.parts", j, "the parts named share no node (none closer than " + g(tol) +
                                                         "): a junction joins parts whose edges coincide; give "
                                                         "junction.tolerance, or connect them with a [[joint]]")});
    for (int p : members)
      if (first_junction[p] < 0) first_junction[p] = static_cast<int>(j);
    s.has_junctions = true;
  }

  if (!s.has_junctions && np == 1) {
    s.joined = s.parts[0].mesh;
    s.parts[0].node_map.resize(s.joined.node_count());
    std::iota(s.parts[0].node_map.begin(), s.parts[0].node_map.end(), 0);
    s.quad_part.assign(s.joined.quad_count(), 0);
    return s;
  }
  // joined ids in order of first appearance; the first part's node keeps its director and frame,
  // a later one whose director differs makes it a fold node (each quad keeps its own director)
  mesh::ShellMesh& out = s.joined;
  std::vector<int> new_id(total, -1);
  for (std::size_t p = 0; p < np; ++p) {
    StructurePart& part = s.parts[p];
    const mesh::ShellMesh& m = part.mesh;
    part.node_map.resize(m.node_count());
    for (int i = 0; i < m.node_count(); ++i) {
      const int r = root(parent, offset[p] + i);
      if (new_id[r] < 0) {
        new_id[r] = out.node_count();
        out.points.push_back(m.points[i]);
        out.normals.push_back(m.normals[i]);
        out.frames.push_back(m.frames[i]);
        out.fold.push_back(i < static_cast<int>(m.fold.size()) ? m.fold[i] : 0);
      } else {
        const int n = new_id[r];
        const double cosine = std::clamp(out.normals[n].dot(m.normals[i]), -1.0, 1.0);
        if (std::acos(cosine) > 1e-6) out.fold[n] = 1;
      }
      part.node_map[i] = new_id[r];
    }
  }
  for (std::size_t p = 0; p < np; ++p) {
    const mesh::ShellMesh& m = s.parts[p].mesh;
    const int patch_offset = static_cast<int>(out.patches.size()), quad_offset = out.quad_count();
    for (int q = 0; q < m.quad_count(); ++q) {
      std::array<int, 4> c{};
      std::array<Eigen::Vector3d, 4> n;
      for (int k = 0; k < 4; ++k) {
        c[k] = s.parts[p].node_map[m.quads[q][k]];
        n[k] = q < static_cast<int>(m.corner_normals.size()) ? m.corner_normals[q][k] : m.normals[m.quads[q][k]];
      }
      out.quads.push_back(c);
      out.corner_normals.push_back(n);
      out.quad_patch.push_back(patch_offset + (q < static_cast<int>(m.quad_patch.size()) ? m.quad_patch[q] : 0));
      s.quad_part.push_back(static_cast<int>(p));
    }
    for (mesh::Patch patch : m.patches) {
      for (int& id : patch.grid) id = s.parts[p].node_map[id];
      patch.first_quad += quad_offset;
      out.patches.push_back(std::move(patch));
    }
    // a file's named group selects its nodes in every part that has it (parts cut from one file
    // by part.group share the file's curve and point groups)
    for (const mesh::MeshGroup& g : m.groups) {
      int k = out.find_group(g.name);
      if (k < 0) {
        k = static_cast<int>(out.groups.size());
        out.groups.push_back({g.name, g.dimension, {}, {}, g.origin});
      }
      mesh::MeshGroup& joined_group = out.groups[static_cast<std::size_t>(k)];
      for (int id : g.nodes) joined_group.nodes.push_back(s.parts[p].node_map[id]);
      for (int q : g.quads) joined_group.quads.push_back(quad_offset + q);
      std::sort(joined_group.nodes.begin(), joined_group.nodes.end());
      joined_group.nodes.erase(std::unique(joined_group.nodes.begin(), joined_group.nodes.end()), joined_group.nodes.end());
    }
  }
  out.frame_reference = s.parts[0].mesh.frame_reference;
  // the joined parts must turn their directors to one side: a shared edge then runs opposite ways
  // in the two quads that meet on it (core/mesh/README.md convention 1)
  const mesh::MeshCheck check = mesh::validate(out);
  for (const mesh::MeshIssue& issue : check.issues) {
    if (issue.kind != mesh::IssueKind::inconsistent_orientation) continue;
    const int p = issue.quad >= 0 ? s.quad_part[issue.quad] : 0;
    const int j = first_junction[p] >= 0 ? first_junction[p] : 0;
    throw SceneError({d.issue("junction.parts", static_cast<std::size_t>(j),
                              "the joined parts' directors point to opposite sides where they meet (" + issue.message +
                                  "); set part.flip_director = true on one of them")});
  }
  return s;
}

std::vector<std::pair<std::string, std::string>> mesh_import_settings(const Structure& s) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const StructurePart& part : s.parts)
    if (part.from_file && !part.mesh.patches.empty())
      out.emplace_back(s.parts.size() == 1 ? "mesh_import" : "mesh_import_" + part.name, part.mesh.patches[0].description);
  return out;
}

void structure_sections(const Structure& s, std::vector<shell::ShellSection>& sections,
                        std::vector<double>& drilling_factors, std::vector<int>& quad_section) {
  sections.clear(), drilling_factors.clear(), quad_section.clear();
  if (s.materials.size() == 1) return;
  for (const StructureMaterial& m : s.materials) sections.push_back(m.section), drilling_factors.push_back(m.drilling_factor);
  for (int p : s.quad_part) quad_section.push_back(s.parts[p].material);
}

}  // namespace ff::scene
