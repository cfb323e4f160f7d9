#include "core/scene/shell_dynamic_scene.h"

#include <algorithm>
#include <sstream>
#include <cmath>
#include <limits>
#include <numbers>

#include "core/mesh/generators.h"
#include "core/scene/node_selection.h"
#include "core/scene/scene_common.h"
#include "core/scene/timeline.h"
#include "core/shell/shell_dynamic_simulation.h"

namespace ff::scene {

namespace {
Eigen::Vector3d vec(const std::vector<double>& v) { return Eigen::Vector3d(v[0], v[1], v[2]); }
constexpr double kDeg = std::numbers::pi / 180.0;
}  // namespace

const Schema& shell_dynamic_schema() {
  static const Schema schema = [] {
    Schema s;
    declare_scene_table(s,
                        "effects to simulate: elastic and inertia (required), gravity, hr, ans, drilling (6 DoF "
                        "per shell node), joints (the [[joint]] constraints)",
                        {"elastic", "inertia", "gravity", "hr", "ans", "drilling", "joints"});
    s.table("solver", "time stepping: Lie-group generalized-alpha (core/solve/generalized_alpha.md)", true)
        .number("solver.dt", "time step [s]", std::nullopt, Range::positive())
        .number("solver.end", "end time [s]", std::nullopt, Range::positive())
        .integer("solver.output_every", "publish (store, render) every n-th step", 10, IntRange::closed(1, 1000000))
        .number("solver.count_until", "NOI/NOU are also counted up to this time (metrics NOI_window, NOU_window)",
                1e300, Range::positive())
        .number("solver.rho_inf", "spectral radius at infinity", 0.9, Range::closed(0.0, 1.0))
        .number("solver.tolerance", "Newton stops when the 2-norm of the correction is below this", 1e-6,
                Range::left_open(0.0, 1.0))
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
                 IntRange::closed(0, 20));
    declare_linear_solver(s, "mumps where compiled in, else umfpack: 14 % less wall time on the double pendulum, "
                             "docs/validation/shell-dynamics.md");
    s.table("gravity", "uniform gravity (effect gravity)")
        .number_list("gravity.g", "acceleration of gravity [m/s^2]", std::vector<double>{0, 0, -9.81}, {}, 3, 3)
        .live("gravity.g");
    s.table_array("shell", "flexible CB shell bodies", 1, 16)
        .string("shell.name", "body name (joints, probes and patch_edge selections use it)", std::nullopt)
        .choice("shell.generator", "cut_cylinder: cylinder with axis along y cut by two parallel end planes "
                "y = end_slope x + y0 and y = end_slope x + y0 + length; rectangular_plate: plate in the xy plane",
                {"cut_cylinder", "rectangular_plate"}, std::nullopt)
        .integer("shell.n1", "elements along the arc (cut_cylinder) or the length (plate)", 15, IntRange::closed(1, 512))
        .integer("shell.n2", "elements along the axis (cut_cylinder) or the width (plate)", 15, IntRange::closed(1, 512))
        .number("shell.radius", "cut_cylinder: radius", 1.0, Range::positive())
        .number_list("shell.center", "cut_cylinder: [x, z] of the axis", std::vector<double>{0, 0}, {}, 2, 2)
        .number("shell.phi_start", "cut_cylinder: start angle in the xz plane [deg] (x = cx + R cos, z = cz + R sin)",
                180.0)
        .number("shell.phi_end", "cut_cylinder: end angle [deg]", 0.0)
        .number("shell.length", "cut_cylinder: extent along y; plate: length along x", 1.0, Range::positive())
        .number("shell.width", "rectangular_plate: width along y", 1.0, Range::positive())
        .number_list("shell.origin", "rectangular_plate: corner", std::vector<double>{0, 0, 0}, {}, 3, 3)
        .number("shell.end_slope", "cut_cylinder: dy/dx of the end planes (tan of their angle to the xz plane)", 0.0)
        .number("shell.y0", "cut_cylinder: y of the first end plane at x = 0", 0.0)
        .number("shell.youngs_modulus", "E [Pa]", std::nullopt, Range::positive())
        .number("shell.poisson_ratio", "nu", 0.3, Range::right_open(0.0, 0.5))
        .number("shell.thickness", "h0 [m]", std::nullopt, Range::positive())
        .number("shell.density", "rho [kg/m^3]", std::nullopt, Range::positive())
        .number("shell.drilling_factor", "c in gamma = c G h0 (effect drilling)", 1e-3, Range::left_open(0.0, 1e3));
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
        .string("joint.body", "body whose nodes the selector picks", std::nullopt)
        .string("joint.other", "second body (its node coincident with each selected node); \"\" = ground",
                std::string{})
        .number_list("joint.axis", "revolute: axis direction (global, reference configuration)",
                     std::vector<double>{0, 1, 0}, {}, 3, 3);
    declare_selector_keys(s, "joint", EdgeNames::parametric_only);
    s.table_array("probe", "node displacements recorded every step (direction . u)", 0, 32)
        .string("probe.name", "probe name (also the plot file name)", std::nullopt)
        .string("probe.label", "plot label", std::string{})
        .string("probe.body", "body the node belongs to", std::nullopt)
        .number_list("probe.direction", "global direction the displacement is projected on", std::nullopt, {}, 3, 3);
    declare_selector_keys(s, "probe", EdgeNames::parametric_only);
    s.table_array("arc", "curves whose relative chord and length changes are recorded (arc_rate_<name>)", 0, 16)
        .string("arc.name", "arc name", std::nullopt)
        .string("arc.body", "body the nodes belong to", std::nullopt);
    declare_selector_keys(s, "arc", EdgeNames::parametric_only);
    s.table_array("metric", "numbers written to summary.json", 0, 32)
        .string("metric.name", "metric name", std::nullopt)
        .choice("metric.kind", "how it is read from the history", {"min", "max", "max_abs", "final"}, std::nullopt)
        .string("metric.probe", "probe (or arc_rate_<arc>, arc_strain_<arc>) it reads", std::nullopt);
    declare_output_keys(s, {"displacement", "strain"}, true);
    declare_timeline(s, "time of the event", "s", {"gravity"});
    // one vocabulary across models: time stepping and the integrator are the [solver] table
    s.renamed("time", "solver").renamed("integrator", "solver");
    return s;
  }();
  return schema;
}

namespace {
mesh::ShellMesh body_mesh(const Document& d, std::size_t i) {
  const std::string name = d.string("shell.name", i), gen = d.string("shell.generator", i);
  const int n1 = static_cast<int>(d.integer("shell.n1", i)), n2 = static_cast<int>(d.integer("shell.n2", i));
  try {
    if (gen == "rectangular_plate") {
      mesh::RectangularPlate p;
      p.a = d.number("shell.length", i);
      p.b = d.number("shell.width", i);
      p.origin = vec(d.numbers("shell.origin", i));
      return mesh::rectangular_plate(p, n1, n2, name);
    }
    const std::vector<double> c = d.numbers("shell.center", i);
    const double R = d.number("shell.radius", i), p0 = d.number("shell.phi_start", i) * kDeg,
                 p1 = d.number("shell.phi_end", i) * kDeg, L = d.number("shell.length", i),
                 slope = d.number("shell.end_slope", i), y0 = d.number("shell.y0", i);
    if (std::abs(p1 - p0) < 1e-9 || std::abs(p1 - p0) > 2 * std::numbers::pi)
      throw SceneError({d.issue("shell.phi_end", i, "the arc must span more than 0 and at most 360 degrees")});
    // as for static cylinders (mesh_generator_keys.cpp): at most 120 degrees an element (at 180 its
    // corners and directors lie in one plane through the axis), and thinner than the radius
    const double span_deg = std::abs(p1 - p0) / kDeg;
    if (span_deg / n1 > 120.0 * (1 + 1e-12)) {
      std::ostringstream m;
      m << "shell.n1 = " << n1 << " element(s) over the arc span " << span_deg / n1
        << " degrees each; an element may span at most 120 (at 180 the stiffness is singular)";
      throw SceneError({d.issue("shell.n1", i, m.str())});
    }
    if (!(d.number("shell.thickness", i) < R)) {
      const std::string m = "shell body '" + name + "' is at least as thick as its radius (" + d.value_text("shell.thickness", i) +
                            " against " + d.value_text("shell.radius", i) + "); a shell must be thinner than its radius "
                            "of curvature";
      throw SceneError({d.issue("shell.thickness", i, m), d.issue("shell.radius", i, m)});
    }
    // outward normal when the arc runs clockwise in (x, z) seen from +y ... keep it the radial direction
    const double cx = c[0], cz = c[1];
    return mesh::parametric_patch(
        name, "cylinder R=" + std::to_string(R) + " cut by planes y = " + std::to_string(slope) + " x + const", n1, n2,
        [=](double u, double v) {
          const double phi = p0 + u * (p1 - p0);
          const Eigen::Vector3d radial(std::cos(phi), 0.0, std::sin(phi));
          const double x = cx + R * radial.x(), z = cz + R * radial.z();
          return mesh::SurfacePoint{Eigen::Vector3d(x, slope * x + y0 + v * L, z), radial};
        });
  } catch (const std::invalid_argument& e) {
    throw SceneError({d.issue("shell.generator", i, e.what())});
  }
}

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

std::unique_ptr<Simulation> build_shell_dynamic(const Document& d, const std::string& path, const SceneContext& ctx) {
  using namespace ff::shell;
  const std::vector<std::string> fx = d.strings("scene.effects");
  auto has = [&](const char* e) { return std::find(fx.begin(), fx.end(), e) != fx.end(); };
  for (const char* needed : {"elastic", "inertia"})
    if (!has(needed))
      throw SceneError({d.issue("scene.effects", std::string("a shell_dynamic scene needs the effect '") + needed + "'")});

  MultibodySpec spec;
  // every body's nodes from its counts (a 360-degree arc merges its seam), so that bodies that
  // cannot fit are refused at the largest one's count before any mesh is built
  std::string count_key = "shell.n1";
  {
    long long total = 0, largest_nodes = -1;
    std::size_t largest = 0;
    for (std::size_t i = 0; i < d.count("shell"); ++i) {
      const int n1 = static_cast<int>(d.integer("shell.n1", i)), n2 = static_cast<int>(d.integer("shell.n2", i));
      const double span = std::abs(d.number("shell.phi_end", i) - d.number("shell.phi_start", i));
      const bool closed = d.string("shell.generator", i) == "cut_cylinder" && std::abs(span - 360.0) <= 1e-9 * 360.0 && n1 > 1;
      const long long nodes = mesh::patch_node_count(n1, n2, closed, false);
      total += nodes;
      if (nodes > largest_nodes) largest_nodes = nodes, largest = i;
    }
    if (total > 0) {
      count_key = d.integer("shell.n1", largest) >= d.integer("shell.n2", largest) ? "shell.n1" : "shell.n2";
      refuse_oversized(d, ctx, static_cast<int>(std::min<long long>(total, std::numeric_limits<int>::max())),
                       has("drilling") ? 1.0 : 0.0, count_key, static_cast<int>(largest));
    }
  }
  std::vector<std::string> names;
  for (std::size_t i = 0; i < d.count("shell"); ++i) {
    ShellBodySpec b;
    b.name = d.string("shell.name", i);
    if (std::find(names.begin(), names.end(), b.name) != names.end())
      throw SceneError({d.issue("shell.name", i, "another body is already called '" + b.name + "'")});
    names.push_back(b.name);
    b.mesh = body_mesh(d, i);
    b.section = {d.number("shell.youngs_modulus", i), d.number("shell.poisson_ratio", i), d.number("shell.thickness", i),
                 5.0 / 6.0};
    b.density = d.number("shell.density", i);
    b.options.hr = has("hr");
    b.options.ans = has("ans");
    b.options.drilling = has("drilling");
    b.options.drilling_factor = d.number("shell.drilling_factor", i);
    spec.shells.push_back(std::move(b));
  }
  {
    // the static fit (shell_model.cpp) for all bodies together, at the largest body's mesh size
    int total = 0, largest = 0;
    for (std::size_t i = 0; i < spec.shells.size(); ++i) {
      total += spec.shells[i].mesh.node_count();
      if (spec.shells[i].mesh.node_count() > spec.shells[largest].mesh.node_count()) largest = static_cast<int>(i);
    }
    if (total > 0) refuse_oversized(d, ctx, total, has("drilling") ? 1.0 : 0.0, count_key, largest);
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

  // a body by name: its mesh (shells) and the model-wide id of its local node 0
  std::vector<int> offsets;
  int total = 0;
  for (const ShellBodySpec& b : spec.shells) offsets.push_back(total), total += b.mesh.node_count();
  auto body_index = [&](const std::string& table, const std::string& key, std::size_t i, bool allow_rigid) {
    const std::string name = d.string(table + "." + key, i);
    for (std::size_t b = 0; b < spec.shells.size(); ++b)
      if (spec.shells[b].name == name) return static_cast<int>(b);
    for (std::size_t r = 0; r < spec.rigid.size(); ++r)
      if (spec.rigid[r].name == name) {
        if (allow_rigid) return static_cast<int>(spec.shells.size() + r);
        throw SceneError({d.issue(table + "." + key, i, "'" + name + "' is a rigid body; select nodes of a shell body")});
      }
    throw SceneError({d.issue(table + "." + key, i, "no body called '" + name + "'")});
  };
  auto node_id = [&](int body, int local) {
    return body < static_cast<int>(spec.shells.size()) ? offsets[body] + local
                                                       : total + (body - static_cast<int>(spec.shells.size()));
  };
  auto position_of = [&](int body, int local) {
    return body < static_cast<int>(spec.shells.size()) ? spec.shells[body].mesh.points[local]
                                                       : spec.rigid[body - spec.shells.size()].pose.p;
  };

  if (d.count("joint") > 0 && !has("joints"))
    throw SceneError({d.issue("scene.effects", "the scene has [[joint]] entries but not the effect 'joints'")});
  for (std::size_t i = 0; i < d.count("joint"); ++i) {
    const std::string type = d.string("joint.type", i);
    const int a = body_index("joint", "body", i, false);
    const std::vector<int> ids = select_nodes(d, spec.shells[a].mesh, "joint", i);
    const bool ground = d.string("joint.other", i).empty();
    if (type == "simple_support" && !ground)
      throw SceneError({d.issue("joint.other", i, "a simple support holds nodes in space: leave 'other' empty")});
    const int b = ground ? -1 : body_index("joint", "other", i, true);
    if (b == a) throw SceneError({d.issue("joint.other", i, "a joint needs two different bodies")});
    const double tol = 1e-6 * std::max(1.0, mesh::max_edge_length(spec.shells[a].mesh));
    std::vector<std::pair<int, int>> pairs;  // model-wide (node a, node b or -1)
    for (int id : ids) {
      int partner = -1;
      if (!ground) {
        if (b >= static_cast<int>(spec.shells.size())) {
          partner = node_id(b, 0);
        } else {
          const mesh::ShellMesh& mb = spec.shells[b].mesh;
          for (int k = 0; k < mb.node_count(); ++k)
            if ((mb.points[k] - position_of(a, id)).norm() < tol) partner = node_id(b, k);
          if (partner < 0)
            throw SceneError({d.issue("joint.other", i, "node at (" + std::to_string(position_of(a, id).x()) + ", " +
                                                            std::to_string(position_of(a, id).y()) + ", " +
                                                            std::to_string(position_of(a, id).z()) +
                                                            ") has no coincident node in body '" +
                                                            d.string("joint.other", i) + "'")});
        }
      }
      pairs.push_back({node_id(a, id), partner});
    }
    const bool six = spec.shells[a].options.drilling;
    const bool other_rigid = b >= static_cast<int>(spec.shells.size());
    for (const auto& [na, nb] : pairs) {
      PositionConstraint pc;
      pc.a = na;
      pc.b = nb;
      pc.target = position_of(a, na - offsets[a]);
      // a rigid body carries the joint point at its offset from the centre of mass (body axes = W at t = 0)
      if (other_rigid) pc.b_offset = pc.target - spec.rigid[b - spec.shells.size()].pose.p;
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
        const Eigen::Vector3d p0 = position_of(a, pairs.front().first - offsets[a]);
        for (const auto& pr : pairs) {
          const Eigen::Vector3d off = position_of(a, pr.first - offsets[a]) - p0;
          if ((off - off.dot(axis) * axis).norm() > tol)
            throw SceneError({d.issue("joint.axis", i, "the selected nodes do not lie on one line along the axis; "
                                                       "a 5-DoF revolute joint is the line of its nodes")});
        }
      } else {
        // rows (D13): two (revolute) or three (fixed) perpendicularities per pair, from the reference frames
        Eigen::Vector3d e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
        for (const auto& [na, nb] : pairs) {
          const Mat3& Ra = spec.shells[a].mesh.frames[na - offsets[a]];
          const Mat3 Rb = nb < 0 ? Mat3::Identity()
                                 : (b < static_cast<int>(spec.shells.size())
                                        ? spec.shells[b].mesh.frames[nb - offsets[b]]
                                        : spec.rigid[b - spec.shells.size()].pose.R);
          auto row = [&](const Eigen::Vector3d& u, const Eigen::Vector3d& w) {
            spec.perpendiculars.push_back({na, nb, Ra.transpose() * u, nb < 0 ? w : Eigen::Vector3d(Rb.transpose() * w)});
          };
          row(axis, e1), row(axis, e2);
          if (type == "fixed") row(e1, e2);
        }
      }
    }
  }

  refuse_impossible_step_count(d, "solver.dt", "solver.end");
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
  st.integrator.backend = read_linear_solver(d, LinearBackend::mumps);
  if (linear_backend_is_symmetric(st.integrator.backend))  // [S kGᵀ; kB 0] is indefinite (G7)
    throw SceneError({d.issue("solver.linear_solver", "'" + d.string("solver.linear_solver") +
                                                      "' needs a symmetric positive definite matrix; the dynamic "
                                                      "iteration matrix with joints is indefinite (use umfpack, "
                                                      "mumps or sparse_lu)")});
  for (std::size_t i = 0; i < d.count("probe"); ++i) {
    const int b = body_index("probe", "body", i, false);
    const std::vector<int> ids = select_nodes(d, spec.shells[b].mesh, "probe", i);
    const std::string name = d.string("probe.name", i), label = d.string("probe.label", i);
    st.probes.push_back({name, label.empty() ? name : label, node_id(b, ids.front()), vec(d.numbers("probe.direction", i))});
  }
  for (std::size_t i = 0; i < d.count("arc"); ++i) {
    const int b = body_index("arc", "body", i, false);
    std::vector<int> ids = ordered(spec.shells[b].mesh, select_nodes(d, spec.shells[b].mesh, "arc", i));
    if (ids.size() < 2) throw SceneError({d.issue("arc.select", i, "an arc needs at least two nodes")});
    for (int& id : ids) id = node_id(b, id);
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
    mt.probe = d.string("metric.probe", i);
    const std::string kind = d.string("metric.kind", i);
    mt.kind = kind == "min" ? DynamicMetric::Kind::min
              : kind == "max" ? DynamicMetric::Kind::max
              : kind == "max_abs" ? DynamicMetric::Kind::max_abs
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
  info.effects = fx;
  try {
    return std::make_unique<ShellDynamicSimulation>(std::move(spec), std::move(st), std::move(info));
  } catch (const shell::BodySpecError& e) {
    using Part = shell::BodySpecError::Part;
    const std::size_t b = static_cast<std::size_t>(e.body());
    switch (e.part()) {
      case Part::shell_element:
        // det J <= 0 through the thickness: the thickness against the curvature, or a distorted mesh
        throw SceneError({d.issue("shell.thickness", b,
                                  std::string(e.what()) + " (a thickness larger than the local radius of curvature, "
                                                          "or a distorted mesh, makes the element invalid)")});
      case Part::shell_density: throw SceneError({d.issue("shell.density", b, e.what())});
      case Part::rigid_mass: throw SceneError({d.issue("rigid.mass", b, e.what())});
      case Part::rigid_inertia: throw SceneError({d.issue("rigid.inertia", b, e.what())});
    }
    throw SceneError({d.issue("scene.effects", e.what())});
  } catch (const std::invalid_argument& e) {
    throw SceneError({d.issue("scene.effects", e.what())});
  }
}

}  // namespace ff::scene
