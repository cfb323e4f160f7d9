#include "core/scene/shell_boundary.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/scene/node_selection.h"

namespace ff::scene {

namespace {
using Vec3 = Eigen::Vector3d;
Vec3 vec(const std::vector<double>& v) { return Vec3(v[0], v[1], v[2]); }

// Loads and prescribed displacements within what the element's products with lengths (at most
// 1e100, mesh_generator_keys.cpp) keep inside double precision: a force of 1e300 or a pressure of
// 1e308 ended "non-finite residual" at the first step, and in dynamics "failed" (exit 1)
const Range kLoadRange = Range::closed(-1e100, 1e100);

// DoF names per frame: three translations, then three rotations, each along axis k of the frame
const std::map<std::string, std::vector<std::string>> kDofNames = {
    {"global", {"ux", "uy", "uz", "rx", "ry", "rz"}},
    {"cylindrical", {"ur", "ut", "ua", "rr", "rt", "ra"}},
    {"node", {"u1", "u2", "u3", "r1", "r2", "r3"}}};

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

// the axes of entry i's frame at node I, world components, as columns
Eigen::Matrix3d frame_axes(const Document& d, std::size_t i, const mesh::ShellMesh& m, int I) {
  const std::string frame = d.string("bc.frame", i);
  if (frame == "global") return Eigen::Matrix3d::Identity();
  if (frame == "node") return m.frames[I];
  // cylindrical: radial (from the axis to the node), tangential = axis x radial, axial
  const Vec3 axis = vec(d.numbers("bc.axis", i));
  // a length that overflows (components near 1e308) would normalize to zero further on
  if (!(axis.norm() > 0) || !axis.allFinite() || !std::isfinite(axis.squaredNorm()))
    throw SceneError({d.issue("bc.axis", i, "the cylinder axis must be a finite non-zero vector whose length stays "
                                            "inside double precision")});
  const Vec3 a = axis.normalized();
  const Vec3 rel = m.points[I] - vec(d.numbers("bc.axis_point", i));
  const Vec3 radial = rel - rel.dot(a) * a;
  if (!(radial.norm() > 1e-9 * std::max(1.0, rel.norm())))
    throw SceneError({d.issue("bc.axis_point", i, "node " + std::to_string(I) + " lies on the cylinder axis, where the "
                                                  "radial direction is undefined")});
  Eigen::Matrix3d T;
  const Vec3 er = radial.normalized();
  T << er, a.cross(er), a;
  return T;
}
}  // namespace

void declare_bc_keys(Schema& s) {
  s.table_array("bc", "supports on node sets (restraints, symmetry, prescribed displacements)", 0, 64)
      .choice("bc.type",
              "clamped (all DoFs), hinged (all translations), symmetry (plane through the nodes: no translation along "
              "its normal, rotation only about it), fix (the listed DoFs, in bc.frame), displacement (the listed "
              "translations prescribed: lambda x bc.displacement; displacement control)",
              {"clamped", "hinged", "symmetry", "fix", "displacement"}, std::nullopt)
      .string_list("bc.fix",
                   "fix: DoFs held at zero; displacement: translations prescribed (default all three). Names per "
                   "frame: global ux uy uz rx ry rz; cylindrical ur ut ua rr rt ra (radial, tangential = axis x "
                   "radial, axial); node u1 u2 u3 r1 r2 r3 (the node's reference frame, 3 = director)",
                   std::vector<std::string>{},
                   {"ux", "uy", "uz", "rx", "ry", "rz", "ur", "ut", "ua", "rr", "rt", "ra", "u1", "u2", "u3", "r1", "r2", "r3"})
      .choice("bc.frame", "axes the fix / displacement components refer to (fixed in space, taken per node)",
              {"global", "cylindrical", "node"}, "global")
      .number_list("bc.axis", "frame = cylindrical: direction of the cylinder axis", std::vector<double>{0, 0, 1}, {}, 3, 3)
      .number_list("bc.axis_point", "frame = cylindrical: a point of the cylinder axis", std::vector<double>{0, 0, 0}, {}, 3, 3)
      .number_list("bc.displacement",
                   "displacement: components at lambda = 1 along the frame's three translation axes (only those "
                   "listed in bc.fix are prescribed)",
                   std::vector<double>{0, 0, 0}, kLoadRange, 3, 3);
  s.unit_of("bc.axis_point", "length").unit_of("bc.displacement", "length");
  declare_selector_keys(s, "bc");
}

void declare_load_keys(Schema& s) {
  s.table_array("load", "loads at lambda = 1 on node sets", 0, 64)
      .choice("load.type",
              "force / moment: a point load (several nodes share the total by tributary length); line: a force per "
              "unit length along the mesh edges joining the selected nodes (consistent nodal forces); pressure: a "
              "uniform pressure on every quad whose 4 corner nodes are selected (select = \"all\": the whole mesh); "
              "surface: a force per unit area in a fixed direction (self-weight, snow) on those quads",
              {"force", "moment", "line", "pressure", "surface"}, std::nullopt)
      .number_list("load.total", "force / moment (required there): total vector at lambda = 1 (global components)",
                   std::vector<double>{0, 0, 0}, kLoadRange, 3, 3)
      .number_list("load.per_length", "line (required there): force per unit length at lambda = 1 (global components)",
                   std::vector<double>{0, 0, 0}, kLoadRange, 3, 3)
      .number_list("load.per_area",
                   "surface (required there): force per unit area of the reference mid-surface at lambda = 1 "
                   "(global components; a dead load: consistent nodal forces, core/shell/shell_model.md P5)",
                   std::vector<double>{0, 0, 0}, kLoadRange, 3, 3)
      .number("load.pressure",
              "pressure (required there): force per unit area at lambda = 1, positive along the director (the "
              "normal of a counter-clockwise quad)", 0.0, kLoadRange)
      .boolean("load.follower",
               "force / moment: turn with the nodes (components then in the node frame); pressure: act on the "
               "current normal and area instead of the reference ones; line and surface loads are dead loads", false);
  s.unit_of("load.total", "force (moment: force length)")
      .unit_of("load.per_length", "force/length")
      .unit_of("load.per_area", "force/length^2")
      .unit_of("load.pressure", "force/length^2");
  declare_selector_keys(s, "load");
}

void declare_probe_keys(Schema& s) {
  s.table_array("probe", "quantities recorded along the path", 1, 32)
      .string("probe.name", "probe name, also its plot's file name plots/<name>.png: one plain file name (no '/', '\\', "
                               "'..' or control characters, at most 200 bytes)",
                  std::nullopt)
      .string("probe.label", "plot label", std::string{})
      .choice("probe.quantity",
              "displacement: direction . u of the (first) selected node; reaction: direction . (support force) "
              "summed over the selected nodes (the force the supports exert on the shell, with the sign of the "
              "external load it balances reversed: f_int - lambda f_ext); stress: the nodal value of the stress "
              "field probe.field at the (first) selected node",
              {"displacement", "reaction", "stress"}, "displacement")
      .number_list("probe.direction",
                   "displacement, reaction (required there): global direction the quantity is projected on",
                   std::vector<double>{0, 0, 0}, {}, 3, 3);
  declare_probe_field_key(s);
  declare_selector_keys(s, "probe");
}

std::vector<std::string> stress_field_names() {
  std::vector<std::string> names;
  for (const shell::StressField& f : shell::stress_fields(shell::StressLayout{})) names.push_back(f.name);
  return names;
}

void declare_probe_field_key(Schema& s) {
  s.string("probe.field",
           "quantity = \"stress\" (required there): the stress field read, e.g. von_mises, sigma11_top, N11, "
           "ply2_sigma1 (every name: docs/guide/running.md, stress fields); its value at the node is the mean of the "
           "values at the centres of the elements around it. Turns output.stresses on",
           std::string{});
}

bool probe_reads_stress(const Document& d, std::size_t i) {
  const std::string quantity = d.string("probe.quantity", i);
  if (quantity == "stress") {
    if (!d.present("probe.field", i))
      throw SceneError({d.issue("probe.quantity", i, "quantity = \"stress\" needs probe.field, the stress field to "
                                                     "read at the node (e.g. \"von_mises\")")});
    if (d.present("probe.direction", i))
      throw SceneError({d.issue("probe.direction", i, "a stress probe reads the value of probe.field at its node, "
                                                      "along no direction; probe.direction belongs to quantity = "
                                                      "\"displacement\" or \"reaction\"")});
    return true;
  }
  if (d.present("probe.field", i))
    throw SceneError({d.issue("probe.field", i, "probe.field belongs to quantity = \"stress\"; this probe's quantity "
                                                "is \"" + quantity + "\"")});
  if (!d.present("probe.direction", i))
    throw SceneError({d.issue("probe.direction", i, "quantity = \"" + quantity + "\" needs probe.direction, the "
                                                    "global direction the " + quantity + " is projected on")});
  // a zero direction projects everything to 0: the probe would record 0 throughout
  if (vec(d.numbers("probe.direction", i)).isZero(0.0))
    throw SceneError({d.issue("probe.direction", i, "the direction is the zero vector: the " + quantity +
                                                    " projected on it is 0 throughout; give the direction to read")});
  return false;
}

bool stresses_wanted(const Document& d, const std::vector<std::string>& fixed_fields) {
  if (d.boolean("output.stresses")) return true;
  const std::string& colour = d.string("output.color_field");
  if (colour != "none" && std::find(fixed_fields.begin(), fixed_fields.end(), colour) == fixed_fields.end()) return true;
  for (std::size_t i = 0; i < d.count("probe"); ++i)
    if (d.string("probe.quantity", i) == "stress") return true;
  return false;
}

void refuse_unknown_probe_fields(const Document& d, const std::vector<shell::StressField>& fields) {
  for (std::size_t i = 0; i < d.count("probe"); ++i) {
    if (d.string("probe.quantity", i) != "stress") continue;
    const std::string& name = d.string("probe.field", i);
    std::string names;
    bool known = false;
    for (const shell::StressField& f : fields) {
      known = known || f.name == name;
      names += (names.empty() ? "" : ", ") + f.name;
    }
    if (known) continue;
    const bool ply = name.rfind("ply", 0) == 0 || name.find("tsai_wu") != std::string::npos;
    throw SceneError({d.issue("probe.field", i, "'" + name + "' is not a stress field of this structure (its fields: " +
                                                    names + ")" +
                                                    (ply ? "; the ply fields and tsai_wu follow the structure's "
                                                           "layup: plyK for K up to its most plies, tsai_wu only "
                                                           "when the plies have strengths"
                                                         : ""))});
  }
}

void read_bcs(const Document& d, shell::ShellModelSpec& spec) {
  using namespace ff::shell;
  const mesh::ShellMesh& m = spec.mesh;
  for (std::size_t i = 0; i < d.count("bc"); ++i) {
    const int source = static_cast<int>(i);
    const std::string type = d.string("bc.type", i);
    const std::vector<int> ids = select_nodes(d, m, "bc", i);
    if (type == "symmetry") {
      const std::string& how = d.string("bc.select", i);
      if (how != "plane" && how != "group")
        throw SceneError({d.issue("bc.select", i, "a symmetry condition needs select = \"plane\" (its normal is the "
                                                  "plane's normal) or select = \"group\" with bc.normal")});
      if (how == "group" && !d.present("bc.normal", i))
        throw SceneError({d.issue("bc.group", i, "a symmetry condition on a group needs bc.normal, the normal of its "
                                                 "symmetry plane")});
      const Vec3 n = vec(d.numbers("bc.normal", i));
      if (!(n.norm() > 0) || !n.allFinite() || !std::isfinite(n.squaredNorm()))
        throw SceneError({d.issue("bc.normal", i, "the plane normal must be a finite non-zero vector")});
      for (int id : ids) spec.symmetry_planes.push_back({id, n.normalized(), source});
      continue;
    }
    if (type == "clamped" || type == "hinged") {
      if (d.present("bc.fix", i))
        throw SceneError({d.issue("bc.fix", i, "type = \"" + type + "\" restrains a fixed set of DoFs; use type = "
                                                 "\"fix\" to list them")});
      for (int id : ids)
        for (int k = 0; k < (type == "clamped" ? 6 : 3); ++k)
          spec.directions.push_back({id, Vec3::Unit(k % 3), k >= 3, 0.0, source});
      continue;
    }
    // fix / displacement: DoF names of the entry's frame
    const std::string frame = d.string("bc.frame", i);
    const std::vector<std::string>& names = kDofNames.at(frame);
    std::vector<std::string> dofs = d.strings("bc.fix", i);
    const bool prescribe = type == "displacement";
    if (dofs.empty()) {
      if (!prescribe)
        throw SceneError({d.issue("bc.fix", i, "type = \"fix\" needs the DoFs to fix, e.g. [\"" + names[2] + "\"] (frame = \"" +
                                                   frame + "\": " + joined(names) + ")")});
      dofs.assign(names.begin(), names.begin() + 3);
    }
    if (!prescribe && d.present("bc.displacement", i))
      throw SceneError({d.issue("bc.displacement", i, "bc.displacement belongs to type = \"displacement\"")});
    const Vec3 value = vec(d.numbers("bc.displacement", i));
    if (!value.allFinite()) throw SceneError({d.issue("bc.displacement", i, "the displacement is not finite")});
    std::vector<int> slots;
    for (const std::string& name : dofs) {
      const auto it = std::find(names.begin(), names.end(), name);
      if (it == names.end())
        throw SceneError({d.issue("bc.fix", i, "'" + name + "' is not a DoF of frame = \"" + frame + "\" (its DoFs: " +
                                                   joined(names) + ")")});
      const int k = static_cast<int>(it - names.begin());
      if (prescribe && k >= 3)
        throw SceneError({d.issue("bc.fix", i, "'" + name + "': only translations can be prescribed; hold rotations "
                                                   "with a type = \"fix\" entry")});
      slots.push_back(k);
    }
    for (int id : ids) {
      const Eigen::Matrix3d T = frame_axes(d, i, m, id);
      for (int k : slots)
        spec.directions.push_back({id, T.col(k % 3), k >= 3, prescribe ? value[k] : 0.0, source});
    }
  }
}

std::vector<std::pair<int, Vec3>> line_load_forces(const mesh::ShellMesh& m, const std::vector<int>& ids, const Vec3& q,
                                                   std::string& why) {
  std::vector<char> in(m.node_count(), 0);
  for (int i : ids) in[i] = 1;
  std::map<std::pair<int, int>, double> edges;  // unique edges between selected nodes, with their length
  for (int k = 0; k < m.quad_count(); ++k) {
    const auto& quad = m.quads[k];
    if (std::all_of(quad.begin(), quad.end(), [&](int i) { return in[i] != 0; })) {
      why = "selects all 4 corners of quad " + std::to_string(k) + ", i.e. an area; a line load needs nodes along a line "
            "(an edge of the mesh or a line of nodes across it)";
      return {};
    }
    for (int c = 0; c < 4; ++c) {
      const int a = quad[c], b = quad[(c + 1) % 4];
      if (in[a] && in[b]) edges[{std::min(a, b), std::max(a, b)}] = (m.points[a] - m.points[b]).norm();
    }
  }
  if (edges.empty()) {
    why = "selects " + std::to_string(ids.size()) + " node(s) but no mesh edge joins two of them; a line load needs "
          "nodes along a line of edges";
    return {};
  }
  std::map<int, double> share;  // tributary length per node: half of each adjacent selected edge
  for (const auto& [e, len] : edges) share[e.first] += 0.5 * len, share[e.second] += 0.5 * len;
  std::vector<std::pair<int, Vec3>> out;
  for (const auto& [node, len] : share) out.emplace_back(node, len * q);
  return out;
}

std::vector<std::pair<int, Vec3>> surface_load_forces(const mesh::ShellMesh& m, const std::vector<int>& quads,
                                                      const Vec3& t) {
  std::map<int, Vec3> f;  // summed per node
  for (int q : quads) {
    std::array<Vec3, 4> x;
    for (int c = 0; c < 4; ++c) x[c] = m.points[m.quads[q][c]];
    const std::array<Vec3, 4> fq = shell::surface_traction_forces(x, t);
    for (int c = 0; c < 4; ++c) f.try_emplace(m.quads[q][c], Vec3::Zero()).first->second += fq[c];
  }
  return {f.begin(), f.end()};
}

void read_load(const Document& d, std::size_t i, shell::ShellModelSpec& spec) {
  using namespace ff::shell;
  const mesh::ShellMesh& m = spec.mesh;
  {
    const std::string type = d.string("load.type", i);
    const std::vector<int> ids = select_nodes(d, m, "load", i);
    // each type takes its own amount key, and only that one
    const std::map<std::string, std::string> amount = {
        {"force", "load.total"}, {"moment", "load.total"}, {"line", "load.per_length"}, {"pressure", "load.pressure"},
        {"surface", "load.per_area"}};
    const std::map<std::string, std::string> owner = {{"load.total", "type = \"force\" or \"moment\""},
                                                      {"load.per_length", "type = \"line\""},
                                                      {"load.pressure", "type = \"pressure\""},
                                                      {"load.per_area", "type = \"surface\""}};
    for (const auto& [key, types] : owner)
      if (key != amount.at(type) && d.present(key, i))
        throw SceneError({d.issue(key, i, key + " belongs to " + types + "; a " + type + " load takes " + amount.at(type))});
    if (!d.present(amount.at(type), i))
      throw SceneError({d.issue("load.type", i, "type = \"" + type + "\" needs " + amount.at(type))});
    if ((type == "line" || type == "surface") && d.boolean("load.follower", i))
      throw SceneError({d.issue("load.follower", i, type + " loads are dead loads (fixed direction); follower = true "
                                                    "is not supported for them (a pressure can follow the surface)")});
    if (type == "pressure" || type == "surface") {
      const std::vector<int> quads = selected_quads(d, m, "load", i, ids);
      if (quads.empty())
        throw SceneError({d.issue("load.select", i, "selects " + std::to_string(ids.size()) +
                                                        " nodes but no quad with all 4 corners among them; a " + type +
                                                        " load acts on whole quads (select = \"all\" for the whole "
                                                        "mesh)")});
      if (type == "pressure")
        for (int q : quads) spec.pressures.push_back({q, d.number("load.pressure", i), d.boolean("load.follower", i)});
      else
        for (const auto& [node, f] : surface_load_forces(m, quads, vec(d.numbers("load.per_area", i))))
          spec.loads.push_back({node, f, Vec3::Zero(), false});
      return;
    }
    if (type == "line") {
      std::string why;
      const auto forces = line_load_forces(m, ids, vec(d.numbers("load.per_length", i)), why);
      if (!why.empty()) throw SceneError({d.issue("load.select", i, why)});
      for (const auto& [node, f] : forces) spec.loads.push_back({node, f, Vec3::Zero(), false});
      return;
    }
    const std::vector<double> w = tributary_weights(m, ids);
    const Vec3 total = vec(d.numbers("load.total", i));
    const bool moment = type == "moment";
    for (std::size_t k = 0; k < ids.size(); ++k) {
      NodalLoad l;
      l.node = ids[k];
      (moment ? l.moment : l.force) = w[k] * total;
      l.follower = d.boolean("load.follower", i);
      spec.loads.push_back(l);
    }
  }
}

std::vector<shell::ShellProbe> read_probes(const Document& d, const mesh::ShellMesh& m) {
  std::vector<shell::ShellProbe> probes;
  for (std::size_t i = 0; i < d.count("probe"); ++i) {
    const std::vector<int> ids = select_nodes(d, m, "probe", i);
    const std::string name = d.string("probe.name", i), label = d.string("probe.label", i);
    for (const shell::ShellProbe& p : probes)
      if (p.name == name) throw SceneError({d.issue("probe.name", i, "a probe named '" + name + "' is already declared")});
    shell::ShellProbe p;
    p.name = name;
    p.label = label.empty() ? name : label;
    p.node = ids.front();
    p.direction = vec(d.numbers("probe.direction", i));
    if (probe_reads_stress(d, i)) {
      p.quantity = shell::ShellProbe::Quantity::stress;
      p.field = d.string("probe.field", i);
    } else if (d.string("probe.quantity", i) == "reaction") {
      p.quantity = shell::ShellProbe::Quantity::reaction;
      p.nodes = ids;
    }
    probes.push_back(std::move(p));
  }
  return probes;
}

std::vector<HeldDirection> held_directions(const shell::ShellModelSpec& spec) {
  std::vector<HeldDirection> held;
  for (const shell::DirectionRestraint& r : spec.directions)
    held.push_back({r.node, r.direction.normalized(), r.rotation, r.value != 0.0, "bc[" + std::to_string(r.source) + "]"});
  for (const shell::SymmetryPlane& p : spec.symmetry_planes) {
    const Vec3 n = p.normal.normalized(), t1 = n.unitOrthogonal(), t2 = n.cross(t1);
    const std::string entry = "bc[" + std::to_string(p.source) + "]";
    held.push_back({p.node, n, false, false, entry});
    held.push_back({p.node, t1, true, false, entry});  // rotation only about the normal
    held.push_back({p.node, t2, true, false, entry});
  }
  return held;
}

namespace {
// What the supports hold at one node: orthonormal bases of the held translations and rotations,
// and the entries holding them
struct NodeHold {
  std::vector<Vec3> translations, rotations;
  std::vector<std::string> entries;
  bool prescribed = false;
};
// adds `v` to the orthonormal basis `basis` unless it lies in its span already
void add_to_basis(std::vector<Vec3>& basis, Vec3 v) {
  for (const Vec3& b : basis) v -= v.dot(b) * b;
  if (v.norm() > 1e-9) basis.push_back(v.normalized());
}
std::map<int, NodeHold> holds_by_node(const std::vector<HeldDirection>& held) {
  std::map<int, NodeHold> out;
  for (const HeldDirection& h : held) {
    NodeHold& n = out[h.node];
    add_to_basis(h.rotation ? n.rotations : n.translations, h.direction);
    if (std::find(n.entries.begin(), n.entries.end(), h.entry) == n.entries.end()) n.entries.push_back(h.entry);
    n.prescribed = n.prescribed || h.prescribed;
  }
  return out;
}
// the part of v the basis leaves free
Vec3 free_part(const std::vector<Vec3>& basis, Vec3 v) {
  for (const Vec3& b : basis) v -= v.dot(b) * b;
  return v;
}
// v (non-zero) lies in what `basis` holds, to round-off; a follower vector only when all of it is held
bool held_along(const std::vector<Vec3>& basis, const Vec3& v, bool follower) {
  if (follower) return basis.size() == 3;
  // measured on v scaled to its largest component, so that neither 1e308 nor 1e-300 leaves double precision
  const double scale = v.cwiseAbs().maxCoeff();
  if (!(scale > 0) || !std::isfinite(scale)) return false;
  const Vec3 unit = v / scale;
  return free_part(basis, unit).norm() <= 1e-9 * unit.norm();
}
// "its one node", "each of its 3 nodes"
std::string each_node_text(std::size_t n) { return n == 1 ? "its one node" : "each of its " + std::to_string(n) + " nodes"; }
}  // namespace

void refuse_loads_on_held_dofs(const Document& d, const mesh::ShellMesh& m, const std::vector<HeldDirection>& held,
                               const std::vector<EntryLoads>& loads) {
  if (held.empty()) return;
  const std::map<int, NodeHold> holds = holds_by_node(held);
  for (const EntryLoads& e : loads) {
    // every non-zero nodal force and moment of the entry, pressures as their reference nodal forces
    std::vector<shell::NodalLoad> nodal = e.nodal;
    for (const shell::PressureLoad& p : e.pressures) {
      std::array<Vec3, 4> x;
      for (int c = 0; c < 4; ++c) x[c] = m.points[m.quads[p.quad][c]];
      const std::array<Vec3, 4> f = shell::dead_pressure_forces(x, p.pressure);
      for (int c = 0; c < 4; ++c) nodal.push_back({m.quads[p.quad][c], f[c], Vec3::Zero(), p.follower});
    }
    bool loaded = false, works = false;
    std::vector<int> nodes;
    std::vector<std::string> entries;
    bool prescribed = false;
    for (const shell::NodalLoad& l : nodal) {
      const bool force = !l.force.isZero(0.0), moment = !l.moment.isZero(0.0);
      if (!force && !moment) continue;
      loaded = true;
      const auto it = holds.find(l.node);
      if (it == holds.end()) {  // a node no support holds
        works = true;
        break;
      }
      const NodeHold* h = &it->second;
      if ((force && !held_along(h->translations, l.force, l.follower)) ||
          (moment && !held_along(h->rotations, l.moment, l.follower))) {
        works = true;
        break;
      }
      if (std::find(nodes.begin(), nodes.end(), l.node) == nodes.end()) nodes.push_back(l.node);
      for (const std::string& name : h->entries)
        if (std::find(entries.begin(), entries.end(), name) == entries.end()) entries.push_back(name);
      prescribed = prescribed || h->prescribed;
    }
    if (!loaded || works) continue;
    const std::size_t i = e.entry;
    const std::string type = d.string("load.type", i);
    const std::string amount = type == "force" || type == "moment" ? "load.total"
                               : type == "line"                    ? "load.per_length"
                               : type == "pressure"                ? "load.pressure"
                                                                   : "load.per_area";
    std::string by;
    for (const std::string& name : entries) by += (by.empty() ? "" : ", ") + name;
    throw SceneError({d.issue(amount, i, "load[" + std::to_string(i) + "] does no work: at " +
                                             each_node_text(nodes.size()) + " the supports (" + by + ") " +
                                             (prescribed ? "hold or prescribe" : "hold") + " every direction it " +
                                             (type == "moment" ? "turns" : "pushes") + ", so they take all of it and "
                                             "the structure never feels it; load nodes the supports leave free along "
                                             "the load, or give the load another direction")});
  }
}

void warn_probes_on_held_dofs(const Document& d, const mesh::ShellMesh& m, const std::vector<HeldDirection>& held,
                              bool reaction_probes, std::vector<std::string>* warnings) {
  if (!warnings) return;
  const std::map<int, NodeHold> holds = holds_by_node(held);
  auto held_at = [&](int node) -> const NodeHold* {
    const auto it = holds.find(node);
    return it == holds.end() ? nullptr : &it->second;
  };
  for (std::size_t i = 0; i < d.count("probe"); ++i) {
    const std::string quantity = d.string("probe.quantity", i);
    if (quantity == "stress") continue;
    const Vec3 given = vec(d.numbers("probe.direction", i));
    const double scale = given.cwiseAbs().maxCoeff();  // a direction of 1e308 or 1e-300 stays a direction
    if (!(scale > 0) || !std::isfinite(scale)) continue;
    const Vec3 direction = given / scale;
    const std::vector<int> ids = select_nodes(d, m, "probe", i);
    const std::string name = "probe[" + std::to_string(i) + "] '" + d.string("probe.name", i) + "'";
    if (quantity == "displacement") {
      const NodeHold* h = held_at(ids.front());
      if (!h || h->prescribed || !held_along(h->translations, direction, false)) continue;
      std::string by;
      for (const std::string& e : h->entries) by += (by.empty() ? "" : ", ") + e;
      warnings->push_back(d.issue("probe.direction", i, name + " reads the displacement of node " +
                                                            std::to_string(ids.front()) + " along a direction the "
                                                            "supports (" + by + ") hold there: it records 0 throughout" +
                                                            (reaction_probes ? " (quantity = \"reaction\" reads the "
                                                                               "support's force)"
                                                                             : ""))
                              .to_string());
    } else if (quantity == "reaction") {
      const bool any = std::any_of(ids.begin(), ids.end(), [&](int node) {
        const NodeHold* h = held_at(node);
        return h && free_part(h->translations, direction).norm() < (1.0 - 1e-9) * direction.norm();
      });
      if (!any)
        warnings->push_back(d.issue("probe.direction", i, name + " sums the support force along a direction no "
                                                              "support holds at " +
                                                              (ids.size() == 1 ? std::string("its node")
                                                                               : "any of its " + std::to_string(ids.size()) +
                                                                                     " nodes") +
                                                              ": it records only the residual, about 0 (select the "
                                                              "supported nodes)")
                                .to_string());
    }
  }
}

Issue located(const Document& d, const shell::ShellSpecError& e, const Structure& structure) {
  using Part = shell::ShellSpecError::Part;
  const std::size_t i = e.source() >= 0 ? static_cast<std::size_t>(e.source()) : 0;
  // the part a quad belongs to, and its material
  const int q = e.source();
  const std::size_t part =
      q >= 0 && q < static_cast<int>(structure.quad_part.size()) ? static_cast<std::size_t>(structure.quad_part[q]) : 0;
  const int material = part < structure.parts.size() ? structure.parts[part].material : 0;
  switch (e.part()) {
    case Part::restraint:
    case Part::symmetry:
      if (e.source() >= 0 && i < d.count("bc")) return d.issue("bc.type", i, e.what());
      break;
    case Part::pressure:
      break;
    case Part::element:
      // an element that forms with a thinner section (det J <= 0 through this thickness only):
      // the thickness against the curvature
      return thickness_issue(d, structure, material,
                     std::string(e.what()) +
                         " (the element forms with a thinner section: this thickness is larger than the local radius "
                         "of curvature of the mesh)");
    case Part::mid_surface: {
      // degenerate at any thickness: the mesh's own geometry (its corners or directors)
      const bool file = d.string("part.generator", part) == "file";
      return d.issue(file ? "part.file" : "part.generator", part,
                     std::string(e.what()) + " at any thickness: the quad's corners or directors carry no shell (" +
                         (file ? "a collapsed or folded quad, or normals lying in it" : "check the mesh dimensions") + ")");
    }
  }
  return d.issue("bc.type", 0, e.what());
}

}  // namespace ff::scene
