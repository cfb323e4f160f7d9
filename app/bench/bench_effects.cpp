// `flexframe bench --effects`: what an effect left out saves (DESIGN.md "Effects: simulate only
// what the scene asks for"). Every case is the same model built with and without one effect, timed
// in interleaved rounds (best round per case), so the ratios come from one run of the command.
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "app/bench/bench.h"
#include <nlohmann/json.hpp>
#include "core/hubbeam/hub_beam_system.h"
#include "core/mesh/generators.h"
#include "core/shell/multibody_model.h"
#include "core/shell/shell_model.h"
#include "core/solve/sparse_solver.h"

namespace ff::app {

namespace {

using shell::ShellOptions;

// CPU seconds of the whole process: on a machine shared with other jobs, time spent descheduled
// does not count (run with OMP_NUM_THREADS=1 so that CPU time is the single thread's work)
double cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

// n x n plate 1 x 1, clamped along x = 0, h = 0.01, E = 1e9, density 7810: the pendulum's material
ShellOptions shell_options(bool hr, bool ans, bool drilling) {
  ShellOptions o;
  o.hr = hr;
  o.ans = ans;
  o.drilling = drilling;
  return o;
}

mesh::ShellMesh plate_mesh(int n) { return mesh::rectangular_plate(1.0, 1.0, n, n, "plate"); }

// a state away from the reference (every element deformed): small random increments
Eigen::VectorXd small_random(int size, unsigned seed, double scale) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::VectorXd x(size);
  for (int i = 0; i < size; ++i) x[i] = scale * u(g);
  return x;
}

/// One statics Newton iteration's model work: residual + tangent (+ load vector).
struct StaticCase {
  std::unique_ptr<shell::ShellModel> model;
  Eigen::VectorXd r, f, x;
  SparseMatrixD K;
  SparseLinearSolver solver;
  StaticCase(int n, const ShellOptions& o) {
    shell::ShellModelSpec s;
    s.mesh = plate_mesh(n);
    s.section = shell::isotropic_section(1.0e9, 0.3, 0.01);
    s.options = o;
    for (int i = 0; i < s.mesh.node_count(); ++i)
      if (s.mesh.points[i].x() < 1e-12) s.restraints.push_back({i, shell::kClamped});
    s.pressures.push_back({0, 1.0, false});
    model = std::make_unique<shell::ShellModel>(std::move(s));
    model->update(small_random(model->size(), 3, 1e-3));
    assemble(true);
    solver.analyze(K);
  }
  void assemble(bool tangent) { model->evaluate(0.5, r, tangent ? &K : nullptr, tangent ? &f : nullptr); }
  void factorize_solve() {
    solver.factorize(K);
    solver.solve(r, x);
  }
};

/// One dynamics iteration's model work on the same plate: residual + iteration matrix
/// S = a M + b C + c K (elastic + inertia, no gravity, no joints).
struct DynamicCase {
  std::unique_ptr<shell::MultibodyModel> model;
  Eigen::VectorXd v, a, lambda, r, phi;
  SparseMatrixD S, B;
  IterationWeights w{4.0e6, 2.0e3, 1.0};
  DynamicCase(int n, const ShellOptions& o) {
    shell::MultibodySpec s;
    shell::ShellBodySpec body;
    body.name = "plate";
    body.mesh = plate_mesh(n);
    body.section = shell::isotropic_section(1.0e9, 0.3, 0.01);
    body.options = o;
    body.density = 7810;
    s.shells = {body};
    model = std::make_unique<shell::MultibodyModel>(std::move(s));
    model->configure(small_random(model->size(), 3, 1e-3));
    v = small_random(model->size(), 4, 0.1);
    a = small_random(model->size(), 5, 1.0);
    lambda.resize(0);
  }
  void assemble(bool tangent) {
    model->evaluate(0.0, v, a, lambda, r, phi, tangent ? &w : nullptr, tangent ? &S : nullptr, nullptr);
  }
};

/// The hub-beam's equations of motion per Newton iteration: residual + iteration matrix.
struct HubBeamCase {
  std::unique_ptr<hubbeam::HubBeamSystem> sys;
  Eigen::VectorXd x, v, a, r;
  Eigen::MatrixXd J;
  HubBeamCase(bool first_order, bool axial) {
    hubbeam::HubBeamParams p;
    hubbeam::HubBeamEffects fx;
    fx.first_order_coupling = first_order;
    fx.axial = axial;
    sys = std::make_unique<hubbeam::HubBeamSystem>(p, fx, hubbeam::make_fem_basis(p.length, hubbeam::FemOptions{}));
    const int n = sys->size();
    x = small_random(n, 6, 1e-3);
    v = small_random(n, 7, 0.1);
    a = small_random(n, 8, 0.1);
    v[0] = 2.0;
  }
  void evaluate() {
    sys->residual(x, v, a, 0.5, r);
    sys->iteration_matrix(x, v, a, 0.5, 1.0, 0.5, 0.25, J);
  }
};

struct Timed {
  std::string name;
  std::function<void()> once;
  int per_round = 1;
  double best = std::numeric_limits<double>::infinity();  // seconds per call
};

// interleaved rounds: each case runs `per_round` calls (about 20 ms of CPU) per round; the best
// round per case is kept
void measure(std::vector<Timed>& cases, int rounds, const std::atomic<bool>& stop) {
  for (Timed& c : cases) {
    c.once();  // warm-up (first factorization, caches)
    const double t0 = cpu_seconds();
    for (int k = 0; k < 3; ++k) c.once();
    const double s = (cpu_seconds() - t0) / 3;
    c.per_round = std::max(1, static_cast<int>(0.02 / std::max(s, 1e-9)));
  }
  for (int r = 0; r < rounds && !stop; ++r)
    for (Timed& c : cases) {
      const double t0 = cpu_seconds();
      for (int k = 0; k < c.per_round; ++k) c.once();
      c.best = std::min(c.best, (cpu_seconds() - t0) / c.per_round);
    }
}

struct Row {
  std::string comparison, without, with_;
  double t_without, t_with;
};

}  // namespace

int run_effects_bench(const BenchOptions& opt, const std::atomic<bool>& stop) {
  const int n = opt.effects_plate;
  const char* threads = std::getenv("OMP_NUM_THREADS");
  std::printf("Effects left out: %d x %d plate (CB shell, 5 DoF = no drilling), CPU time per call, best of %d "
              "interleaved rounds, OMP_NUM_THREADS=%s\n\n",
              n, n, opt.repeat, threads ? threads : "(unset)");
  std::fflush(stdout);

  // every model once; the cases below only call them
  StaticCase st_hr_ans(n, shell_options(true, true, false)), st_hr(n, shell_options(true, false, false)),
      st_ans(n, shell_options(false, true, false)), st_none(n, shell_options(false, false, false)),
      st_6(n, shell_options(true, true, true));
  DynamicCase dyn(n, shell_options(true, true, false));
  HubBeamCase hb_first(true, true), hb_zero(false, true), hb_first_noaxial(true, false);

  std::vector<Timed> cases = {
      {"static F+K", [&] { st_hr_ans.assemble(true); }},
      {"dynamic F+S", [&] { dyn.assemble(true); }},
      {"static F", [&] { st_hr_ans.assemble(false); }},
      {"dynamic F", [&] { dyn.assemble(false); }},
      {"6dof F+K", [&] { st_6.assemble(true); }},
      {"5dof LU", [&] { st_hr_ans.factorize_solve(); }},
      {"6dof LU", [&] { st_6.factorize_solve(); }},
      {"hr F+K", [&] { st_hr.assemble(true); }},
      {"ans F+K", [&] { st_ans.assemble(true); }},
      {"none F+K", [&] { st_none.assemble(true); }},
      {"hr F", [&] { st_hr.assemble(false); }},
      {"ans F", [&] { st_ans.assemble(false); }},
      {"none F", [&] { st_none.assemble(false); }},
      {"hb first", [&] { hb_first.evaluate(); }},
      {"hb zero", [&] { hb_zero.evaluate(); }},
      {"hb first noaxial", [&] { hb_first_noaxial.evaluate(); }},
  };
  measure(cases, opt.repeat, stop);
  if (stop) return 130;
  auto t = [&](const char* name) {
    for (const Timed& c : cases)
      if (c.name == name) return c.best;
    return std::numeric_limits<double>::quiet_NaN();
  };
  const std::string dofs5 = std::to_string(st_hr_ans.model->size()), dofs6 = std::to_string(st_6.model->size());
  const std::vector<Row> rows = {
      {"mass matrix: static residual + tangent vs dynamic residual + iteration matrix (elastic + inertia)",
       "static (no mass)", "dynamic", t("static F+K"), t("dynamic F+S")},
      {"mass matrix: residual only", "static", "dynamic", t("static F"), t("dynamic F")},
      {"drilling: residual + tangent, 5 vs 6 DoF per node", "5 DoF", "6 DoF", t("static F+K"), t("6dof F+K")},
      {"drilling: UMFPACK factorize + solve of that tangent (" + dofs5 + " vs " + dofs6 + " DoFs)", "5 DoF", "6 DoF",
       t("5dof LU"), t("6dof LU")},
      {"ans off: residual + tangent (hr on)", "hr", "hr + ans", t("hr F+K"), t("static F+K")},
      {"hr off: residual + tangent (ans on)", "ans", "hr + ans", t("ans F+K"), t("static F+K")},
      {"hr and ans off: residual + tangent", "neither", "hr + ans", t("none F+K"), t("static F+K")},
      {"ans off: residual only", "hr", "hr + ans", t("hr F"), t("static F")},
      {"hr off: residual only", "ans", "hr + ans", t("ans F"), t("static F")},
      {"hr and ans off: residual only", "neither", "hr + ans", t("none F"), t("static F")},
      {"hub-beam (FEM, 9 elements): residual + iteration matrix, zero vs first-order coupling", "zero order",
       "first order", t("hb zero"), t("hb first")},
      {"hub-beam: axial DoFs off vs on (first order)", "no axial", "axial", t("hb first noaxial"), t("hb first")},
  };
  std::printf("| comparison | without | time [ms] | with | time [ms] | without / with |\n|---|---|---|---|---|---|\n");
  nlohmann::ordered_json json_rows = nlohmann::ordered_json::object();
  for (const Row& r : rows) {
    std::printf("| %s | %s | %.4g | %s | %.4g | %.2f |\n", r.comparison.c_str(), r.without.c_str(), 1e3 * r.t_without,
                r.with_.c_str(), 1e3 * r.t_with, r.t_without / r.t_with);
    json_rows[r.comparison] = {{"without", r.without}, {"without_s", r.t_without}, {"with", r.with_},
                               {"with_s", r.t_with}, {"ratio", r.t_without / r.t_with}};
  }
  if (!opt.out_file.empty()) {
    const nlohmann::ordered_json root = {{"plate", n},
                                         {"repeat", opt.repeat},
                                         {"omp_num_threads", threads ? threads : ""},
                                         {"effects", json_rows}};
    if (!write_bench_json(opt.out_file, root.dump(2) + "\n")) return 1;
  }
  return 0;
}

}  // namespace ff::app
