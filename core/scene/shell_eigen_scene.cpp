#include "core/scene/shell_eigen_scene.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/scene/scene_common.h"
#include "core/scene/node_selection.h"
#include "core/scene/shell_boundary.h"
#include "core/scene/shell_dynamic_scene.h"
#include "core/scene/shell_structure_scene.h"
#include "core/scene/structure_parts.h"
#include "core/scene/timeline.h"
#include "core/shell/multibody_modes.h"
#include "core/shell/shell_eigen_simulation.h"

namespace ff::scene {

namespace {

// the keys of the load-control path to the preloaded state: refused when the modes are about the
// reference state, which no path reaches
const std::vector<std::string>& preload_keys() {
  static const std::vector<std::string> k = {"end", "initial_step", "max_step", "min_step", "tolerance", "max_iterations"};
  return k;
}

// The modes wanted, the Lanczos basis and the linear solver of the analysis; refuses a basis not
// larger than the modes
EigenSolveSettings read_eigen_solve(const Document& d, const std::string& analysis) {
  EigenSolveSettings st;
  st.count = static_cast<int>(d.integer(analysis + ".modes"));
  st.subspace = static_cast<int>(d.integer(analysis + ".lanczos_vectors"));
  if (st.subspace > 0 && st.subspace <= st.count)
    throw SceneError({d.issue(analysis + ".lanczos_vectors", "the Lanczos basis must be larger than " + analysis +
                                                                 ".modes (" + std::to_string(st.count) + ")")});
  st.backend = read_linear_solver(d);
  return st;
}

// the key that makes the Lanczos basis large: lanczos_vectors when the scene gives it, else the
// modes its default follows
std::string basis_key(const Document& d, const std::string& analysis) {
  return d.integer(analysis + ".lanczos_vectors") > 0 ? analysis + ".lanczos_vectors" : analysis + ".modes";
}

// Unknowns before the supports take theirs: every node's DoFs (6 with drilling, else 5; a fold
// node's sixth is left out), 6 per rigid body. An upper bound for the memory estimate.
long long unknowns_bound(const Document& d, long long nodes) {
  const std::vector<std::string> fx = d.strings("scene.effects");
  const bool drilling = std::find(fx.begin(), fx.end(), "drilling") != fx.end();
  const long long rigid = d.declares_array("rigid") ? static_cast<long long>(d.count("rigid")) : 0;
  return nodes * (drilling ? 6 : 5) + 6 * rigid;
}

// The run's peak: the structure's (shell::estimated_peak_bytes, a static run's model and factor)
// and the Lanczos iteration's (lanczos_peak_bytes) on the unknowns' bound
double eigen_bytes(const Document& d, const std::string& path, const SceneContext& ctx, const std::string& analysis,
                   const EigenSolveSettings& st) {
  const double structure = estimated_structure_bytes(d, path, ctx);
  const long long nodes = structure_size(d, path, ctx).nodes;
  return structure > 0 ? structure + lanczos_peak_bytes(st, unknowns_bound(d, nodes)) : 0.0;
}

// Refuses, before anything is built, an analysis whose Lanczos basis does not fit beside its
// structure in the memory the machine allows, at the key that makes the basis large, with the
// figures. A structure too large on its own is left to refuse_oversized (at its mesh keys).
void refuse_oversized_basis(const Document& d, const std::string& path, const SceneContext& ctx,
                            const std::string& analysis, const EigenSolveSettings& st) {
  if (!(ctx.memory_limit_bytes > 0)) return;
  const double structure = estimated_structure_bytes(d, path, ctx);
  if (!(structure > 0) || structure > ctx.memory_limit_bytes) return;
  const long long n = unknowns_bound(d, structure_size(d, path, ctx).nodes);
  const double basis = lanczos_peak_bytes(st, n);
  if (structure + basis <= ctx.memory_limit_bytes) return;
  std::ostringstream m;
  m.precision(3);
  m << "the Lanczos iteration for " << st.count << " modes keeps a basis of " << lanczos_basis_size(st, n)
    << " vectors of up to " << n << " unknowns: about " << basis / 1e9 << " GB (with the copy it makes while it "
    << "restarts and the modes it returns), which with the structure's " << structure / 1e9 << " GB is more than the "
    << ctx.memory_limit_bytes / 1e9 << " GB this machine allows; ask for fewer modes, a smaller "
    << analysis << ".lanczos_vectors (0: max(2 modes + 1, modes + 20)) or a coarser mesh";
  throw SceneError({d.issue(basis_key(d, analysis), m.str())});
}

// Refuses, at their keys, more modes than the built structure can have (at most its free
// unknowns less one) and a basis larger than its unknowns
void refuse_counts_beyond_unknowns(const Document& d, const std::string& analysis, const EigenSolveSettings& st,
                                   long long unknowns, const std::string& what) {
  if (st.count >= unknowns)
    throw SceneError({d.issue(analysis + ".modes", "asks for " + std::to_string(st.count) + " modes of a structure with " +
                                                       std::to_string(unknowns) + " unknowns (" + what +
                                                       "): at most " + std::to_string(std::max(0LL, unknowns - 1)) +
                                                       " (a finer mesh has more)")});
  if (st.subspace > unknowns)
    throw SceneError({d.issue(analysis + ".lanczos_vectors",
                              "a Lanczos basis of " + std::to_string(st.subspace) + " vectors in a structure of " +
                                  std::to_string(unknowns) + " unknowns (" + what + "): at most " +
                                  std::to_string(unknowns) + " (0: max(2 modes + 1, modes + 20), at most the unknowns)")});
}

// modal.shift against the structure's frequency scale f_ref = sqrt(ω²_ref) / 2π (shell_eigen.md
// (E3), of the order of its highest frequency). Above kLargestShiftRatio f_ref the modes nearest
// the shift are the mesh's own highest, which the iteration cannot resolve: on a 10 x 10 plate
// whose highest frequency is about 1.3e5 Hz, a shift of 1e5 Hz gave the modes near it, one of
// 1e6 Hz a mixture of wrong ones, and 1e12 Hz repeated wrong frequencies, each "completed".
// Below kSmallestShiftRatio f_ref (sqrt of the rigid-body tolerance, (E4)) the shift is the zero
// frequency itself, on which K - shift M is singular for a free structure.
constexpr double kLargestShiftRatio = 1.0, kSmallestShiftRatio = 1e-6;
void refuse_shift_beyond_mesh(const Document& d, double omega2_ref) {
  const double shift = d.number("modal.shift");
  if (!(shift > 0.0)) return;
  const double f_ref = std::sqrt(omega2_ref) / (2.0 * std::acos(-1.0));
  if (shift >= kSmallestShiftRatio * f_ref && shift <= kLargestShiftRatio * f_ref) return;
  std::ostringstream m;
  m.precision(4);
  m << "modal.shift = " << shift << " Hz is outside [" << kSmallestShiftRatio * f_ref << ", " << kLargestShiftRatio * f_ref
    << "] Hz, the frequencies this mesh can resolve about (its frequency scale sqrt(max K_ii / M_ii) / 2 pi = " << f_ref
    << " Hz, core/shell/shell_eigen.md (E3)): "
    << (shift > f_ref ? "above it the modes nearest the shift are the mesh's own highest, which the iteration cannot "
                        "tell apart"
                      : "below it the shift is the zero frequency of a rigid-body mode, on which K - shift M is "
                        "singular")
    << "; give a frequency within the range, or 0 for the lowest modes";
  throw SceneError({d.issue("modal.shift", m.str())});
}

Schema eigen_schema(const std::string& analysis) {
  Schema s;
  declare_shell_structure_scene_keys(s);
  const bool modal = analysis == "modal";
  const std::string t = analysis;
  s.table(t, modal ? "natural vibration K phi = omega^2 M phi (core/shell/shell_eigen.md): the lowest modes"
                   : "linear buckling (K0 + lambda K_G) phi = 0 (core/shell/shell_eigen.md): the lowest load "
                     "multipliers of the scene's loads",
          true)
      .integer(t + ".modes",
               std::string(modal ? "modes wanted, the lowest (rigid-body modes of a free structure included)"
                                 : "load multipliers wanted, the lowest positive ones") +
                   "; fewer than the structure's unknowns (its DoFs the supports leave free)",
               6, IntRange::closed(1, 500))
      .choice(t + ".about",
              "the state the modes are about: reference (unloaded; "
                  + std::string(modal ? "the loads are not applied" : "K_G from the linear prestress of the loads") +
                  ") or preload (the loads applied first by a nonlinear static solve to solver.end, then the "
                  "tangent stiffness there" +
                  (modal ? ": a tensioned part stiffens" : "; the multipliers are then total load factors") + ")",
              {"reference", "preload"}, "reference")
      .integer(t + ".lanczos_vectors",
               "size of the Lanczos basis; 0: max(2 modes + 1, modes + 20). More converge a clustered spectrum "
               "(a cylinder's buckling loads) in fewer restarts; at most the structure's unknowns, and refused when "
               "the basis (about 16 x unknowns x lanczos_vectors bytes) does not fit in memory",
               0, IntRange::closed(0, 5000));
  if (modal) declare_multibody_keys(s);  // a jointed structure: modes with its joints as constraints
  if (modal)
    s.number("modal.shift",
             "frequency [Hz] the modes are found nearest to (shift-invert about sigma = (2 pi shift)^2); 0: a small "
             "negative shift below every frequency, sigma = -1e-8 max_i K_ii / M_ii, so the lowest modes (rigid-body "
             "modes first) come out. Otherwise within [1e-6, 1] x f_ref, f_ref = sqrt(max_i K_ii / M_ii) / 2 pi (the "
             "mesh's frequency scale, which check names)",
             0.0, Range::non_negative());
  s.table("solver", "the load-control path to a preloaded state (about = \"preload\") and the linear solver", false)
      .number("solver.load_scale",
              "load reported per unit lambda: critical_load = load_scale x the first multiplier (buckling), the load "
              "probe",
              1.0)
      .string("solver.load_label", "name of the load on plots", std::string("load"))
      .number("solver.end", "about = \"preload\": the load factor of the preloaded state", 1.0, Range::positive())
      .number("solver.initial_step", "about = \"preload\": first load step", 0.25, Range::left_open(0.0, 1.0))
      .number("solver.max_step", "about = \"preload\": largest load step", 0.25, Range::left_open(0.0, 1.0))
      .number("solver.min_step", "about = \"preload\": smallest load step before giving up", 1e-5,
              Range::left_open(0.0, 1.0))
      .number("solver.tolerance", "about = \"preload\": relative residual and increment tolerance", 1e-8,
              Range::left_open(0.0, 1e-2))
      .integer("solver.max_iterations", "about = \"preload\": Newton corrections per attempt", 25,
               IntRange::closed(2, 500));
  declare_linear_solver(s, "mumps where compiled in (LDLᵀ of the symmetric matrices), else umfpack");
  declare_output_keys(s, {"displacement", "strain"}, true);
  declare_timeline(s, "load factor of the event (eigen-analyses: camera keys only)", "", {});
  s.renamed("mesh", "part");
  return s;
}

// A modal analysis of a structure with rigid bodies or joints: the dynamic model's stiffness and
// mass at rest, the joints as constraints (core/shell/multibody_modes.h), about the reference state
std::unique_ptr<Simulation> build_jointed_modal(const Document& d, const std::string& path, const SceneContext& ctx,
                                                bool preload, const EigenSolveSettings& solve) {
  using namespace ff::shell;
  if (preload)
    throw SceneError({d.issue("modal.about", "a structure with rigid bodies or joints ([[" +
                                                 std::string(d.count("joint") > 0 ? "joint" : "rigid") +
                                                 "]]) has its modes about the reference state only in this version; "
                                                 "about = \"preload\" needs a static solve of the multibody model")});
  MultibodyInput in = read_multibody_input(d, path, ctx, false, false);
  in.spec.gravity = false;  // the unloaded reference state: loads and gravity are not applied
  std::vector<MultibodyEigenSimulation::Probe> probes;
  for (std::size_t i = 0; i < d.count("probe"); ++i) {
    if (d.string("probe.quantity", i) != "displacement")
      throw SceneError({d.issue("probe.quantity", i, "a modal analysis of a jointed structure records displacement "
                                                     "probes only (its state is the unloaded reference)")});
    probe_reads_stress(d, i);  // its direction given and not zero
    const std::vector<int> ids = select_nodes(d, in.structure.joined, "probe", i);
    const std::string name = d.string("probe.name", i), label = d.string("probe.label", i);
    probes.push_back({name, label.empty() ? name : label, ids.front(), [&] {
      const std::vector<double> v = d.numbers("probe.direction", i);
      return Eigen::Vector3d(v[0], v[1], v[2]);
    }()});
  }
  std::optional<double> shift;
  if (d.number("modal.shift") > 0.0) {
    const double w = 2.0 * std::acos(-1.0) * d.number("modal.shift");
    shift = w * w;
  }
  RunInfo info;
  describe_run(d, path, info);
  // what the analysis evaluates besides the scene's effects: the inertia (the mass) and the joints
  info.effects = d.strings("scene.effects");
  info.effects.push_back("inertia");
  if (d.count("joint") > 0) info.effects.push_back("joints");
  std::unique_ptr<MultibodyEigenSimulation> sim;
  try {
    sim = std::make_unique<MultibodyEigenSimulation>(std::move(in.spec), solve, shift, std::move(probes), std::move(info));
  } catch (const std::invalid_argument& e) {
    throw SceneError({d.issue(d.count("joint") > 0 ? "joint.type" : "rigid.name", 0, e.what())});
  }
  // the joints' rows leave size - rows independent unknowns to vibrate (lowest_constrained_vibration_modes)
  refuse_counts_beyond_unknowns(d, "modal", solve, sim->model().size() - sim->model().constraint_count(),
                                "its DoFs left free by the supports, less one per joint constraint");
  if (shift) refuse_shift_beyond_mesh(d, sim->reference_omega2());
  return sim;
}

std::unique_ptr<Simulation> build_eigen(const Document& d, const std::string& path, const SceneContext& ctx,
                                        const std::string& analysis) {
  using namespace ff::shell;
  if (d.string("scene.analysis") != analysis)
    throw SceneError({d.issue("scene.analysis", "the analysis is chosen by the scene file (it picks the keys the "
                                                "scene may have); write analysis = \"" + d.string("scene.analysis") +
                                                "\" in the file instead of setting it")});
  const std::vector<std::string> fx = d.strings("scene.effects");
  if (std::find(fx.begin(), fx.end(), "elastic") == fx.end())
    throw SceneError({d.issue("scene.effects", "an eigen-analysis needs the effect 'elastic'")});
  const bool modal = analysis == "modal";
  const bool preload = d.string(analysis + ".about") == "preload";
  if (!preload)
    for (const std::string& k : preload_keys())
      if (d.present("solver." + k))
        throw SceneError({d.issue("solver." + k, "solver." + k + " sets the path to a preloaded state, but " + analysis +
                                                     ".about = \"reference\": the modes are about the unloaded "
                                                     "structure and no path is followed")});
  // loads of a modal analysis about the unloaded structure change nothing: said, not refused (the
  // same file serves about = "preload" with --set modal.about=reference as its comparison)
  if (modal && !preload && d.count("load") > 0 && ctx.warnings)
    ctx.warnings->push_back(d.issue("load.type", 0, "the [[load]] entries have no effect: modal.about = \"reference\" "
                                                    "takes the modes of the unloaded structure; about = \"preload\" "
                                                    "applies them first")
                                .to_string());
  const EigenSolveSettings solve = read_eigen_solve(d, analysis);
  refuse_oversized_basis(d, path, ctx, analysis, solve);
  if (modal && (d.count("rigid") > 0 || d.count("joint") > 0)) return build_jointed_modal(d, path, ctx, preload, solve);
  // buckling needs loads (their prestress); a modal analysis about the reference state does not
  ShellStructureInput in =
      read_shell_structure_input(d, path, ctx, !modal ? "scene.analysis" : preload ? "modal.about" : "");
  ShellEigenSettings st;
  st.analysis = modal ? ShellEigenSettings::Analysis::modal : ShellEigenSettings::Analysis::buckling;
  st.modes = solve.count;
  st.preload = preload;
  if (modal && d.number("modal.shift") > 0.0) {
    const double w = 2.0 * std::acos(-1.0) * d.number("modal.shift");
    st.shift = w * w;
  }
  st.solver = solve;
  st.load_control.lambda_end = d.number("solver.end");
  st.load_control.initial_step = d.number("solver.initial_step");
  st.load_control.max_step = d.number("solver.max_step");
  st.load_control.min_step = d.number("solver.min_step");
  st.load_control.lambda_end_name = "solver.end";
  st.load_control.convergence.residual_tolerance = st.load_control.convergence.increment_tolerance =
      d.number("solver.tolerance");
  st.load_control.convergence.max_iterations = static_cast<int>(d.integer("solver.max_iterations"));
  st.load_control.convergence.linear_backend = st.solver.backend;
  if (preload) refuse_unworkable_load_steps(d, st.load_control.max_steps);
  st.load_scale = d.number("solver.load_scale");
  st.load_label = d.string("solver.load_label");
  st.probes = std::move(in.probes);
  if (modal) {
    // every quad's density: its part's material (a layup: its plies' own, laminate.md (L10))
    for (std::size_t p = 0; p < in.structure.parts.size(); ++p)
      require_density(d, in.structure, p,
                      "a modal analysis needs the mass of every part: give material.density for part '" +
                          in.structure.parts[p].name + "'");
    for (int q = 0; q < static_cast<int>(in.structure.quad_part.size()); ++q)
      st.densities.push_back(in.structure.materials[in.structure.parts[in.structure.quad_part[q]].material].density);
  }
  if (modal) in.info.effects.push_back("inertia");  // the mass: evaluated whether or not the scene lists it
  std::unique_ptr<ShellEigenSimulation> sim;
  try {
    sim = std::make_unique<ShellEigenSimulation>(std::move(in.spec), std::move(st), std::move(in.info));
  } catch (const ShellSpecError& e) {
    throw SceneError({located(d, e, in.structure)});
  }
  refuse_counts_beyond_unknowns(d, analysis, solve, sim->model().size(), "its DoFs left free by the supports");
  if (modal && d.number("modal.shift") > 0.0) refuse_shift_beyond_mesh(d, sim->reference_omega2());
  refuse_unknown_probe_fields(d, stress_fields(sim->model().stress_layout()));
  refuse_unknown_color_field(d, sim->info());
  return sim;
}

}  // namespace

const Schema& shell_modal_schema() {
  static const Schema schema = eigen_schema("modal");
  return schema;
}
const Schema& shell_buckling_schema() {
  static const Schema schema = eigen_schema("buckling");
  return schema;
}

double estimated_eigen_bytes(const Document& d, const std::string& path, const SceneContext& ctx) {
  const std::string analysis = d.string("scene.analysis");
  return eigen_bytes(d, path, ctx, analysis, read_eigen_solve(d, analysis));
}

std::unique_ptr<Simulation> build_shell_modal(const Document& d, const std::string& path, const SceneContext& ctx) {
  return build_eigen(d, path, ctx, "modal");
}
std::unique_ptr<Simulation> build_shell_buckling(const Document& d, const std::string& path, const SceneContext& ctx) {
  return build_eigen(d, path, ctx, "buckling");
}

}  // namespace ff::scene
