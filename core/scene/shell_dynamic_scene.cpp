#include "core/scene/shell_dynamic_scene.h"
#include "core/scene/shell_structure_scene.h"

#include <algorithm>
#include <sstream>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/mesh/generators.h"
#include "core/scene/mesh_quality_report.h"
#include "core/scene/node_selection.h"
#include "core/scene/scene_common.h"
#include "core/scene/shell_boundary.h"
#include "core/scene/structure_parts.h"
#include "core/scene/timeline.h"
#include "core/shell/shell_dynamic_simulation.h"

namespace ff::scene {

namespace {
Eigen::Vector3d vec(const std::vector<double>& v) { return Eigen::Vector3d(v[0], v[1], v[2]); }
// the smallest Newton tolerance of a step, as a fraction of the structure's size
constexpr double kSmallestDynamicTolerance = 1e-12;
constexpr double kDeg = std::numbers::pi / 180.0;
}  // namespace

const Schema& shell_dynamic_schema() {
  static const Schema schema = [] {
    Schema s;
    declare_scene_table(s,
                        "effects to simulate: elastic and inertia (required), gravity, hr, ans, drilling (6 DoF "
                        "per shell node), joints (the [[joint]] constraints)",
                        {"elastic", "inertia", "gravity", "hr", "ans", "drilling", "joints"});
    s.choice("scene.analysis", kShellAnalysisDoc, shell_analyses(), std::nullopt);
    s.table("solver", "time stepping: Lie-group generalized-alpha (core/solve/generalized_alpha.md)", true)
        .number("solver.dt", "time step [s]", std::nullopt, Range::positive())
        .number("solver.end", "end time [s]", std::nullopt, Range::positive())
        .integer("solver.output_every", "publish (store, render) every n-th step", 10, IntRange::closed(1, 1000000))
        .number("solver.count_until", "NOI/NOU are also counted up to this time (metrics NOI_window, NOU_window)",
                1e300, Range::positive())
        .number("solver.rho_inf", "spectral radius at infinity", 0.9, Range::closed(0.0, 1.0))
        .number("solver.tolerance",
                "Newton stops when the 2-norm of the correction is below this (at least 1e-12 x the structure's "
                "size: below it the coordinates' round-off)",
                1e-6, Range::left_open(0.0, 1.0))
        .integer("solver.max_iterations", "corrections per attempt", 30, IntRange::closed(2, 500))
        .choice("solver.policy",
                "iteration matrix: full (every iteration), nni (from iteration nni on), frozen (the first one, "
                "kept), lazy (kept until a correction shrinks by less than refresh_ratio, then refreshed)",
                {"full", "nni", "frozen", "lazy"}, "full")
        .choice("solver.predictor",
                "the acceleration a step's Newton iteration starts from: zero, previous (the last step's), or "
                "auto (previous, except zero under the frozen policy, whose never-updated matrix converges "
                "more slowly from the shifted start; core/solve/generalized_alpha.md (G3'))",
                {"auto", "zero", "previous"}, "auto")
        .integer("solver.nni", "policy nni: update at this and later iterations of a step", 3, IntRange::closed(1, 100))
        .number("solver.refresh_ratio",
                "policy lazy: refresh the matrix at an iteration whose correction was more than this fraction of "
                "the one before (a slow contraction means it has aged)",
                0.3, Range::open(0.0, 1.0))
        .number("solver.step_refresh_ratio",
                "policy lazy: the next step starts with a fresh matrix when a step that kept its matrix ended on "
                "a correction more than this fraction of the one before (the kept matrix's contraction rate, "
                "core/solve/generalized_alpha.md (G10')); 1 turns this off",
                0.1, Range::left_open(0.0, 1.0))
        .integer("solver.max_cutbacks", "halvings of a failing step before the run is declared diverged", 6,
                 IntRange::closed(0, 20))
        .choice("solver.initial_state",
                "at_rest: the run starts from the undeformed reference at rest; static_equilibrium: from the "
                "static equilibrium under the loads and gravity at t = 0, found by Newton first (a static preload, "
                "which a load ending at load.end then releases; core/solve/generalized_alpha.md (G11))",
                {"at_rest", "static_equilibrium"}, "at_rest");
    declare_linear_solver(s, "mumps where compiled in, else umfpack: 14 % less wall time on the double pendulum, "
                             "docs/validation/shell-dynamics.md");
    s.table("gravity", "uniform gravity (effect gravity)")
        .number_list("gravity.g", "acceleration of gravity [m/s^2]; each component within [-1e100, 1e100]",
                     std::vector<double>{0, 0, -9.81}, Range::closed(-1e100, 1e100), 3, 3)
        .live("gravity.g");
    declare_structure_keys(s);
    declare_mesh_quality_keys(s);
    declare_multibody_keys(s);
    // supports and loads as in statics; each load on a time history instead of the load factor
    // (cb_shell_dynamics.md (D16)); supports that hold whole translations or rotations
    declare_bc_keys(s);
    declare_load_keys(s);
    s.number("load.start", "dynamics: time the load is applied, all at once unless load.ramp > 0", 0.0, {}, "s")
        .number("load.end", "dynamics: time the load is removed (a pulse); 0 = held to the end of the run", 0.0,
                Range::non_negative(), "s")
        .number("load.ramp", "dynamics: the load rises linearly from 0 over this long from load.start; 0 = suddenly",
                0.0, Range::non_negative(), "s");
    s.table_array("probe", "node displacements (direction . u) or stresses recorded every step", 0, 32)
        .string("probe.name", "probe name, also its plot's file name plots/<name>.png: one plain file name (no '/', '\\', "
                               "'..' or control characters, at most 200 bytes)",
                  std::nullopt)
        .string("probe.label", "plot label", std::string{})
        .choice("probe.quantity",
                "displacement: direction . u of the (first) selected node; stress: the nodal value of the stress "
                "field probe.field there",
                {"displacement", "stress"}, "displacement")
        .number_list("probe.direction",
                     "displacement (required there): global direction the displacement is projected on",
                     std::vector<double>{0, 0, 0}, {}, 3, 3);
    declare_probe_field_key(s);
    declare_selector_keys(s, "probe");
    s.table_array("arc", "curves whose relative chord and length changes are recorded (arc_rate_<name>)", 0, 16)
        .string("arc.name", "arc name, also in its plots' file names plots/arc_rate_<name>.png: one plain file name",
                std::nullopt);
    declare_selector_keys(s, "arc");
    s.table_array("metric", "numbers written to summary.json", 0, 32)
        .string("metric.name", "metric name", std::nullopt)
        .choice("metric.kind",
                "how it is read from the history: min, max, max_abs, final, or mean (the time average over the "
                "run, trapezoid rule over every step)",
                {"min", "max", "max_abs", "final", "mean"}, std::nullopt)
        .string("metric.probe", "probe (or arc_rate_<arc>, arc_strain_<arc>) it reads", std::nullopt);
    declare_output_keys(s, {"displacement", "strain"}, true, stress_field_names());
    declare_timeline(s, "time of the event", "s", {"gravity"});
    // one vocabulary across models: time stepping and the integrator are the [solver] table
    s.renamed("time", "solver").renamed("integrator", "solver");
    // one structure vocabulary for every analysis: [[part]] and [[material]] tables, selections by
    // patch (a part's name) as in statics
    // [[shell]] split into [[part]] and [[material]]: each of its keys says where it went
    for (const char* k : {"youngs_modulus", "poisson_ratio", "thickness", "density", "drilling_factor"})
      s.renamed(std::string("shell.") + k, std::string("material.") + k);
    s.renamed("shell.phi_start", "part.start_angle").renamed("shell.phi_end", "part.end_angle");
    s.renamed("shell.center", "part.origin").renamed("shell.y0", "part.origin");
    for (const char* k : {"name", "generator", "n1", "n2", "radius", "length", "width", "origin", "end_slope"})
      s.renamed(std::string("shell.") + k, std::string("part.") + k);
    s.renamed("joint.body", "joint.patch").renamed("probe.body", "probe.patch").renamed("arc.body", "arc.patch");
    return s;
  }();
  return schema;
}

namespace {
// nodes of an arc in order along the direction joining its two extreme points
std::vector<int> ordered(const mesh::ShellMesh& m, std::vector<int> ids) {
  if (ids.size() < 2) return ids;
  double best = -1;
  Eigen::Vector3d a = m.points[ids[0]], b = a;
  for (int i : ids)
    for (int j : ids)
      if ((m.points[i] - m.points[j]).norm() > best) best = (m.points[i] - m.points[j]).norm(), a = m.points[i], b = m.points[j];
  const Eigen::Vector3d dir = (b - a).normalized();
  std::sort(ids.begin(), ids.end(), [&](int i, int j) { return dir.dot(m.points[i] - a) < dir.dot(m.points[j] - a); });
  return ids;
}
}  // namespace

void declare_multibody_keys(Schema& s) {
  s.table_array("rigid", "rigid bodies (SE(3) pose, mass, inertia about the centre of mass)", 0, 64)
      .string("rigid.name", "body name", std::nullopt)
      .number_list("rigid.position", "centre of mass [m]", std::nullopt, {}, 3, 3)
      .number("rigid.mass", "mass [kg]", std::nullopt, Range::positive())
      .number_list("rigid.inertia", "principal moments about the body axes (= global axes at t = 0) [kg m^2]",
                   std::nullopt, {}, 3, 3);
  s.table_array("joint", "joints and supports as constraints (effect joints)", 0, 64)
      .choice("joint.type", "simple_support (nodes fixed in space, free to rotate), spherical (coincident "
              "points), revolute (coincident points + common axis), fixed (coincident points and frames)",
              {"simple_support", "spherical", "revolute", "fixed"}, std::nullopt)
      .string("joint.other",
              "the part or rigid body the selected nodes are joined to (for a part: its node coincident with each "
              "selected node); \"\" = ground",
              std::string{})
      .number_list("joint.axis", "revolute: axis direction (global, reference configuration)",
                   std::vector<double>{0, 1, 0}, {}, 3, 3);
  declare_selector_keys(s, "joint");
}

MultibodyInput read_multibody_input(const Document& d, const std::string& path, const SceneContext& ctx, bool with_loads,
                                    bool joints_need_effect) {
  using namespace ff::shell;
  const std::vector<std::string> fx = d.strings("scene.effects");
  auto has = [&](const char* e) {
    if (!joints_need_effect && std::string(e) == "joints") return true;
    return std::find(fx.begin(), fx.end(), e) != fx.end();
  };
  MultibodyInput in;
  MultibodySpec& spec = in.spec;
  // every part's nodes from its counts, so that parts that cannot fit are refused at the largest
  // one's count before any mesh is built
  const StructureSize size = structure_size(d, path, ctx);
  refuse_oversized(d, ctx, static_cast<int>(std::min<long long>(size.nodes, std::numeric_limits<int>::max())),
                   has("drilling") ? 1.0 : 0.0, size.key, size.part);
  in.structure = read_structure(d, path, ctx);
  Structure& structure = in.structure;
  report_mesh_quality(d, structure, ctx);  // refuses inverted or degenerate quads; warnings for poor ones
  // the shell bodies: one per part, or, where [[junction]]s make parts share nodes, one body of
  // the joined structure whose quads keep their parts' materials. Either way the model's shell
  // node ids are the joined structure's (parts in order), so selections on it need no mapping.
  std::vector<std::string> names;
  for (std::size_t i = 0; i < structure.parts.size(); ++i) {
    const StructurePart& part = structure.parts[i];
    require_density(d, structure, i,
                    "a dynamic analysis needs material.density (mass per unit volume) for part '" + part.name + "'");
    names.push_back(part.name);
  }
  auto body_of = [&](const std::string& name, const mesh::ShellMesh& m) {
    ShellBodySpec b;
    b.name = name;
    b.mesh = m;
    b.options.hr = has("hr");
    b.options.ans = has("ans");
    b.options.drilling = has("drilling");
    return b;
  };
  if (structure.has_junctions) {
    std::string joined_names;
    for (const StructurePart& part : structure.parts) joined_names += (joined_names.empty() ? "" : "+") + part.name;
    ShellBodySpec b = body_of(joined_names, structure.joined);
    // the first part's section (the first [[material]] may be only a ply of a layup)
    const StructureMaterial& first = structure.materials[structure.parts.front().material];
    b.section = first.section, b.density = first.density, b.options.drilling_factor = first.drilling_factor;
    for (const StructureMaterial& m : structure.materials)
      b.sections.push_back(m.section), b.densities.push_back(m.density), b.drilling_factors.push_back(m.drilling_factor);
    for (int part : structure.quad_part) b.quad_material.push_back(structure.parts[part].material);
    b.quad_reference_direction = structure.quad_reference_direction;
    spec.shells.push_back(std::move(b));
  } else {
    for (const StructurePart& part : structure.parts) {
      const StructureMaterial& material = structure.materials[part.material];
      ShellBodySpec b = body_of(part.name, part.mesh);
      b.section = material.section;
      b.density = material.density;
      b.options.drilling_factor = material.drilling_factor;
      if (!structure.quad_reference_direction.empty()) b.quad_reference_direction = part.reference_direction;
      spec.shells.push_back(std::move(b));
    }
  }
  {
    int total = 0;
    for (const ShellBodySpec& b : spec.shells) total += b.mesh.node_count();
    if (total > 0) refuse_oversized(d, ctx, total, has("drilling") ? 1.0 : 0.0, size.key, size.part);
  }
  for (std::size_t i = 0; i < d.count("rigid"); ++i) {
    RigidBodySpec r;
    r.name = d.string("rigid.name", i);
    if (std::find(names.begin(), names.end(), r.name) != names.end())
      throw SceneError({d.issue("rigid.name", i, "another body is already called '" + r.name + "'")});
    names.push_back(r.name);
    r.pose.p = vec(d.numbers("rigid.position", i));
    r.mass = d.number("rigid.mass", i);
    const std::vector<double> J = d.numbers("rigid.inertia", i);
    if (*std::min_element(J.begin(), J.end()) <= 0)
      throw SceneError({d.issue("rigid.inertia", i, "principal moments must be positive")});
    r.inertia = Eigen::Vector3d(J[0], J[1], J[2]).asDiagonal();
    spec.rigid.push_back(r);
  }
  spec.gravity = has("gravity");
  spec.g = vec(d.numbers("gravity.g"));

  // shell nodes are the joined structure's; rigid body r is node shell_nodes + r
  const mesh::ShellMesh& joined = structure.joined;
  const int shell_nodes = joined.node_count();
  std::vector<int> node_part(shell_nodes, -1);  // the first part a node belongs to
  for (std::size_t p = 0; p < structure.parts.size(); ++p)
    for (int id : structure.parts[p].node_map)
      if (node_part[id] < 0) node_part[id] = static_cast<int>(p);
  // joint.other by name: a part (>= 0) or a rigid body (-1 - its index)
  auto other_of = [&](std::size_t i) {
    const std::string name = d.string("joint.other", i);
    if (const int p = structure.find(name); p >= 0) return p;
    for (std::size_t r = 0; r < spec.rigid.size(); ++r)
      if (spec.rigid[r].name == name) return -1 - static_cast<int>(r);
    throw SceneError({d.issue("joint.other", i, "no part or rigid body called '" + name + "'")});
  };

  // what the supports and the joints to the ground hold, for the loads and probes on them
  std::vector<HeldDirection> held;
  auto hold = [&](int node, bool rotation, const std::string& entry) {
    for (int k = 0; k < 3; ++k) held.push_back({node, Eigen::Vector3d::Unit(k), rotation, false, entry});
  };

  if (d.count("joint") > 0 && !has("joints"))
    throw SceneError({d.issue("scene.effects", "the scene has [[joint]] entries but not the effect 'joints'")});
  for (std::size_t i = 0; i < d.count("joint"); ++i) {
    const std::string type = d.string("joint.type", i);
    // the selected nodes (of the whole structure) must lie in one part: the joint joins them to another
    const std::vector<int> ids = select_nodes(d, joined, "joint", i);
    const int a = node_part[ids.front()];
    for (int id : ids)
      if (node_part[id] != a)
        throw SceneError({d.issue("joint.select", i, "the selected nodes lie in parts '" + structure.parts[a].name +
                                                         "' and '" + structure.parts[node_part[id]].name +
                                                         "'; a joint joins nodes of one part to another body (name "
                                                         "the part with joint.patch)")});
    const bool ground = d.string("joint.other", i).empty();
    if (ground)  // the joint holds its nodes' points in space
      for (int id : ids) hold(id, false, "joint[" + std::to_string(i) + "]");
    if (type == "simple_support" && !ground)
      throw SceneError({d.issue("joint.other", i, "a simple support holds nodes in space: leave 'other' empty")});
    const int other = ground ? 0 : other_of(i);
    const bool other_rigid = !ground && other < 0;
    const int rigid = other_rigid ? -1 - other : -1;
    if (!ground && !other_rigid && other == a)
      throw SceneError({d.issue("joint.other", i, "a joint needs two different bodies")});
    const double tol = 1e-6 * std::max(1.0, mesh::max_edge_length(structure.parts[a].mesh));
    std::vector<std::pair<int, int>> pairs;  // model-wide (node a, node b or -1)
    for (int id : ids) {
      int partner = -1;
      if (other_rigid) {
        partner = shell_nodes + rigid;
      } else if (!ground) {
        for (int k : structure.parts[other].node_map)
          if ((joined.points[k] - joined.points[id]).norm() < tol) partner = k;
        if (partner < 0)
          throw SceneError({d.issue("joint.other", i, "node at (" + std::to_string(joined.points[id].x()) + ", " +
                                                          std::to_string(joined.points[id].y()) + ", " +
                                                          std::to_string(joined.points[id].z()) +
                                                          ") has no coincident node in part '" +
                                                          d.string("joint.other", i) + "'")});
      }
      pairs.push_back({id, partner});
    }
    const bool six = has("drilling");
    for (const auto& [na, nb] : pairs) {
      PositionConstraint pc;
      pc.a = na;
      pc.b = nb;
      pc.target = joined.points[na];
      // a rigid body carries the joint point at its offset from the centre of mass (body axes = W at t = 0)
      if (other_rigid) pc.b_offset = pc.target - spec.rigid[rigid].pose.p;
      spec.positions.push_back(pc);
    }
    if (type == "revolute" || type == "fixed") {
      const Eigen::Vector3d axis = vec(d.numbers("joint.axis", i)).normalized();
      if (!six) {
        // 5-DoF shell nodes: the joint is the line of coincident nodes itself (cb_shell_dynamics.md §6)
        if (type == "fixed")
          throw SceneError({d.issue("joint.type", i, "a fixed joint needs rotational rows, which 5-DoF shell nodes "
                                                     "cannot carry: enable the drilling effect")});
        if (pairs.size() < 2)
          throw SceneError({d.issue("joint.select", i, "a revolute joint between 5-DoF shell nodes needs two or more "
                                                       "node pairs along its axis (or the drilling effect)")});
        const Eigen::Vector3d p0 = joined.points[pairs.front().first];
        for (const auto& pr : pairs) {
          const Eigen::Vector3d off = joined.points[pr.first] - p0;
          if ((off - off.dot(axis) * axis).norm() > tol)
            throw SceneError({d.issue("joint.axis", i, "the selected nodes do not lie on one line along the axis; "
                                                       "a 5-DoF revolute joint is the line of its nodes")});
        }
      } else {
        // rows (D13): two (revolute) or three (fixed) perpendicularities per pair, from the reference frames
        Eigen::Vector3d e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
        for (const auto& [na, nb] : pairs) {
          const Mat3& Ra = joined.frames[na];
          const Mat3 Rb = nb < 0 ? Mat3::Identity() : (other_rigid ? spec.rigid[rigid].pose.R : Mat3(joined.frames[nb]));
          auto row = [&](const Eigen::Vector3d& u, const Eigen::Vector3d& w) {
            spec.perpendiculars.push_back({na, nb, Ra.transpose() * u, nb < 0 ? w : Eigen::Vector3d(Rb.transpose() * w)});
          };
          row(axis, e1), row(axis, e2);
          if (type == "fixed") row(e1, e2);
        }
      }
    }
  }

  // [[bc]]: supports that hold all three translations, all three rotations, or both, of the
  // selected nodes: exact in the local increments of dynamics (they leave the unknowns)
  for (std::size_t i = 0; i < d.count("bc"); ++i) {
    const std::string type = d.string("bc.type", i);
    NodeSupport support;
    if (type == "clamped" || type == "hinged") {
      if (d.present("bc.fix", i))
        throw SceneError({d.issue("bc.fix", i, "type = \"" + type + "\" restrains a fixed set of DoFs; use type = "
                                                 "\"fix\" to list them")});
      support.translations = true;
      support.rotations = type == "clamped";
    } else if (type == "fix") {
      const std::vector<std::string> dofs = d.strings("bc.fix", i);
      int translations = 0, rotations = 0;
      for (const std::string& name : dofs) (name[0] == 'u' ? translations : rotations) += 1;
      support.translations = translations == 3;
      support.rotations = rotations == 3;
      if ((translations != 0 && translations != 3) || (rotations != 0 && rotations != 3) || dofs.empty())
        throw SceneError({d.issue("bc.fix", i, "a dynamic analysis holds a node's three translations, its three "
                                               "rotations, or both (fix = [\"ux\", \"uy\", \"uz\"] and/or [\"rx\", \"ry\", "
                                               "\"rz\"]); single directions are static supports in this version (in "
                                               "dynamics a [[joint]] holds points and axes)")});
    } else {
      throw SceneError({d.issue("bc.type", i, "type = \"" + type + "\" is a static support in this version; a dynamic "
                                              "analysis takes clamped, hinged and fix of whole translations or "
                                              "rotations (a [[joint]] holds points and axes)")});
    }
    for (int id : select_nodes(d, structure.joined, "bc", i)) {
      support.node = id;
      spec.supports.push_back(support);
      if (support.translations) hold(id, false, "bc[" + std::to_string(i) + "]");
      if (support.rotations) hold(id, true, "bc[" + std::to_string(i) + "]");
    }
  }
  warn_probes_on_held_dofs(d, joined, held, false, ctx.warnings);
  std::vector<std::size_t>& load_entry = in.load_entry;
  std::vector<std::size_t>& pressure_entry = in.pressure_entry;
  // [[load]]: the static reading (the same selections, consistent line, surface and pressure
  // forces) on the whole structure, then each entry's time history
  if (with_loads) {
    ShellModelSpec loaded;
    loaded.mesh = structure.joined;
    std::vector<EntryLoads> entry_loads;
    for (std::size_t i = 0; i < d.count("load"); ++i) {
      LoadHistory history;
      history.start = d.number("load.start", i);
      if (d.number("load.end", i) > 0) history.end = d.number("load.end", i);
      history.ramp = d.number("load.ramp", i);
      if (*history.defect())
        throw SceneError({d.issue(d.present("load.end", i) ? "load.end" : "load.ramp", i,
                                  std::string("the load's time history is not usable: ") + history.defect())});
      if (d.string("load.type", i) == "pressure" && d.boolean("load.follower", i))
        throw SceneError({d.issue("load.follower", i, "a follower pressure is a static analysis's load in this version; "
                                                      "in dynamics a pressure is dead (reference normal and area)")});
      const std::size_t loads_before = loaded.loads.size(), pressures_before = loaded.pressures.size();
      read_load(d, i, loaded);
      entry_loads.push_back(
          {i, {loaded.loads.begin() + static_cast<std::ptrdiff_t>(loads_before), loaded.loads.end()},
           {loaded.pressures.begin() + static_cast<std::ptrdiff_t>(pressures_before), loaded.pressures.end()}});
      for (std::size_t k = loads_before; k < loaded.loads.size(); ++k)
        spec.loads.push_back({loaded.loads[k], history}), load_entry.push_back(i);
      for (std::size_t k = pressures_before; k < loaded.pressures.size(); ++k) {
        TimedPressure p;
        p.body = structure.has_junctions ? 0 : structure.quad_part[loaded.pressures[k].quad];
        p.load = loaded.pressures[k];
        p.load.quad -= structure.has_junctions ? 0 : structure.first_quad(p.body);  // the body's own quad number
        p.history = history;
        spec.pressures.push_back(p);
        pressure_entry.push_back(i);
      }
    }
    refuse_loads_on_held_dofs(d, joined, held, entry_loads);
  }
  return in;
}

std::unique_ptr<Simulation> build_shell_dynamic(const Document& d, const std::string& path, const SceneContext& ctx) {
  using namespace ff::shell;
  const std::vector<std::string> fx = d.strings("scene.effects");
  auto has = [&](const char* e) { return std::find(fx.begin(), fx.end(), e) != fx.end(); };
  for (const char* needed : {"elastic", "inertia"})
    if (!has(needed))
      throw SceneError({d.issue("scene.effects", std::string("a dynamic analysis needs the effect '") + needed + "'")});
  if (d.string("scene.analysis") != "dynamic")  // the file's analysis chose this schema; --set cannot change it
    throw SceneError({d.issue("scene.analysis", "the analysis is chosen by the scene file (it picks the keys the "
                                                "scene may have); write analysis = \"" + d.string("scene.analysis") +
                                                "\" in the file instead of setting it")});

  MultibodyInput in = read_multibody_input(d, path, ctx, true, true);
  MultibodySpec& spec = in.spec;
  Structure& structure = in.structure;
  std::vector<std::size_t>& load_entry = in.load_entry;
  std::vector<std::size_t>& pressure_entry = in.pressure_entry;
  refuse_impossible_step_count(d, "solver.dt", "solver.end");
  // solver.tolerance bounds the 2-norm of a Newton correction, in the structure's length unit: one
  // below the round-off of its coordinates is never met (on the double pendulum, about 2 across,
  // 1e-13 converged, 1e-14 had not finished a step in two minutes, 1e-300 "diverged")
  {
    const mesh::ShellMesh& joined = structure.joined;
    Eigen::Vector3d lo = joined.points.front(), hi = lo;
    for (const Eigen::Vector3d& x : joined.points) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
    const double size = (hi - lo).norm(), smallest = kSmallestDynamicTolerance * size;
    if (d.number("solver.tolerance") < smallest) {
      std::ostringstream m;
      m << "a correction of " << d.value_text("solver.tolerance") << " is below the round-off of the coordinates of "
        << "a structure " << size << " across (the 2-norm of a Newton correction, in its length unit): Newton "
        << "cannot reach it; give at least " << smallest << " (" << kSmallestDynamicTolerance << " of the size)";
      throw SceneError({d.issue("solver.tolerance", m.str())});
    }
  }
  ShellDynamicSettings st;
  st.dt = d.number("solver.dt");
  st.end_time = d.number("solver.end");
  st.output_every = static_cast<int>(d.integer("solver.output_every"));
  st.count_until = d.number("solver.count_until");
  if (st.count_until > 1e299) st.count_until = std::numeric_limits<double>::infinity();
  st.integrator.rho_inf = d.number("solver.rho_inf");
  st.integrator.tolerance = d.number("solver.tolerance");
  st.integrator.max_iterations = static_cast<int>(d.integer("solver.max_iterations"));
  const std::string policy = d.string("solver.policy");
  st.integrator.policy = policy == "full"   ? MatrixPolicy::full
                         : policy == "nni"  ? MatrixPolicy::nni
                         : policy == "lazy" ? MatrixPolicy::lazy
                                            : MatrixPolicy::frozen;
  st.integrator.nni_threshold = static_cast<int>(d.integer("solver.nni"));
  const std::string predictor = d.string("solver.predictor");
  st.integrator.predictor = predictor == "previous" || (predictor == "auto" && policy != "frozen")
                                ? AccelerationPredictor::previous
                                : AccelerationPredictor::zero;
  st.integrator.refresh_ratio = d.number("solver.refresh_ratio");
  st.integrator.step_refresh_ratio = d.number("solver.step_refresh_ratio");
  st.integrator.max_cutbacks = static_cast<int>(d.integer("solver.max_cutbacks"));
  st.static_start = d.string("solver.initial_state") == "static_equilibrium";
  st.integrator.backend = read_linear_solver(d, LinearBackend::mumps);
  if (linear_backend_is_symmetric(st.integrator.backend))  // [S kGᵀ; kB 0] is indefinite (G7)
    throw SceneError({d.issue("solver.linear_solver", "'" + d.string("solver.linear_solver") +
                                                      "' needs a symmetric positive definite matrix; the dynamic "
                                                      "iteration matrix with joints is indefinite (use umfpack, "
                                                      "mumps or sparse_lu)")});
  for (std::size_t i = 0; i < d.count("probe"); ++i) {
    const std::vector<int> ids = select_nodes(d, structure.joined, "probe", i);
    const std::string name = d.string("probe.name", i), label = d.string("probe.label", i);
    st.probes.push_back({name, label.empty() ? name : label, ids.front(), vec(d.numbers("probe.direction", i)),
                         probe_reads_stress(d, i) ? d.string("probe.field", i) : std::string()});
  }
  for (std::size_t i = 0; i < d.count("arc"); ++i) {
    std::vector<int> ids = ordered(structure.joined, select_nodes(d, structure.joined, "arc", i));
    if (ids.size() < 2) throw SceneError({d.issue("arc.select", i, "an arc needs at least two nodes")});
    st.arcs.push_back({d.string("arc.name", i), ids});
  }
  auto known_probe = [&](const std::string& n) {
    for (const DynamicProbe& p : st.probes)
      if (p.name == n) return true;
    for (const DynamicArc& a : st.arcs)
      if ("arc_rate_" + a.name == n || "arc_strain_" + a.name == n) return true;
    return false;
  };
  for (std::size_t i = 0; i < d.count("metric"); ++i) {
    DynamicMetric mt;
    mt.name = d.string("metric.name", i);
    if (mt.name.empty())  // summary.json and results.h5 key the metric by its name
      throw SceneError({d.issue("metric.name", i, "a metric needs a name (its key in summary.json and results.h5)")});
    mt.probe = d.string("metric.probe", i);
    const std::string kind = d.string("metric.kind", i);
    mt.kind = kind == "min" ? DynamicMetric::Kind::min
              : kind == "max" ? DynamicMetric::Kind::max
              : kind == "max_abs" ? DynamicMetric::Kind::max_abs
              : kind == "mean" ? DynamicMetric::Kind::mean
                                  : DynamicMetric::Kind::final_value;
    if (!known_probe(mt.probe)) throw SceneError({d.issue("metric.probe", i, "no probe called '" + mt.probe + "'")});
    st.metrics.push_back(mt);
  }
  // [[timeline]] gravity changes, applied by the simulation exactly at their time
  const Timeline timeline = read_timeline(d, st.end_time);
  for (std::size_t i = 0, k = 0; i < d.count("timeline"); ++i) {
    if (!d.present("timeline.gravity", i)) continue;
    if (!spec.gravity) throw SceneError({d.issue("timeline.gravity", i, "changes gravity, but scene.effects lacks gravity")});
    while (timeline.changes[k].key != "gravity") ++k;
    const std::vector<double>& g = timeline.changes[k++].value;
    st.gravity_changes.push_back({d.number("timeline.at", i), Vec3(g[0], g[1], g[2])});
  }
  RunInfo info;
  describe_run(d, path, info);
  // how an imported mesh was read
  for (auto& setting : mesh_import_settings(structure)) info.settings.push_back(std::move(setting));
  info.effects = fx;
  st.record_stresses = stresses_wanted(d, {"displacement", "strain", shell::kErrorIndicatorField});
  st.record_error_indicator = d.boolean("output.error_bar") || d.string("output.color_field") == shell::kErrorIndicatorField;
  try {
    auto sim = std::make_unique<ShellDynamicSimulation>(std::move(spec), std::move(st), std::move(info));
    // the stress fields follow the structure's layup: known once its elements are built
    refuse_unknown_probe_fields(d, shell::stress_fields(sim->model().stress_layout()));
    refuse_unknown_color_field(d, sim->info());
    return sim;
  } catch (const shell::LoadSpecError& e) {
    const std::vector<std::size_t>& entry = e.part() == shell::LoadSpecError::Part::nodal_load ? load_entry : pressure_entry;
    const std::size_t i = e.index() >= 0 && static_cast<std::size_t>(e.index()) < entry.size() ? entry[e.index()] : 0;
    throw SceneError({d.issue("load.type", i, e.what())});
  } catch (const shell::BodySpecError& e) {
    using Part = shell::BodySpecError::Part;
    const std::size_t b = static_cast<std::size_t>(e.body());
    // the part of a shell body (the part at the quad when the body is the joined structure)
    const std::size_t part = structure.has_junctions && e.quad() >= 0
                                 ? static_cast<std::size_t>(structure.quad_part.at(e.quad()))
                                 : std::min(b, structure.parts.size() - 1);
    const int material = structure.parts[part].material;
    switch (e.part()) {
      case Part::shell_element:
        // det J <= 0 through the thickness: the thickness against the curvature, or a distorted mesh
        throw SceneError({thickness_issue(d, structure, material,
                                          std::string(e.what()) + " (a thickness larger than the local radius of curvature, "
                                                                  "or a distorted mesh, makes the element invalid)")});
      case Part::shell_density:
        throw SceneError({density_issue(d, structure, material, e.what())});
      case Part::rigid_mass: throw SceneError({d.issue("rigid.mass", b, e.what())});
      case Part::rigid_inertia: throw SceneError({d.issue("rigid.inertia", b, e.what())});
    }
    throw SceneError({d.issue("scene.effects", e.what())});
  } catch (const std::invalid_argument& e) {
    throw SceneError({d.issue("scene.effects", e.what())});
  }
}

}  // namespace ff::scene
