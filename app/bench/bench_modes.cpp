// `flexframe bench --modes N`: the cost of N natural modes against one factorization
// (core/shell/shell_eigen.md): clamped square plates of n x n elements (the Leissa scene's
// material), the shifted matrix K - sigma M factorized once, then the Lanczos iteration's solves
// with that factorization. Wall seconds of one run per plate (the eigen-solve is deterministic).
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "app/bench/bench.h"
#include "core/mesh/generators.h"
#include "core/shell/shell_eigen_simulation.h"

namespace ff::app {

namespace {

// n x n clamped square plate 1 x 1 x 0.01, E = 210 GPa, nu = 0.3, rho = 7800 (modal_clamped_plate)
shell::ShellModelSpec clamped_plate(int n) {
  shell::ShellModelSpec s;
  s.mesh = mesh::rectangular_plate(1.0, 1.0, n, n);
  s.section.youngs_modulus = 2.1e11;
  s.section.poisson_ratio = 0.3;
  s.section.thickness = 0.01;
  s.options.hr = s.options.ans = true;
  for (int I = 0; I < s.mesh.node_count(); ++I) {
    const Eigen::Vector3d& p = s.mesh.points[I];
    if (p.x() < 1e-9 || p.y() < 1e-9 || p.x() > 1 - 1e-9 || p.y() > 1 - 1e-9) s.restraints.push_back({I, shell::kClamped});
  }
  return s;
}

}  // namespace

int run_modes_bench(const BenchOptions& options, const std::atomic<bool>& stop) {
  const int modes = options.modes;
  std::printf("# %d natural modes against one factorization (clamped plate, shift-invert Lanczos)\n\n", modes);
  std::printf("| plate | unknowns | factorizations | factorization s | Lanczos solves | Lanczos s | s per mode | f1 Hz |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  nlohmann::json rows = nlohmann::json::array();
  for (int n : {16, 32, 64, 128}) {
    if (n > options.solve_max_n || stop.load()) break;
    shell::ShellEigenSettings st;
    st.modes = modes;
    shell::ShellModelSpec spec = clamped_plate(n);
    st.densities.assign(spec.mesh.quad_count(), 7800.0);
    shell::ShellEigenSimulation sim(std::move(spec), st, RunInfo{});
    if (const std::string why = sim.compute(); !why.empty()) {
      std::fprintf(stderr, "error: %d x %d plate: %s\n", n, n, why.c_str());
      return 3;
    }
    const EigenSolveResult& r = sim.solve_result();
    const double per_mode = (r.factorization_seconds + r.iteration_seconds) / modes;
    std::printf("| %d x %d | %d | %d | %.3f | %d | %.3f | %.4f | %.3f |\n", n, n, sim.model().size(), r.factorizations,
                r.factorization_seconds, r.operator_applications, r.iteration_seconds, per_mode,
                sim.modes()->modes.front().value);
    rows.push_back({{"plate", n}, {"unknowns", sim.model().size()}, {"modes", modes},
                    {"factorizations", r.factorizations}, {"factorization_s", r.factorization_seconds},
                    {"lanczos_solves", r.operator_applications}, {"lanczos_s", r.iteration_seconds},
                    {"s_per_mode", per_mode}, {"f1_hz", sim.modes()->modes.front().value}});
    std::fflush(stdout);
  }
  if (!options.out_file.empty() && !write_bench_json(options.out_file, nlohmann::json{{"modes", rows}}.dump(2)))
    return 1;
  return 0;
}

}  // namespace ff::app
