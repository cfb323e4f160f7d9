// Linear-solver backends on shell-stiffness sparsity (tests/support/sparse_grid.h): analyze,
// factorize and solve timed separately for n×n quad grids, 6 DoF per node. The symmetric
// backends (cholmod_llt, simplicial_ldlt) get the symmetric part of the same pattern.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <string>

#include "tests/support/sparse_grid.h"
#include "core/solve/sparse_solver.h"

namespace {

using ff::LinearBackend;
using ff::SparseLinearSolver;
using ff::SparseMatrixD;

const SparseMatrixD& grid(int n, bool symmetric) {
  static std::map<std::pair<int, bool>, SparseMatrixD> cache;
  auto it = cache.find({n, symmetric});
  if (it == cache.end()) it = cache.emplace(std::make_pair(n, symmetric), ff::shell_grid_matrix(n, symmetric ? 0.0 : 0.05)).first;
  return it->second;
}

const SparseMatrixD& matrix_for(LinearBackend backend, int n) {
  return grid(n, ff::linear_backend_is_symmetric(backend));
}

void check(benchmark::State& state, const ff::LinearStatus& s) {
  if (!s) state.SkipWithError(s.message.c_str());
}

void set_counters(benchmark::State& state, const SparseMatrixD& k) {
  state.counters["dofs"] = static_cast<double>(k.rows());
  state.counters["nnz"] = static_cast<double>(k.nonZeros());
}

void bm_analyze(benchmark::State& state, LinearBackend backend) {
  const SparseMatrixD& k = matrix_for(backend, static_cast<int>(state.range(0)));
  SparseLinearSolver solver(backend);
  for (auto _ : state) check(state, solver.analyze(k));
  set_counters(state, k);
}

void bm_factorize(benchmark::State& state, LinearBackend backend) {
  const SparseMatrixD& k = matrix_for(backend, static_cast<int>(state.range(0)));
  SparseLinearSolver solver(backend);
  check(state, solver.analyze(k));
  for (auto _ : state) check(state, solver.factorize(k));
  set_counters(state, k);
}

void bm_solve(benchmark::State& state, LinearBackend backend) {
  const SparseMatrixD& k = matrix_for(backend, static_cast<int>(state.range(0)));
  SparseLinearSolver solver(backend);
  check(state, solver.factorize(k));
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(k.rows());
  Eigen::VectorXd x;
  for (auto _ : state) {
    check(state, solver.solve(b, x));
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["rel_residual"] = (k * x - b).norm() / b.norm();
  set_counters(state, k);
}

}  // namespace

int main(int argc, char** argv) {
  // the machine is shared: three repetitions and their minimum, except the one-shot 256×256 grid
  auto min = [](const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); };
  for (LinearBackend backend : ff::all_linear_backends()) {
    if (!ff::linear_backend_available(backend)) continue;
    const std::string name(ff::to_string(backend));
    for (auto [phase, fn] : {std::pair{"analyze", &bm_analyze}, {"factorize", &bm_factorize}, {"solve", &bm_solve}})
      for (int n : {16, 32, 64, 128, 256}) {
        auto* b = benchmark::RegisterBenchmark((name + "/" + phase).c_str(), fn, backend)->Arg(n)->Unit(benchmark::kMillisecond);
        if (n < 256)
          b->Repetitions(3)->ComputeStatistics("min", min)->ReportAggregatesOnly(true);
        else
          b->Iterations(1);
      }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
