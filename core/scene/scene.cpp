#include "core/scene/scene.h"

#include <algorithm>
#include <sstream>

#include <fstream>
#include <sstream>
#include <toml++/toml.h>

#include "core/hubbeam/hub_beam_simulation.h"
#include "core/scene/shell_dynamic_scene.h"
#include "core/scene/scene_common.h"
#include "core/scene/timeline.h"
#include "core/scene/shell_scene.h"

namespace ff::scene {

const Schema& hub_beam_schema() {
  static const Schema schema = [] {
    Schema s;
    declare_scene_table(s,
                        "effects to simulate; nothing else is evaluated. hub_beam needs inertia and bending; "
                        "axial adds the stretch DoFs, first_order_coupling the foreshortening w_c and its "
                        "dynamic stiffening (without it: the zero-order model), hub_torque the drive",
                        {"inertia", "bending", "axial", "first_order_coupling", "hub_torque"});
    s.table("hub", "rigid hub (hub_beam)")
        .number("hub.radius", "hub radius a", 0.05, Range::non_negative(), "m")
        .number("hub.inertia", "hub moment of inertia J_H about its axis", 0.3, Range::positive(), "kg m^2");
    s.table("beam", "flexible Euler-Bernoulli beam clamped to the hub (hub_beam)")
        .number("beam.length", "length L", 1.8, Range::positive(), "m")
        .number("beam.area", "cross-section area A", 2.5e-4, Range::positive(), "m^2")
        .number("beam.density", "mass density rho", 2.7667e3, Range::positive(), "kg/m^3")
        .number("beam.youngs_modulus", "Young's modulus E", 6.8952e10, Range::positive(), "Pa")
        .number("beam.second_moment", "second moment of area I", 1.3021e-10, Range::positive(), "m^4");
    s.table("torque", "hub torque tau(t) = amplitude sin(2 pi t / period) for t <= period, 0 after")
        .number("torque.amplitude", "tau0", 1.0, Range::non_negative(), "N m")
        .number("torque.period", "T", 2.0, Range::positive(), "s");
    s.table("discretization", "how the beam is discretized")
        .choice("discretization.method", "efg (IGMLS meshless) or fem (Hermite + linear elements)",
                {"efg", "fem"}, "efg");
    s.table("efg", "element-free Galerkin settings (method = efg)")
        .integer("efg.nodes", "field nodes, uniformly spaced", 10, IntRange::closed(3, 400))
        .number("efg.scale", "support size d_mI = scale * nearest-node spacing", 2.5, Range::left_open(1.0, 10.0))
        .integer("efg.gauss_points", "Gauss points per background cell", 4, IntRange::closed(1, 20))
        .integer("efg.cells", "background cells; 0 = nodes - 1", 0, IntRange::closed(0, 2000))
        .integer("efg.basis_order", "degree of the transverse GMLS basis (seed: 2)", 2, IntRange::closed(1, 4))
        .integer("efg.axial_basis_order", "degree of the axial IMLS basis", 1, IntRange::closed(1, 4));
    s.table("fem", "finite-element settings (method = fem)")
        .integer("fem.elements", "number of elements", 9, IntRange::closed(1, 2000))
        .integer("fem.gauss_points", "Gauss points per element (4 integrates every matrix exactly)", 4,
                 IntRange::closed(1, 20));
    s.table("solver", "time integration", true)
        .choice("solver.integrator", "time integrator", {"newmark"}, "newmark")
        .number("solver.dt", "time step", std::nullopt, Range::positive(), "s")
        .number("solver.t_end", "end time", std::nullopt, Range::positive(), "s")
        .number("solver.newmark_beta", "Newmark beta (0.25 average acceleration; the hub-beam seed states 0.75)",
                0.25, Range::left_open(0.0, 1.0))
        .number("solver.newmark_gamma", "Newmark gamma (0.5: no numerical damping)", 0.5, Range::closed(0.5, 1.0))
        .number("solver.tolerance", "Newton stops when |dx|_inf <= tolerance (1 + |x|_inf)", 1e-10,
                Range::left_open(0.0, 1e-2))
        .integer("solver.max_iterations", "Newton iterations per step before the step counts as failed", 25,
                 IntRange::closed(1, 500))
        .integer("solver.max_cutbacks", "times a failed step may be halved before the run stops as diverged", 0,
                 IntRange::closed(0, 20))
        .number("solver.max_tip_deflection_ratio",
                "stop as diverged when |tip deflection| exceeds this multiple of L", 1.0, Range::left_open(0.0, 100.0));
    declare_output_keys(s, {"deflection", "transverse"}, false);
    declare_timeline(s, "time of the event", "s", {"torque_scale"});
    return s;
  }();
  return schema;
}

namespace {

[[noreturn]] void fail_at(const Document& doc, const std::string& key, const std::string& message) {
  throw SceneError({doc.issue(key, message)});
}

bool has(const std::vector<std::string>& v, const char* name) {
  return std::find(v.begin(), v.end(), name) != v.end();
}

std::unique_ptr<Simulation> build_hub_beam(const Document& d, const std::string& path) {
  using namespace ff::hubbeam;
  const std::vector<std::string> effects = d.strings("scene.effects");
  for (const char* needed : {"inertia", "bending"})
    if (!has(effects, needed))
      fail_at(d, "scene.effects", std::string("a hub_beam scene needs the effect '") + needed + "'");
  HubBeamParams p;
  p.hub_radius = d.number("hub.radius");
  p.hub_inertia = d.number("hub.inertia");
  p.length = d.number("beam.length");
  p.area = d.number("beam.area");
  p.density = d.number("beam.density");
  p.youngs_modulus = d.number("beam.youngs_modulus");
  p.second_moment = d.number("beam.second_moment");
  p.torque_amplitude = d.number("torque.amplitude");
  p.torque_period = d.number("torque.period");
  HubBeamEffects fx;
  fx.axial = has(effects, "axial");
  fx.first_order_coupling = has(effects, "first_order_coupling");
  fx.hub_torque = has(effects, "hub_torque");

  std::unique_ptr<BeamBasis> basis;
  const std::string method = d.string("discretization.method");
  try {
    if (method == "efg") {
      EfgOptions o;
      o.nodes = static_cast<int>(d.integer("efg.nodes"));
      o.scale = d.number("efg.scale");
      o.gauss_points = static_cast<int>(d.integer("efg.gauss_points"));
      o.cells = static_cast<int>(d.integer("efg.cells"));
      o.basis_order = static_cast<int>(d.integer("efg.basis_order"));
      o.axial_basis_order = static_cast<int>(d.integer("efg.axial_basis_order"));
      basis = make_efg_basis(p.length, o);
    } else {
      FemOptions o;
      o.elements = static_cast<int>(d.integer("fem.elements"));
      o.gauss_points = static_cast<int>(d.integer("fem.gauss_points"));
      basis = make_fem_basis(p.length, o);
    }
  } catch (const std::invalid_argument& e) {
    fail_at(d, method == "efg" ? "efg.scale" : "fem.elements", e.what());
  }
  HubBeamRunSettings rs;
  rs.dt = d.number("solver.dt");
  rs.t_end = d.number("solver.t_end");
  if (rs.dt > rs.t_end) fail_at(d, "solver.dt", "the time step must not exceed solver.t_end");
  rs.newmark.beta = d.number("solver.newmark_beta");
  rs.newmark.gamma = d.number("solver.newmark_gamma");
  if (rs.newmark.beta < 0.5 * rs.newmark.gamma)
    fail_at(d, "solver.newmark_beta", "Newmark with gamma = " + std::to_string(rs.newmark.gamma) +
                                          " is only unconditionally stable for beta >= gamma / 2 = " +
                                          std::to_string(0.5 * rs.newmark.gamma));
  rs.newmark.tolerance = d.number("solver.tolerance");
  rs.newmark.max_iterations = static_cast<int>(d.integer("solver.max_iterations"));
  rs.newmark.max_cutbacks = static_cast<int>(d.integer("solver.max_cutbacks"));

  for (const ParameterChange& c : read_timeline(d, rs.t_end).changes)
    if (c.key == "torque_scale") rs.torque_scale_changes.push_back({c.at, c.value[0]});
  auto system = std::make_unique<HubBeamSystem>(p, fx, std::move(basis), d.number("solver.max_tip_deflection_ratio"));
  RunInfo info;
  describe_run(d, path, info);
  return std::make_unique<HubBeamSimulation>(std::move(system), rs, std::move(info));
}


}  // namespace

namespace {
// the model named in the file picks the schema; anything unreadable falls back to the hub-beam
// schema, whose validation then reports the problem with its location
std::string peek_model_text(const std::string& text, const std::string& path) {
  try {
    const toml::table t = toml::parse(text, path);
    return t["scene"]["model"].value<std::string>().value_or("hub_beam");
  } catch (const toml::parse_error&) {
    return "hub_beam";
  }
}
std::string peek_model(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return peek_model_text(ss.str(), path);
}
}  // namespace

const Schema& schema_for_text(const std::string& text) {
  const std::string model = peek_model_text(text, "scene_text");
  if (model == "shell_static") return shell_static_schema();
  if (model == "shell_dynamic") return shell_dynamic_schema();
  return hub_beam_schema();
}

const Schema& scene_schema(const std::string& path) {
  const std::string model = peek_model(path);
  if (model == "shell_static") return shell_static_schema();
  if (model == "shell_dynamic") return shell_dynamic_schema();
  return hub_beam_schema();
}

std::string scene_reference_markdown() {
  return "## model = \"hub_beam\"\n\n" + hub_beam_schema().markdown_reference() + "\n## model = \"shell_static\"\n\n" +
         shell_static_schema().markdown_reference() + "\n## model = \"shell_dynamic\"\n\n" +
         shell_dynamic_schema().markdown_reference();
}

LoadedScene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  const std::string model = peek_model(path);
  if (model == "shell_static" || model == "shell_dynamic") {
    const bool statics = model == "shell_static";
    const Document d = validate_file(statics ? shell_static_schema() : shell_dynamic_schema(), path, overrides);
    LoadedScene s;
    s.name = d.string("scene.name");
    s.path = path;
    s.output = read_output(d, true);
    s.output.camera_path = read_timeline(d, d.number(statics ? "solver.lambda_end" : "time.end")).camera;
    s.simulation = statics ? build_shell_static(d, path) : build_shell_dynamic(d, path);
    return s;
  }
  const Document d = validate_file(hub_beam_schema(), path, overrides);
  LoadedScene s;
  s.name = d.string("scene.name");
  s.path = path;
  s.output = read_output(d, false);
  s.output.camera_path = read_timeline(d, d.number("solver.t_end")).camera;
  s.simulation = build_hub_beam(d, path);
  return s;
}

std::string check_scene(const std::string& path, const std::vector<std::string>& overrides) {
  LoadedScene s = load_scene(path, overrides);
  const RunInfo& info = s.simulation->info();
  std::ostringstream out;
  out << s.name << ": valid; effects";
  for (const std::string& e : info.effects) out << ' ' << e;
  out << "; " << info.mesh.point_count() << " drawn points; ends at t = " << s.simulation->end_time() << ' '
      << info.time_unit;
  return out.str();
}

}  // namespace ff::scene
