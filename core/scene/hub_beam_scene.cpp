#include "core/scene/hub_beam_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/hubbeam/hub_beam_simulation.h"
#include "core/scene/scene_common.h"
#include "core/scene/timeline.h"

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
        .number("torque.amplitude",
                "tau0; at most 1e100 (the model's products with lengths and inertias stay inside double precision)",
                1.0, Range::closed(0.0, 1e100), "N m")
        .number("torque.period", "T", 2.0, Range::positive(), "s")
        .live("torque.amplitude");
    s.table("discretization", "how the beam is discretized")
        .choice("discretization.method", "efg (IGMLS meshless) or fem (Hermite + linear elements)",
                {"efg", "fem"}, "efg");
    s.table("efg", "element-free Galerkin settings (method = efg)")
        .integer("efg.nodes", "field nodes, uniformly spaced", 10, IntRange::closed(3, 400))
        .number("efg.scale", "support size d_mI = scale * nearest-node spacing", 2.5, Range::left_open(1.0, 10.0))
        .integer("efg.gauss_points", "Gauss points per background cell", 4, IntRange::closed(1, 20))
        .integer("efg.cells", "background cells; 0 = nodes - 1", 0, IntRange::closed(0, 2000))
        .integer("efg.basis_order", "degree of the transverse GMLS basis (the hub-beam paper: 2)", 2, IntRange::closed(1, 4))
        .integer("efg.axial_basis_order", "degree of the axial IMLS basis", 1, IntRange::closed(1, 4));
    s.table("fem", "finite-element settings (method = fem)")
        .integer("fem.elements", "number of elements", 9, IntRange::closed(1, 2000))
        .integer("fem.gauss_points", "Gauss points per element (4 integrates every matrix exactly)", 4,
                 IntRange::closed(1, 20));
    s.table("solver", "time integration", true)
        .choice("solver.integrator", "time integrator", {"newmark"}, "newmark")
        .number("solver.dt", "time step", std::nullopt, Range::positive(), "s")
        .number("solver.end", "end time", std::nullopt, Range::positive(), "s")
        .number("solver.newmark_beta", "Newmark beta (0.25 average acceleration; the hub-beam paper states 0.75)",
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
    // one vocabulary across models: the end of a run is solver.end everywhere
    s.renamed("solver.t_end", "solver.end");
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

}  // namespace

std::unique_ptr<Simulation> build_hub_beam(const Document& d, const std::string& path, const SceneContext& ctx) {
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
  // The model's coefficients are products of these inputs; one that overflows or underflows
  // double precision makes every matrix meaningless, and the failure would surface later under
  // an unrelated key (the EFG moment matrix, say). Name the input that dominates the product.
  struct Factor {
    const char* key;
    double value;
    int power;
  };
  auto representable = [&](const char* what, std::initializer_list<Factor> factors) {
    double product = 1.0;
    for (const Factor& f : factors) product *= std::pow(f.value, f.power);
    if (std::isfinite(product) && std::abs(product) >= std::numeric_limits<double>::min()) return;
    const Factor* worst = factors.begin();
    for (const Factor& f : factors)
      if (std::abs(f.power * std::log10(f.value)) > std::abs(worst->power * std::log10(worst->value))) worst = &f;
    std::ostringstream m;
    m << what << " = " << product << " is outside double precision (" << worst->key << " = " << worst->value << ")";
    fail_at(d, worst->key, m.str());
  };
  representable("the beam mass rho A L", {{"beam.density", p.density, 1}, {"beam.area", p.area, 1}, {"beam.length", p.length, 1}});
  representable("the beam's rotary inertia rho A L^3", {{"beam.density", p.density, 1}, {"beam.area", p.area, 1}, {"beam.length", p.length, 3}});
  representable("the bending stiffness E I / L^3",
                {{"beam.youngs_modulus", p.youngs_modulus, 1}, {"beam.second_moment", p.second_moment, 1}, {"beam.length", p.length, -3}});
  representable("the axial stiffness E A / L",
                {{"beam.youngs_modulus", p.youngs_modulus, 1}, {"beam.area", p.area, 1}, {"beam.length", p.length, -1}});
  representable("L^8 (the scale of the EFG moment matrices)", {{"beam.length", p.length, 8}});
  // the hub radius moves the beam's mass off the axis: its inertia about the axis grows with a^2
  // (1e300 ended "initial accelerations are not finite", exit 1)
  if (p.hub_radius > 0)
    representable("the beam's inertia about the hub axis from its offset, rho A L a^2",
                  {{"beam.density", p.density, 1}, {"beam.area", p.area, 1}, {"beam.length", p.length, 1},
                   {"hub.radius", p.hub_radius, 2}});
  HubBeamEffects fx;
  fx.axial = has(effects, "axial");
  fx.first_order_coupling = has(effects, "first_order_coupling");
  fx.hub_torque = has(effects, "hub_torque");

  const std::string method = d.string("discretization.method");
  // the basis from the scene's keys: built here once, so that a support too small for its basis is
  // refused at its key by `check` too, and again by the run's set-up (cheap beside the matrices);
  // the memory estimate first, so that a beam that cannot fit is refused before anything is built
  EfgOptions efg;
  efg.nodes = static_cast<int>(d.integer("efg.nodes"));
  efg.scale = d.number("efg.scale");
  efg.gauss_points = static_cast<int>(d.integer("efg.gauss_points"));
  efg.cells = static_cast<int>(d.integer("efg.cells"));
  efg.basis_order = static_cast<int>(d.integer("efg.basis_order"));
  efg.axial_basis_order = static_cast<int>(d.integer("efg.axial_basis_order"));
  FemOptions fem;
  fem.elements = static_cast<int>(d.integer("fem.elements"));
  fem.gauss_points = static_cast<int>(d.integer("fem.gauss_points"));
  // values, not the document: the run's set-up calls this after the document is gone
  auto make_basis = [efg, fem, efg_method = method == "efg", length = p.length]() {
    return efg_method ? make_efg_basis(length, efg) : make_fem_basis(length, fem);
  };
  const std::string count_key = method == "efg" ? "efg.nodes" : "fem.elements";
  const int beam_nodes = method == "efg" ? efg.nodes : fem.elements + 1;
  if (ctx.memory_limit_bytes > 0) {
    const double need = estimated_peak_bytes(beam_nodes, fx.axial);
    if (need > ctx.memory_limit_bytes) {
      std::ostringstream m;
      m.precision(3);
      m << "a run with " << beam_nodes << " beam nodes (dense matrices of " << 1 + (fx.axial ? 3 : 2) * (beam_nodes - 1)
        << " DoFs) would need about " << need / 1e9 << " GB, more than the " << ctx.memory_limit_bytes / 1e9
        << " GB this machine allows; use fewer";
      fail_at(d, count_key, m.str());
    }
  }
  try {
    // the shape functions where the run's set-up will evaluate them (not the matrices)
    const std::unique_ptr<BeamBasis> basis = make_basis();
    basis->check_points(evaluation_points(*basis, p.length, fx.first_order_coupling));
  } catch (const std::invalid_argument& e) {
    fail_at(d, method == "efg" ? "efg.scale" : "fem.elements", e.what());
  }
  HubBeamRunSettings rs;
  rs.dt = d.number("solver.dt");
  rs.t_end = d.number("solver.end");
  refuse_impossible_step_count(d, "solver.dt", "solver.end");
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
  // the matrices are built when the run starts (HubBeamSimulation::start): `check` stops here
  const double validity_ratio = d.number("solver.max_tip_deflection_ratio");
  HubBeamSystemBuilder build = [p, fx, validity_ratio, make_basis](const SetupMonitor& monitor) {
    return std::make_unique<HubBeamSystem>(p, fx, make_basis(), validity_ratio, monitor);
  };
  RunInfo info;
  describe_run(d, path, info);
  return std::make_unique<HubBeamSimulation>(std::move(build), ctx.setup, p, fx, rs, std::move(info));
}

double estimated_hub_beam_bytes(const Document& d, const std::string& /*path*/, const SceneContext& /*ctx*/) {
  const std::vector<std::string> fx = d.strings("scene.effects");
  return hubbeam::estimated_peak_bytes(d.string("discretization.method") == "efg"
                                           ? static_cast<int>(d.integer("efg.nodes"))
                                           : static_cast<int>(d.integer("fem.elements")) + 1,
                                       has(fx, "axial"));
}

}  // namespace ff::scene
