// `flexframe bench --solve`: where a static Newton iteration's time goes on growing plates —
// assembly (residual + tangent) against factorization + solve for every compiled linear backend —
// and the CB element's own cost, all measured in one run so the ratios compare like with like
// (docs/performance.md). Wall time, best of --repeat (one round from 128 x 128 on).
#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/bench/bench.h"
#include "core/mesh/generators.h"
#include "core/shell/cb_shell.h"
#include "app/bench/sample_elements.h"
#include "core/shell/shell_model.h"
#include "core/solve/solver_ranks.h"
#include "core/solve/static_common.h"
#include "core/solve/sparse_solver.h"

namespace ff::app {

namespace {

double seconds_of(const std::function<void()>& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double best_of(int rounds, const std::function<void()>& f) {
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < rounds; ++k) best = std::min(best, seconds_of(f));
  return best;
}

// A unit plate n x n clamped along x = 0 under pressure (hr, ans, 5 DoF), moved off its reference
// state by small random increments so every element is deformed and the tangent is unsymmetric
// as in a real Newton iteration.
struct PlateIteration {
  std::unique_ptr<shell::ShellModel> model;
  Eigen::VectorXd r, f, x;
  SparseMatrixD K;
  explicit PlateIteration(int n) {
    shell::ShellModelSpec s;
    s.mesh = mesh::rectangular_plate(1.0, 1.0, n, n, "plate");
    s.section = shell::isotropic_section(1.0e9, 0.3, 0.01);
    s.options.hr = s.options.ans = true;
    for (int i = 0; i < s.mesh.node_count(); ++i)
      if (s.mesh.points[i].x() < 1e-12) s.restraints.push_back({i, shell::kClamped});
    s.pressures.push_back({0, 1.0, false});
    model = std::make_unique<shell::ShellModel>(std::move(s));
    std::mt19937 g(7);
    std::uniform_real_distribution<double> u(-1e-3, 1e-3);
    Eigen::VectorXd dq(model->size());
    for (int i = 0; i < dq.size(); ++i) dq[i] = u(g);
    model->update(dq);
    assemble();
  }
  void assemble() { model->evaluate(0.5, r, &K, &f); }
};

// Wall time of one call of f, as the best over `rounds` of the mean of `calls` back-to-back calls
double best_mean_us(int rounds, int calls, const std::function<void()>& f) {
  return 1e6 * best_of(rounds, [&] {
           for (int i = 0; i < calls; ++i) f();
         }) /
         calls;
}

// Item 2 of the solve benchmark: the CB element (curved, distorted, deformed; 5 DoF, hr, ans) on
// one core, its flop count (cb_shell.md, "Flop count"), and a dense matrix product doing the same
// number of flops timed in the same run, so the ratio says how far the element is from the rate
// this machine reaches on regular arithmetic.
nlohmann::ordered_json element_figures(int rounds) {
  using namespace shell;
  const ElementPoses ref = samples::curved();
  const ElementPoses cur = samples::deformed(ref, 5);
  ShellOptions o;
  o.hr = o.ans = true;
  o.drilling = false;
  const CbShellElement el(ref, isotropic_section(2.0e5, 0.3, 0.05), o);
  Vec24 f;
  Mat24 K;
  // the compiler must not drop evaluations whose results are unused
  double sink = 0.0;
  const double force_us = best_mean_us(rounds, 20000, [&] {
    el.evaluate(cur, f, nullptr);
    sink += f[0];
  });
  const double tangent_us = best_mean_us(rounds, 5000, [&] {
    el.evaluate(cur, f, &K);
    sink += K(0, 0);
  });
  const ElementFlops flops = count_element_flops(el, cur);
  // square product with 2 n^3 closest to the element's flops, its time scaled to exactly that count
  const int n = std::max(2, static_cast<int>(std::lround(std::cbrt(flops.force_tangent / 2.0))));
  Eigen::MatrixXd A = Eigen::MatrixXd::Random(n, n), B = Eigen::MatrixXd::Random(n, n), C(n, n);
  const double product_us = best_mean_us(rounds, 5000, [&] {
    C.noalias() = A * B;
    sink += C(0, 0);
    A(0, 0) = 1e-30 * sink;  // a data dependence between calls
  });
  const double same_flop_us = product_us * flops.force_tangent / (2.0 * n * n * n);
  // a laminated section on the same element (laminate.md): n orthotropic plies [0/90/0/...],
  // each its own layer of the kernel, timed in this run so the ratio to the isotropic one holds
  auto laminate = [&](int n) {
    auto plies = std::make_shared<std::vector<Ply>>();
    for (int k = 0; k < n; ++k)
      plies->push_back({1.4e5, 1.0e4, 5.0e3, 5.0e3, 3.5e3, 0.3, 0.05 / n, k % 2 ? 1.5707963267948966 : 0.0, 0.0, {}});
    ShellSection sec{1.4e5, 0.3, 0.05, 5.0 / 6.0, plies, Vec3::Zero()};
    const CbShellElement lam(ref, sec, o);
    const double lam_force = best_mean_us(rounds, 20000 / n, [&] {
      lam.evaluate(cur, f, nullptr);
      sink += f[0];
    });
    const double lam_tangent = best_mean_us(rounds, 5000 / n, [&] {
      lam.evaluate(cur, f, &K);
      sink += K(0, 0);
    });
    return std::pair<double, double>{lam_force, lam_tangent};
  };
  nlohmann::ordered_json laminated = nlohmann::ordered_json::array();
  std::string laminated_lines;
  for (int n : {1, 3, 8}) {
    const auto [lf, lt] = laminate(n);
    laminated.push_back({{"plies", n}, {"force_us", lf}, {"force_tangent_us", lt},
                         {"force_ratio", lf / force_us}, {"force_tangent_ratio", lt / tangent_us}});
    char line[200];
    std::snprintf(line, sizeof line, "  %d orthotropic plies: force %.3f us (x %.2f), force + tangent %.3f us (x %.2f)\n", n,
                  lf, lf / force_us, lt, lt / tangent_us);
    laminated_lines += line;
  }
  if (!std::isfinite(sink)) std::printf("(non-finite sink)\n");
  std::printf("CB element (curved, distorted, deformed; 5 DoF, hr + ans), one core:\n"
              "  force %.3f us, %lld flops (%.2f Gflop/s)\n"
              "  force + tangent %.3f us, %lld flops (%.2f Gflop/s)\n"
              "  dense %d x %d product scaled to the same flops: %.3f us (%.2f Gflop/s); element / product: %.2f\n\n",
              force_us, static_cast<long long>(flops.force), 1e-3 * flops.force / force_us, tangent_us,
              static_cast<long long>(flops.force_tangent), 1e-3 * flops.force_tangent / tangent_us, n, n, same_flop_us,
              1e-3 * flops.force_tangent / same_flop_us, tangent_us / same_flop_us);
  std::printf("Laminated sections on the same element, against the isotropic one above (x: time ratio):\n%s\n",
              laminated_lines.c_str());
  return {{"force_us", force_us},
          {"force_tangent_us", tangent_us},
          {"force_flops", flops.force},
          {"force_tangent_flops", flops.force_tangent},
          {"same_flop_product_us", same_flop_us},
          {"product_size", n},
          {"laminated", laminated}};
}

// which BLAS kernels the factorizations run on: OpenBLAS names the kernel set it picked for this
// processor (or the one OPENBLAS_CORETYPE forced); another BLAS is reported as such
std::string blas_kernels() {
  using CoreName = char* (*)();
  if (auto f = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename")))
    return std::string("OpenBLAS, ") + f() + " kernels";
  return "not OpenBLAS";
}

}  // namespace

int run_solve_bench(const BenchOptions& opt, const std::atomic<bool>& stop) {
  std::vector<LinearBackend> backends;
  for (LinearBackend b : all_linear_backends())
    // the Cholesky-type backends take symmetric positive definite tangents only: not candidates
    if (linear_backend_available(b) && !linear_backend_is_symmetric(b)) backends.push_back(b);
  // under mpirun (core/solve/distributed.md) only MUMPS spans the ranks: the others are not timed
  const int ranks = linear_solver_ranks();
  if (ranks > 1) backends = {LinearBackend::mumps};
  if (!opt.solve_backend.empty()) {
    const std::optional<LinearBackend> only = parse_linear_backend(opt.solve_backend);
    if (!only || !linear_backend_available(*only)) {
      std::fprintf(stderr, "error: --backend %s is not compiled in\n", opt.solve_backend.c_str());
      return 2;
    }
    backends = {*only};
  }
  const LinearBackend chosen = default_linear_backend();
  const int eigen_threads = Eigen::nbThreads();
  Eigen::setNbThreads(1);  // the element figures are for one core
  const nlohmann::ordered_json element = element_figures(opt.repeat);
  Eigen::setNbThreads(eigen_threads);

  const std::string blas = blas_kernels();
  std::printf("Static Newton iteration on an n x n plate (CB shell, hr + ans, 5 DoF), wall time, best of %d "
              "(1 from n = 128); default backend: %s; BLAS: %s; MUMPS %s (%s); MUMPS ordering: %s; MUMPS over "
              "%d MPI rank(s)%s\n\n",
              opt.repeat, std::string(to_string(chosen)).c_str(), blas.c_str(), mumps_version().c_str(),
              mumps_library_file().c_str(), mumps_ordering_description(), ranks,
              distributed_linear_solver_built() ? " (MPI build)" : " (sequential build)");
  std::printf("| n | DoFs | assembly [ms] |");
  for (LinearBackend b : backends) std::printf(" %s factorize + solve [ms] |", std::string(to_string(b)).c_str());
  std::printf(" default / assembly | umfpack / default | Newton iteration [ms] | MUMPS Gflop | MUMPS MB per rank (largest) | MUMPS MB, all ranks |\n|---|---|---|");
  for (std::size_t k = 0; k < backends.size() + 6; ++k) std::printf("---|");
  std::printf("\n");

  nlohmann::ordered_json plates = nlohmann::ordered_json::array();
  for (int n : {16, 32, 64, 128, 256}) {
    if (n > opt.solve_max_n || stop) break;
    PlateIteration it(n);
    // over ranks MUMPS reads each rank's part of the tangent (core/solve/distributed.md §5): its
    // solver comes first, so the assembly timed is the one in parts
    std::optional<SparseLinearSolver> shared_solver;
    std::optional<TangentInParts> parts;
    if (ranks > 1 && backends == std::vector<LinearBackend>{LinearBackend::mumps}) {
      shared_solver.emplace(LinearBackend::mumps);
      parts.emplace(*it.model, *shared_solver);
      it.assemble();
    }
    const int rounds = n >= 128 ? 1 : opt.repeat;
    const double assembly = best_of(rounds, [&] { it.assemble(); });
    nlohmann::ordered_json row = {{"n", n}, {"dofs", it.model->size()}, {"assembly_ms", 1e3 * assembly}};
    std::printf("| %d | %d | %.4g |", n, it.model->size(), 1e3 * assembly);
    double t_default = 0.0, t_umfpack = 0.0;
    LinearFigures mumps;
    for (LinearBackend b : backends) {
      // SparseLU's column ordering fills in badly on 2-D meshes: 14 s at 128 x 128, 195 s at 256
      if (b == LinearBackend::sparse_lu && n > 64) {
        std::printf(" (skipped) |");
        continue;
      }
      std::optional<SparseLinearSolver> own_solver;
      SparseLinearSolver& solver = shared_solver ? *shared_solver : own_solver.emplace(b);
      // the symbolic analysis is reused across Newton iterations: not timed. MUMPS analyzes the
      // instance it factorizes with (LDLᵀ for this symmetric tangent) at its first factorization,
      // so that one is not timed either: with it, the one timed round of n >= 128 was a
      // sequential analysis plus a factorization (a third of the time at 128 x 128)
      solver.analyze(it.K);
      (void)solver.factorize(it.K);
      bool ok = true;
      const double t = best_of(rounds, [&] {
        ok = solver.factorize(it.K) && solver.solve(it.r, it.x);
      });
      const bool ldlt = ok && solver.symmetric_factorization() && !linear_backend_is_symmetric(b);
      std::printf(ok ? (ldlt ? " %.4g (LDLᵀ) |" : " %.4g |") : " failed |", 1e3 * t);
      row[std::string(to_string(b)) + "_factorize_solve_ms"] = ok ? 1e3 * t : -1.0;
      if (ldlt) row[std::string(to_string(b)) + "_factorization"] = "ldlt";
      if (b == chosen) t_default = t;
      if (b == LinearBackend::mumps && ok) mumps = solver.factorization_figures();
      if (b == LinearBackend::umfpack) t_umfpack = t;
    }
    row["backend"] = std::string(to_string(chosen));
    row["factorize_solve_ms"] = 1e3 * t_default;
    if (t_umfpack > 0) row["umfpack_factorize_solve_ms"] = 1e3 * t_umfpack;
    row["newton_iteration_ms"] = 1e3 * (assembly + t_default);
    row["ranks"] = mumps.ranks;
    row["mumps_flops"] = mumps.flops;
    row["mumps_memory_mb_largest_rank"] = mumps.memory_mb_max_rank;
    row["mumps_memory_mb_all_ranks"] = mumps.memory_mb_total;
    row["mumps_factor_entries"] = mumps.factor_entries;
    std::printf(" %.2f | %.2f | %.4g | %.3g | %.0f | %.0f |\n", t_default / assembly, t_umfpack > 0 ? t_umfpack / t_default : 0.0,
                1e3 * (assembly + t_default), 1e-9 * mumps.flops, mumps.memory_mb_max_rank, mumps.memory_mb_total);
    std::fflush(stdout);
    plates.push_back(row);
  }
  if (!opt.out_file.empty()) {
    const nlohmann::ordered_json root{
        {"element", element}, {"plate", plates}, {"blas", blas}, {"mumps_ordering", mumps_ordering_description()},
        {"ranks", ranks}, {"mumps_build", distributed_linear_solver_built() ? "mpi" : "sequential"},
        {"mumps_version", mumps_version()}, {"mumps_library", mumps_library_file()}};
    if (!write_bench_json(opt.out_file, root.dump(2) + "\n")) return 1;
  }
  return stop ? 130 : 0;
}

}  // namespace ff::app
