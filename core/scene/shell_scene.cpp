#include "core/scene/shell_scene.h"

#include <algorithm>
#include <functional>
#include <cmath>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>
#include <toml++/toml.h>

#include "core/mesh/generators.h"
#include "core/mesh/node_sets.h"
#include "core/scene/mesh_file.h"
#include "core/scene/mesh_generator_keys.h"
#include "core/scene/mesh_quality_report.h"
#include "core/scene/node_selection.h"
#include "core/scene/reference_csv.h"
#include "core/scene/shell_boundary.h"
#include "core/scene/structure_parts.h"
#include "core/scene/scene_common.h"
#include "core/scene/timeline.h"
#include "core/scene/shell_eigen_scene.h"
#include "core/shell/shell_eigen_simulation.h"
#include "core/shell/shell_static_simulation.h"

namespace ff::scene {

namespace fs = std::filesystem;

const Schema& shell_static_schema() {
  static const Schema schema = [] {
    Schema s;
    declare_shell_structure_scene_keys(s);
    s.table_array("metric", "numbers written to summary.json", 0, 32)
        .string("metric.name", "metric name", std::nullopt)
        .choice("metric.kind", "how it is read from the path",
                {"at_load", "final", "first_limit_load", "at_first_limit", "min_load_after_limit", "max_abs",
                 "linear_buckling_load"},
                std::nullopt)
        .string("metric.probe", "probe it reads", std::string{})
        .number("metric.load",
                "at_load: the load where the probe is read, in reported units (load = lambda x solver.load_scale, "
                "not lambda); load control lands a step on it, arc length interpolates between steps",
                0.0);
    s.table_array("imperfection",
                  "geometric imperfections from modes: the structure starts from its mesh moved by amplitude x a mode "
                  "of a modal or buckling scene of the same structure (core/shell/shell_eigen.md §4), computed at "
                  "set-up; several add up",
                  0, 8)
        .string("imperfection.from",
                "the eigen-analysis scene (analysis = \"modal\" or \"buckling\"), relative to this scene file; its "
                "mesh must be this structure's, node for node",
                std::nullopt)
        .integer("imperfection.mode", "which of its modes (1 = the lowest)", 1, IntRange::closed(1, 500))
        .number("imperfection.amplitude",
                "largest nodal translation of the imperfection, in the scene's length unit (the sign flips the mode); "
                "its size between 1e-9 and 1 times the structure's size (the diagonal of its bounding box): "
                "smaller moves nothing a path can see, larger is another structure",
                std::nullopt);
    s.table_array("reference", "reference curves drawn on the load-path plots", 0, 16)
        .string("reference.file", "CSV file relative to the scene file", std::nullopt)
        .string("reference.x_column", "column giving the load (or load ratio)", std::nullopt)
        .number("reference.x_scale", "load = x_scale x column value", 1.0)
        .string("reference.y_column", "column giving the displacement", std::nullopt)
        .number("reference.y_scale", "probe value = y_scale x column value", 1.0)
        .string("reference.probe", "probe the curve belongs to", std::nullopt)
        .string("reference.label", "legend", std::string("reference"));
    s.table("solver", "nonlinear statics", true)
        .choice("solver.method",
                "linear (one solve at the reference state: small displacements, core/shell/shell_model.md §L), "
                "load_control (Newton with cut-backs) or arc_length",
                {"linear", "load_control", "arc_length"}, "load_control")
        .number("solver.load_scale", "load reported per unit lambda (for plots and metrics)", 1.0)
        .string("solver.load_label", "name of the load on plots", std::string("load"))
        .number("solver.end", "load factor to reach (the end of the run)", 1.0, Range::positive())
        .number("solver.initial_step", "first load step (load control) or load increment (arc length)", 0.05,
                Range::left_open(0.0, 1.0))
        .number("solver.max_step", "largest load step (load control); at least solver.initial_step", 0.1, Range::left_open(0.0, 1.0))
        .number("solver.min_step", "smallest load step before giving up", 1e-5, Range::left_open(0.0, 1.0))
        .number("solver.tolerance", "relative residual and increment tolerance", 1e-8, Range::left_open(0.0, 1e-2))
        .integer("solver.max_iterations", "Newton corrections per attempt", 25, IntRange::closed(2, 500))
        .boolean("solver.stop_at_limit_point",
                 "load control: refuse iterates that change the sign of det K (a limit point lies ahead)", true)
        .choice("solver.arc_method", "arc-length constraint", {"crisfield", "lam_morley"}, "crisfield")
        .integer("solver.desired_iterations",
                 "arc length: a step needing more corrections than this shortens the next by sqrt(desired / used)", 5,
                 IntRange::closed(1, 50))
        .number("solver.target_turn",
                "arc length: the angle [deg] between predictor and converged increment the step length aims at "
                "(long steps where the path is straight, short ones where it turns)", 8.0, Range::left_open(0.0, 45.0))
        .number("solver.max_turn",
                "arc length: a step turning more than this [deg] from the tangent at its start or end is retried "
                "shorter (it may have left the path); 0 = no such guard", 24.0, Range::closed(0.0, 90.0))
        .number("solver.max_growth", "arc length: largest growth of the arc length from one step to the next", 2.0,
                Range::closed(1.0, 10.0))
        .choice("solver.tangent",
                "full: a new tangent at every correction (quadratic Newton); modified: keep the factorization while "
                "the residual contracts by at least half per correction, refactor after 4 on one", {"full", "modified"},
                "full")
        .integer("solver.max_steps", "arc length: step budget", 400, IntRange::closed(1, 100000))
        .number("solver.min_load_factor",
                "arc length: lowest load factor the path may reach (a reversed load); a step below it ends the run "
                "incomplete (the range is [min_load_factor, end]; -1: the full load reversed)",
                -1.0, Range::at_most(0.0))
        .boolean("solver.stop_at_first_limit_point",
                 "arc length: end the run (completed) at the first limit point of the load path", false)
        .string("solver.monitor_probe", "arc length: probe whose displacement limit ends the run", std::string{})
        .number("solver.displacement_limit", "arc length: stop when |monitor probe| reaches this", 1e300, Range::positive());
    declare_linear_solver(s, "mumps where compiled in, LDLᵀ when the tangent is symmetric: 1.4-2.3x faster than umfpack on 16 x 16 to 128 x 128 plates, chosen by measurement: core/solve/static_solvers.md §7");
    declare_output_keys(s, {"displacement", "strain"}, true, stress_field_names());
    declare_timeline(s, "load factor of the event (statics: camera keys only)", "", {});
    // one vocabulary across models (the end of a run, material constants)
    s.renamed("solver.lambda_end", "solver.end").renamed("drilling.factor", "material.drilling_factor");
    // one structure vocabulary for every analysis: the shell is made of [[part]] tables
    s.renamed("mesh", "part");
    return s;
  }();
  return schema;
}

namespace {
bool arc_length_method(const Document& d) { return d.string("solver.method") == "arc_length"; }

// A key of the other path-following method is refused at its line, as a mesh key of another
// generator is: the method would silently ignore it
void check_method_keys(const Document& d) {
  static const std::vector<std::string> arc_length_only = {
      "arc_method", "desired_iterations", "target_turn",     "max_turn",       "max_growth",
      "max_steps",  "monitor_probe",      "displacement_limit", "min_load_factor", "stop_at_first_limit_point"};
  static const std::vector<std::string> load_control_only = {"max_step", "min_step", "stop_at_limit_point"};
  const std::string method = d.string("solver.method");
  const bool arc = method == "arc_length";
  if (method == "linear") {
    // one solve: no step, no iteration, no path to follow
    static const std::vector<std::string> path_keys = {"initial_step", "max_step", "min_step", "tolerance",
                                                       "max_iterations", "tangent"};
    std::vector<std::string> keys = arc_length_only;
    keys.insert(keys.end(), load_control_only.begin(), load_control_only.end());
    keys.insert(keys.end(), path_keys.begin(), path_keys.end());
    for (const std::string& k : keys)
      if (d.present("solver." + k))
        throw SceneError({d.issue("solver." + k, "solver." + k + " belongs to a nonlinear method (load_control or "
                                                 "arc_length); method = \"linear\" solves once at the reference state "
                                                 "and would ignore it")});
    return;
  }
  for (const std::string& k : arc ? load_control_only : arc_length_only)
    if (d.present("solver." + k))
      throw SceneError({d.issue("solver." + k, "solver." + k + " belongs to method = \"" +
                                                   (arc ? "load_control" : "arc_length") + "\"; this scene's method = \"" +
                                                   method + "\" would ignore it")});
}
}  // namespace

namespace {
// the sizes of an imperfection's amplitude, as fractions of the structure's size
constexpr double kSmallestImperfection = 1e-9, kLargestImperfection = 1.0;
std::string text_of(double v) {
  std::ostringstream s;
  s.precision(6);
  s << v;
  return s.str();
}

// [[imperfection]]: the mesh moved by amplitude x a mode of an eigen-analysis scene of the same
// structure, computed here (shell_eigen.md §4); refused at the entry's keys when the file is no
// such scene, its mesh is another one, it has fewer modes or its analysis fails
void apply_imperfections(const Document& d, const std::string& path, const SceneContext& ctx, mesh::ShellMesh& mesh) {
  // the structure's size, the diagonal of its bounding box: what an amplitude is measured against
  Eigen::Vector3d lo = mesh.points.front(), hi = lo;
  for (const Eigen::Vector3d& x : mesh.points) lo = lo.cwiseMin(x), hi = hi.cwiseMax(x);
  const double size = (hi - lo).norm();
  for (std::size_t i = 0; i < d.count("imperfection"); ++i) {
    // an imperfection is small beside the structure but must move it: below 1e-9 of its size the
    // path meets the perfect structure's bifurcation, which load control cannot pass (an amplitude
    // of 0 ended "diverged" at the buckling load); one of the structure's own size is no longer
    // an imperfection, and its quads fold
    const double amplitude = d.number("imperfection.amplitude", i);
    if (!(std::abs(amplitude) >= kSmallestImperfection * size) || !(std::abs(amplitude) <= kLargestImperfection * size))
      throw SceneError({d.issue("imperfection.amplitude", i,
                                "an amplitude of " + d.value_text("imperfection.amplitude", i) + " on a structure of size " +
                                    text_of(size) + " (its bounding box's diagonal): |amplitude| must lie in [" +
                                    text_of(kSmallestImperfection * size) + ", " + text_of(kLargestImperfection * size) +
                                    "] (1e-9 to 1 times the size); " +
                                    (std::abs(amplitude) < kSmallestImperfection * size
                                         ? "a smaller one leaves the path at the perfect structure's bifurcation, "
                                           "which it cannot pass (remove the [[imperfection]] to load the perfect "
                                           "structure)"
                                         : "a geometric imperfection is a fraction of the structure (typically of "
                                           "the order of its thickness)"))});
    const fs::path file = fs::path(path).parent_path() / d.string("imperfection.from", i);
    std::error_code ec;
    if (!fs::is_regular_file(file, ec))
      throw SceneError({d.issue("imperfection.from", i, "no file '" + file.string() + "' (the path is relative to this scene's folder)")});
    if (fs::equivalent(file, fs::path(path), ec))
      throw SceneError({d.issue("imperfection.from", i, "names this scene itself; give the modal or buckling scene of the same structure")});
    // its scene.analysis picks its schema, as load_scene does
    std::string analysis;
    try {
      analysis = toml::parse(read_scene_text(file.string()), file.string())["scene"]["analysis"].value_or(std::string());
    } catch (const SceneError& e) {
      throw SceneError({d.issue("imperfection.from", i, "'" + file.string() + "': " + e.issues.front().message)});
    } catch (const toml::parse_error& e) {
      throw SceneError({d.issue("imperfection.from", i, "'" + file.string() + "' is not a TOML file: " +
                                                            std::string(e.description()))});
    }
    if (analysis != "modal" && analysis != "buckling")
      throw SceneError({d.issue("imperfection.from", i, "'" + file.string() + "' has analysis = \"" + analysis +
                                                            "\"; an imperfection takes its shape from a modal or "
                                                            "buckling analysis of the same structure")});
    std::unique_ptr<Simulation> eigen;
    try {
      const bool modal = analysis == "modal";
      const Document e = validate_file(modal ? shell_modal_schema() : shell_buckling_schema(), file.string());
      eigen = modal ? build_shell_modal(e, file.string(), ctx) : build_shell_buckling(e, file.string(), ctx);
    } catch (const SceneError& e) {
      throw SceneError({d.issue("imperfection.from", i, "'" + file.string() + "' is not a valid " + analysis +
                                                            " scene: " + e.what())});
    }
    auto* sim = dynamic_cast<shell::ShellEigenSimulation*>(eigen.get());
    if (!sim) throw std::logic_error("an eigen scene built no eigen simulation");
    const mesh::ShellMesh& theirs = sim->model().spec().mesh;
    bool same = theirs.node_count() == mesh.node_count() && theirs.quad_count() == mesh.quad_count();
    for (int n = 0; same && n < mesh.node_count(); ++n)
      same = (theirs.points[n] - mesh.points[n]).norm() <= 1e-9 * (1.0 + mesh.points[n].norm());
    if (!same)
      throw SceneError({d.issue("imperfection.from", i, "'" + file.string() + "' has another mesh (" +
                                                            std::to_string(theirs.node_count()) + " nodes, this structure " +
                                                            std::to_string(mesh.node_count()) +
                                                            "): an imperfection needs the same structure, node for node")});
    const int wanted = static_cast<int>(d.integer("imperfection.mode", i));
    if (const std::string why = sim->compute(); !why.empty())
      throw SceneError({d.issue("imperfection.from", i, "its " + analysis + " analysis failed: " + why)});
    if (wanted > sim->mode_vectors().cols())
      throw SceneError({d.issue("imperfection.mode", i, "mode " + std::to_string(wanted) + " asked, but '" + file.string() +
                                                            "' computes " + std::to_string(sim->mode_vectors().cols()) +
                                                            " (its " + analysis + ".modes)")});
    const mesh::ShellMesh moved = shell::perturbed_mesh(sim->model(), sim->mode_vectors().col(wanted - 1), amplitude);
    // the move is relative to the eigen scene's reference: apply it to this mesh (equal up to round-off)
    for (int n = 0; n < mesh.node_count(); ++n) {
      mesh.points[n] += moved.points[n] - theirs.points[n];
      mesh.frames[n] = moved.frames[n] * theirs.frames[n].transpose() * mesh.frames[n];
      mesh.normals[n] = mesh.frames[n].col(2);
    }
    for (std::size_t q = 0; q < mesh.corner_normals.size() && q < moved.corner_normals.size(); ++q)
      for (int c = 0; c < 4; ++c) {
        const int n = mesh.quads[q][c];
        mesh.corner_normals[q][c] = moved.frames[n] * theirs.frames[n].transpose() * mesh.corner_normals[q][c];
      }
  }
}

// [[metric]] kind = "linear_buckling_load": one linear buckling analysis of the structure as
// built (a copy: the model snaps its normals as it is built) under the scene's loads about the
// reference state, the first multiplier only (shell_eigen.md), run when the static run starts
std::function<void(double&, std::string&)> linear_buckling_analysis(const shell::ShellModelSpec& spec, double load_scale,
                                                                   LinearBackend backend) {
  auto structure = std::make_shared<const shell::ShellModelSpec>(spec);
  return [structure, load_scale, backend](double& value, std::string& why) {
    using namespace ff::shell;
    ShellEigenSettings es;
    es.analysis = ShellEigenSettings::Analysis::buckling;
    es.modes = 1;
    es.solver.backend = backend;
    es.load_scale = load_scale;
    try {
      ShellEigenSimulation buckling(*structure, es, RunInfo{});
      why = buckling.compute();
      if (why.empty()) {
        if (const std::optional<double> v = find_metric(buckling.metrics(), "critical_load"))
          value = *v;
        else
          for (const auto& [name, reason] : buckling.metrics_unreached()) why = reason;
      }
    } catch (const ShellSpecError& e) {
      why = e.what();
    }
  };
}

}  // namespace

std::unique_ptr<Simulation> build_shell_static(const Document& d, const std::string& path, const SceneContext& ctx) {
  using namespace ff::shell;
  const std::vector<std::string> fx = d.strings("scene.effects");
  auto has = [&](const char* e) { return std::find(fx.begin(), fx.end(), e) != fx.end(); };
  if (d.string("scene.analysis") != "static")  // the file's analysis chose this schema; --set cannot change it
    throw SceneError({d.issue("scene.analysis", "the analysis is chosen by the scene file (it picks the keys the "
                                                "scene may have); write analysis = \"" + d.string("scene.analysis") +
                                                "\" in the file instead of setting it")});
  if (!has("elastic")) throw SceneError({d.issue("scene.effects", "a static analysis needs the effect 'elastic'")});
  ShellStructureInput in = read_shell_structure_input(d, path, ctx, "scene.analysis");
  ShellModelSpec& spec = in.spec;
  Structure& structure = in.structure;
  // the mesh as the scene builds it, kept while imperfections move it: an element they fold is
  // theirs to answer for (below)
  const std::optional<mesh::ShellMesh> unperturbed =
      d.count("imperfection") > 0 ? std::optional<mesh::ShellMesh>(spec.mesh) : std::nullopt;
  apply_imperfections(d, path, ctx, spec.mesh);
  const mesh::ShellMesh& m = spec.mesh;
  ShellStaticSettings st;
  st.load_scale = d.number("solver.load_scale");
  st.load_label = d.string("solver.load_label");
  st.probes = std::move(in.probes);
  auto has_probe = [&](const std::string& n) {
    return std::any_of(st.probes.begin(), st.probes.end(), [&](const ShellProbe& p) { return p.name == n; });
  };
  (void)m;
  RunInfo info = std::move(in.info);
  for (std::size_t i = 0; i < d.count("metric"); ++i) {
    static const std::pair<const char*, ShellMetric::Kind> kinds[] = {
        {"at_load", ShellMetric::Kind::at_load}, {"final", ShellMetric::Kind::final_value},
        {"first_limit_load", ShellMetric::Kind::first_limit_load}, {"at_first_limit", ShellMetric::Kind::at_first_limit},
        {"min_load_after_limit", ShellMetric::Kind::min_load_after_limit}, {"max_abs", ShellMetric::Kind::max_abs},
        {"linear_buckling_load", ShellMetric::Kind::linear_buckling_load}};
    ShellMetric mt;
    mt.name = d.string("metric.name", i);
    if (mt.name.empty())  // summary.json and results.h5 key the metric by its name
      throw SceneError({d.issue("metric.name", i, "a metric needs a name (its key in summary.json and results.h5)")});
    for (const auto& [k, v] : kinds)
      if (d.string("metric.kind", i) == k) mt.kind = v;
    mt.probe = d.string("metric.probe", i);
    mt.load = d.number("metric.load", i);
    const bool needs_probe = mt.kind != ShellMetric::Kind::first_limit_load && mt.kind != ShellMetric::Kind::min_load_after_limit &&
                             mt.kind != ShellMetric::Kind::linear_buckling_load;
    if (needs_probe && !has_probe(mt.probe))
      throw SceneError({d.issue("metric.probe", i, "no probe named '" + mt.probe + "'")});
    st.metrics.push_back(mt);
    // load control lands on the loads it reports at (static_solvers.md §3)
    if (mt.kind == ShellMetric::Kind::at_load && st.load_scale != 0.0)
      st.load_control.stations.push_back(mt.load / st.load_scale);
  }
  for (std::size_t i = 0; i < d.count("reference"); ++i) {
    const std::string probe = d.string("reference.probe", i);
    if (!has_probe(probe)) throw SceneError({d.issue("reference.probe", i, "no probe named '" + probe + "'")});
    const std::string file = (fs::path(path).parent_path() / d.string("reference.file", i)).string();
    ReferenceTable t;
    try {
      t = read_reference_csv(file);
    } catch (const std::runtime_error& e) {
      throw SceneError({d.issue("reference.file", i, e.what())});
    }
    // a column the file lacks is the column key's error, not the file's
    auto column = [&](const std::string& key) {
      try {
        return t.column(d.string(key, i));
      } catch (const std::runtime_error& e) {
        throw SceneError({d.issue(key, i, e.what())});
      }
    };
    ReferenceSeries r{"load", probe, d.string("reference.label", i), column("reference.x_column"),
                      column("reference.y_column")};
    for (double& x : r.x) x *= d.number("reference.x_scale", i);
    for (double& y : r.y) y *= d.number("reference.y_scale", i);
    info.references.push_back(std::move(r));
  }
  // solver
  check_method_keys(d);
  StaticConvergence conv;
  conv.linear_backend = read_linear_solver(d);
  // a symmetric-only backend reads one triangle of the tangent; follower loads and moments add a
  // load stiffness that is not symmetric in general (the backend's documented limit): such runs
  // ended "matrix is not symmetric", or (cantilever_rollup) "not positive definite" at 0.79
  if (linear_backend_is_symmetric(conv.linear_backend))
    for (std::size_t i = 0; i < d.count("load"); ++i)
      if (d.boolean("load.follower", i) || d.string("load.type", i) == "moment")
        throw SceneError({d.issue("solver.linear_solver",
                                  "'" + d.string("solver.linear_solver") + "' needs a symmetric tangent, but load[" +
                                      std::to_string(i) + "] (" + d.where("load.type", i) + ") is " +
                                      (d.boolean("load.follower", i) ? "a follower load" : "a moment") +
                                      ", whose load stiffness is not symmetric; use umfpack, mumps or sparse_lu (or "
                                      "default)")});
  if (d.string("solver.method") == "load_control") refuse_unworkable_load_steps(d, LoadControlSettings{}.max_steps);
  // the arc length measures its later steps against the first load increment: one the load factor
  // cannot hold (below 1e-12 of solver.end, some ten thousand units of its last digit) ended
  // "Δl cut below its minimum" at the start (1e-300)
  if (arc_length_method(d) && d.number("solver.initial_step") < 1e-12 * d.number("solver.end"))
    throw SceneError({d.issue("solver.initial_step", "the first load increment " + d.value_text("solver.initial_step") +
                                                         " is below 1e-12 of solver.end (" + d.value_text("solver.end") +
                                                         "): lost in the round-off of the load factor, the arc length "
                                                         "cannot measure a step by it; give a few per cent of the range")});
  conv.residual_tolerance = conv.increment_tolerance = d.number("solver.tolerance");
  conv.max_iterations = static_cast<int>(d.integer("solver.max_iterations"));
  conv.tangent = d.string("solver.tangent") == "modified" ? TangentPolicy::modified : TangentPolicy::every_iteration;
  st.arc_length = d.string("solver.method") == "arc_length";
  st.linear = d.string("solver.method") == "linear";
  st.load_control.lambda_end = d.number("solver.end");
  st.load_control.initial_step = d.number("solver.initial_step");
  st.load_control.max_step = d.number("solver.max_step");
  st.load_control.min_step = d.number("solver.min_step");
  st.load_control.convergence = conv;
  st.load_control.hold_determinant_sign = d.boolean("solver.stop_at_limit_point");
  st.load_control.lambda_end_name = "solver.end";
  st.arc.method = d.string("solver.arc_method") == "lam_morley" ? ArcLengthMethod::lam_morley : ArcLengthMethod::crisfield;
  st.arc.initial_load_increment = d.number("solver.initial_step");
  st.arc.lambda_max = d.number("solver.end");
  st.arc.lambda_max_name = "solver.end";
  st.arc.lambda_min = d.number("solver.min_load_factor");
  st.arc.lambda_min_name = "solver.min_load_factor";
  st.arc.stop_at_first_limit_point = d.boolean("solver.stop_at_first_limit_point");
  st.arc.desired_iterations = static_cast<int>(d.integer("solver.desired_iterations"));
  const double deg = std::acos(-1.0) / 180.0;
  st.arc.target_turn = d.number("solver.target_turn") * deg;
  st.arc.max_turn = d.number("solver.max_turn") * deg;
  st.arc.max_growth = d.number("solver.max_growth");
  st.arc.max_steps = static_cast<int>(d.integer("solver.max_steps"));
  st.arc.convergence = conv;
  st.monitor_probe = d.string("solver.monitor_probe");
  st.displacement_limit = d.number("solver.displacement_limit");
  if (!st.monitor_probe.empty() && !has_probe(st.monitor_probe))
    throw SceneError({d.issue("solver.monitor_probe", "no probe named '" + st.monitor_probe + "'")});
  st.record_stresses = stresses_wanted(d, {"displacement", "strain", shell::kErrorIndicatorField});
  st.record_error_indicator = d.boolean("output.error_bar") || d.string("output.color_field") == shell::kErrorIndicatorField;
  // the linear_buckling_load metric's analysis runs when the run starts, on the structure as built here
  if (std::any_of(st.metrics.begin(), st.metrics.end(),
                  [](const ShellMetric& m) { return m.kind == ShellMetric::Kind::linear_buckling_load; }))
    st.linear_buckling = linear_buckling_analysis(spec, st.load_scale, conv.linear_backend);
  std::unique_ptr<ShellStaticSimulation> sim;
  const ShellModelSpec spec_copy = unperturbed ? spec : ShellModelSpec{};
  try {
    sim = std::make_unique<ShellStaticSimulation>(std::move(spec), st, std::move(info));
  } catch (const ShellSpecError& e) {
    // an element the structure forms without its imperfections was folded by them: at the
    // largest amplitude, not at the part's mesh
    if (unperturbed && (e.part() == ShellSpecError::Part::element || e.part() == ShellSpecError::Part::mid_surface)) {
      ShellModelSpec perfect = spec_copy;
      perfect.mesh = *unperturbed;
      bool perfect_builds = true;
      try {
        ShellModel model(std::move(perfect));
      } catch (const ShellSpecError&) {
        perfect_builds = false;
      }
      if (perfect_builds) {
        std::size_t largest = 0;
        for (std::size_t i = 1; i < d.count("imperfection"); ++i)
          if (std::abs(d.number("imperfection.amplitude", i)) > std::abs(d.number("imperfection.amplitude", largest)))
            largest = i;
        throw SceneError({d.issue("imperfection.amplitude", largest,
                                  "the imperfections move the mesh so far that it folds: " + std::string(e.what()) +
                                      " (the structure without them forms every element); a geometric imperfection "
                                      "is small beside the elements' size, typically of the order of the thickness")});
      }
    }
    throw SceneError({located(d, e, structure)});
  }
  // the stress fields follow the structure's layup: known once its elements are built
  refuse_unknown_probe_fields(d, stress_fields(sim->model().stress_layout()));
  refuse_unknown_color_field(d, sim->info());
  return sim;
}

}  // namespace ff::scene
