// `flexframe bench --estimate DOFS ...`: what MUMPS's own analysis estimates a factorization of a
// shell model of that many unknowns needs (core/solve/distributed.md "What is left" 8, docs/performance.md "On
// paper"). The model is the pattern of the bench's plates (--solve): an m x m grid of nodes with 5
// DoFs each, every node coupled to the nodes of the four quads around it (a 3 x 3 stencil of
// nodes, 25 entries per node pair), LDLᵀ of its lower triangle. No values and no factorization:
// the analysis alone sizes models that do not fit this machine, and under `mpirun -n K` it gives
// MUMPS's memory estimate per rank for K ranks.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/bench/bench.h"
#include "core/solve/solver_ranks.h"
#include "core/solve/sparse_solver.h"

namespace ff::app {

namespace {

constexpr int kDofsPerNode = 5;

// This rank's share of the lower triangle of the m x m node grid's matrix: the rows of its share of
// the nodes a, paired with the nodes b <= a of a's 3 x 3 stencil; for a = b the 15 entries of the
// lower 5 x 5 block, else all 25 (115 entries per inner node)
void plate_pattern_share(int m, std::vector<int>& rows, std::vector<int>& cols) {
  const RankShare share = rank_share(m * m);
  rows.clear();
  cols.clear();
  rows.reserve(static_cast<std::size_t>(share.end - share.begin) * 115);
  cols.reserve(static_cast<std::size_t>(share.end - share.begin) * 115);
  for (int a = share.begin; a < share.end; ++a) {
    const int i = a / m, j = a % m;
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj) {
        const int bi = i + di, bj = j + dj;
        if (bi < 0 || bj < 0 || bi >= m || bj >= m) continue;
        const int b = bi * m + bj;
        if (b > a) continue;
        for (int r = 0; r < kDofsPerNode; ++r)
          for (int c = 0; c < kDofsPerNode; ++c) {
            if (a == b && c > r) continue;
            rows.push_back(kDofsPerNode * a + r);
            cols.push_back(kDofsPerNode * b + c);
          }
      }
  }
}

}  // namespace

int run_estimate_bench(const BenchOptions& options, const std::atomic<bool>& stop) {
  const int ranks = linear_solver_ranks();
  std::printf("# MUMPS's analysis estimates for shell models of the bench plates' kind (5 DoFs per node, LDLᵀ, "
              "%d MPI rank(s))\n\n",
              ranks);
  std::printf("| DoFs asked | nodes a side | DoFs | entries (lower triangle) | Gflop | factor entries | largest front | "
              "MB, largest rank | MB, all ranks | analysis s |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  nlohmann::json rows_json = nlohmann::json::array();
  for (const double asked : options.estimate_dofs) {
    if (stop.load()) break;
    // the smallest square grid with at least the DoFs asked
    const int m = static_cast<int>(std::ceil(std::sqrt(asked / kDofsPerNode)));
    const long long dofs = static_cast<long long>(kDofsPerNode) * m * m;
    if (m < 2 || dofs > 50'000'000LL) {  // 115 entries a node, counted in MUMPS's 32-bit integers
      std::fprintf(stderr, "error: --estimate %g: between 20 and 5e7 DoFs (MUMPS's 32-bit entry count)\n", asked);
      return 2;
    }
    std::vector<int> r, c;
    plate_pattern_share(m, r, c);
    double entries = static_cast<double>(r.size());
    sum_over_ranks(&entries, 1);
    const auto t0 = std::chrono::steady_clock::now();
    FactorizationEstimate e;
    const LinearStatus st = estimate_symmetric_factorization(static_cast<int>(dofs), std::move(r), std::move(c), e);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!st) {
      std::fprintf(stderr, "error: --estimate %g: %s\n", asked, st.message.c_str());
      return 3;
    }
    std::printf("| %.3g | %d | %lld | %.0f | %.4g | %.4g | %d | %.0f | %.0f | %.2f |\n", asked, m, dofs, entries, e.flops / 1e9,
                e.factor_entries, e.largest_front, e.memory_mb_max_rank, e.memory_mb_total, seconds);
    std::fflush(stdout);
    rows_json.push_back({{"dofs_asked", asked}, {"nodes_a_side", m}, {"dofs", dofs}, {"entries", entries},
                         {"ranks", e.ranks}, {"flops", e.flops}, {"factor_entries", e.factor_entries},
                         {"largest_front", e.largest_front}, {"mb_max_rank", e.memory_mb_max_rank},
                         {"mb_total", e.memory_mb_total}, {"analysis_s", seconds}});
  }
  std::printf("\nGflop: RINFOG(1); factor entries: INFOG(20); MB: INFOG(16) and INFOG(17), the in-core factorization's "
              "estimate. Time per factorization = flops / (flop rate per core x cores x parallel efficiency): "
              "docs/performance.md.\n");
  if (!options.out_file.empty() && !write_bench_json(options.out_file, nlohmann::json{{"estimates", rows_json}}.dump(2)))
    return 1;
  return stop.load() ? 130 : 0;
}

}  // namespace ff::app
