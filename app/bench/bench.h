#pragma once
#include <atomic>
#include <string>
#include <vector>
namespace ff::app {
struct BenchOptions {
  int repeat = 5;
  std::string out_file;  ///< optional JSON
  bool effects = false;  ///< --effects: only the effects table (run_effects_bench)
  int effects_plate = 16;  ///< --plate: elements per side of the effects benchmark's plate
  bool solve = false;      ///< --solve: only the Newton-iteration table (run_solve_bench)
  int solve_max_n = 256;   ///< --max-n: largest plate of --solve
  std::string solve_backend;  ///< --backend: only this linear backend in --solve ("" = every unsymmetric one)
  std::vector<int> solve_ranks;  ///< --ranks: --solve over these MPI rank counts (run_solve_bench_over_ranks)
  int solve_rounds = 1;          ///< --rounds: alternated rounds of the --ranks launches
  std::vector<std::string> scenes;     ///< --scene: time these scenes' whole runs (run_scene_bench)
  std::vector<std::string> overrides;  ///< --set: scene keys changed in every --scene run
  int modes = 0;                       ///< --modes N: only the eigen-solve table (run_modes_bench)
  std::vector<double> estimate_dofs;   ///< --estimate: only MUMPS's analysis estimates (run_estimate_bench)
  bool error_bars = false;             ///< --error-bars: what the error bars cost (run_error_bar_bench)
};
/// `flexframe bench`: steps/s of every bundled hub-beam scene, EFG/FEM cost ratios and headless
/// frames/s, as a markdown table. Ratios come from one run of this command.
int run_bench(const BenchOptions& options, const std::atomic<bool>& stop);
/// `flexframe bench --effects`: time saved by effects left out, as ratios from one run: a static
/// assembly (no mass matrix) against the dynamic one on the same plate, 5 against 6 DoF per node
/// (assembly and sparse factorization), hr / ans off against on, the hub-beam's zero- against
/// first-order coupling and without axial DoFs (app/bench/bench_effects.cpp).
int run_effects_bench(const BenchOptions& options, const std::atomic<bool>& stop);
/// `flexframe bench --solve`: a static Newton iteration on n x n plates (n = 16 .. 256), assembly
/// against factorization + solve for every compiled unsymmetric backend (app/bench/bench_solve.cpp).
int run_solve_bench(const BenchOptions& options, const std::atomic<bool>& stop);
/// `flexframe bench --solve --ranks K[,K2,...]`: the --solve plates with MUMPS alone over 1 and each
/// K ranks, one launch of `mpiexec -n K` of this executable per count (the launcher:
/// FLEXFRAME_MPIEXEC, else the mpiexec CMake found; options for it in FLEXFRAME_MPIEXEC_ARGS), in
/// one table with the speed-up against one rank (app/bench/bench_ranks.cpp). Exit 2 with a message when
/// this build links the sequential MUMPS, no launcher is known or it runs under mpirun itself.
int run_solve_bench_over_ranks(const BenchOptions& options, const std::atomic<bool>& stop);
/// `flexframe bench --scene S [--scene S2 ...]`: wall time of each scene's whole run, solver only
/// (no files, no frames), the median of --repeat runs, with its steps, Newton corrections and
/// matrix updates (factorizations), so a user times a scene of their own or two builds on it.
/// Exit 0 when every run completed, otherwise the exit code of the first that did not.
int run_scene_bench(const BenchOptions& options, const std::atomic<bool>& stop);
/// `flexframe bench --modes N`: N natural modes of clamped n x n plates (n = 16 .. --max-n): one
/// factorization of K - sigma M and the Lanczos solves with it, in seconds (app/bench/bench_modes.cpp).
int run_modes_bench(const BenchOptions& options, const std::atomic<bool>& stop);
/// `flexframe bench --estimate DOFS ...`: MUMPS's analysis alone of the plates' pattern (5 DoFs per
/// node) at each size: estimated flops, factor entries and memory per rank over the ranks it runs
/// on, for models too large to factorize here (app/bench/bench_estimate.cpp).
int run_estimate_bench(const BenchOptions& options, const std::atomic<bool>& stop);
/// `flexframe bench --error-bars [--scene S ...]`: each scene's `flexframe run` with error bars on
/// against off, --repeat alternated pairs of child processes: the whole command's wall-time ratio
/// and the bars' share of the run as the run prints it, beside the targets (35 % static and eigen,
/// 60 % dynamic) (app/bench/bench_error_bars.cpp). Exit 1 when a run failed (its log is kept).
int run_error_bar_bench(const BenchOptions& options, const std::atomic<bool>& stop);
/// A fresh private folder for a bench's scratch files in the system's temporary directory
/// (mkdtemp of "<temp>/flexframe_bench_<name>.XXXXXX"), so that its clean-up cannot meet anyone
/// else's files; "" with errno set when it cannot be made.
std::string make_bench_folder(const std::string& name);
/// The median of a list (the mean of the middle two for an even count); NaN when it is empty.
double median_of(std::vector<double> v);
/// Writes a bench's --json file and checks every step (open, write, close): on failure prints
/// "error: cannot write PATH: <why>" and returns false, and the command exits 1; a benchmark whose
/// numbers were not stored has failed.
bool write_bench_json(const std::string& path, const std::string& text);
}  // namespace ff::app
