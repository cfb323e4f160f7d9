// `flexframe bench --solve --ranks K[,K2,...] [--rounds R]`: the solve benchmark's plates over
// several rank counts in one run. This process starts `mpiexec -n K flexframe bench --solve
// --backend mumps` once per rank count and round (one after the other, never side by side; the
// order of the counts reversed every other round), reads what rank 0 of each wrote to its --json
// file and prints one table: medians over the rounds, and the speed-up against one rank as the
// median of each round's own ratio (core/solve/distributed.md).
// One rank is this executable started without mpiexec: what a user runs on one machine, its
// element loop threaded over every core (mpiexec would bind a lone rank to one core).
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/bench/bench.h"
#include "app/child_process.h"
#include "core/frame/input_file.h"
#include "core/solve/solver_ranks.h"

namespace fs = std::filesystem;

namespace ff::app {

namespace {

// FLEXFRAME_MPIEXEC when set, else the mpiexec CMake found when this build was configured (that
// of the MPI the MUMPS build was linked with); "" when neither
std::string mpi_launcher() {
  if (const char* env = std::getenv("FLEXFRAME_MPIEXEC"); env && *env) return env;
#ifdef FF_MPIEXEC
  return FF_MPIEXEC;
#else
  return "";
#endif
}

// FLEXFRAME_MPIEXEC_ARGS split at white space: options for the launcher, e.g. --oversubscribe
std::vector<std::string> launcher_options() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("FLEXFRAME_MPIEXEC_ARGS")) {
    std::istringstream in(env);
    for (std::string word; in >> word;) out.push_back(word);
  }
  return out;
}

std::string joined(const std::vector<std::string>& words) {
  std::string s;
  for (const std::string& w : words) s += (s.empty() ? "" : " ") + w;
  return s;
}

// Runs `argv` with its stdout to `log` and waits for it; returns its wait status, -1 when it
// could not start (errno kept in *spawn_error)
int run_and_wait(const std::vector<std::string>& argv, const std::string& log, int* spawn_error) {
  // the launch (mpirun, or flexframe itself) stops when this process dies, even by SIGKILL
  ChildSpec spec;
  spec.program = argv.front();
  spec.args = argv;
  spec.log = log;
  const pid_t pid = spawn_child(spec);
  if (pid < 0) {
    *spawn_error = errno;
    return -1;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  return status;
}

struct PlateRow {
  int n = 0, dofs = 0, ranks = 0;
  double assembly_ms = 0, factorize_solve_ms = 0, newton_ms = 0, gflop = 0, mb_largest = 0, mb_total = 0;
};

}  // namespace

int run_solve_bench_over_ranks(const BenchOptions& opt, const std::atomic<bool>& stop) {
  if (launched_ranks() > 1) {
    std::fprintf(stderr, "error: bench --ranks starts flexframe under mpiexec itself: run it as one process (or "
                         "leave out --ranks: `mpirun -n K flexframe bench --solve` times one rank count)\n");
    return 2;
  }
  if (!distributed_linear_solver_built()) {
    std::fprintf(stderr, "error: bench --ranks needs a flexframe built with MUMPS's MPI build: this one links the "
                         "sequential MUMPS, whose factorization runs in one process (configure with "
                         "-DFLEXFRAME_MUMPS=mpi; core/solve/distributed.md)\n");
    return 2;
  }
  if (!opt.solve_backend.empty() && opt.solve_backend != "mumps") {
    std::fprintf(stderr, "error: bench --ranks times MUMPS, the one backend that spans ranks: leave out --backend %s\n",
                 opt.solve_backend.c_str());
    return 2;
  }
  const std::string launcher = mpi_launcher();
  if (launcher.empty()) {
    std::fprintf(stderr, "error: bench --ranks needs MPI's launcher: none was found when this build was configured; "
                         "set FLEXFRAME_MPIEXEC to the mpiexec of the MPI that MUMPS was built with\n");
    return 2;
  }
  if (launcher.find('/') != std::string::npos && access(launcher.c_str(), X_OK) != 0) {
    std::fprintf(stderr, "error: bench --ranks: the MPI launcher %s (%s) is not an executable file: %s\n",
                 launcher.c_str(), std::getenv("FLEXFRAME_MPIEXEC") ? "FLEXFRAME_MPIEXEC" : "found at configuration",
                 std::strerror(errno));
    return 2;
  }
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);  // mpiexec must start this very build
  if (ec) {
    std::fprintf(stderr, "error: bench --ranks: cannot find this executable (/proc/self/exe): %s\n", ec.message().c_str());
    return 1;
  }
  // one rank is always measured: every ratio is against it, from this run
  std::vector<int> counts = opt.solve_ranks;
  counts.push_back(1);
  std::sort(counts.begin(), counts.end());
  counts.erase(std::unique(counts.begin(), counts.end()), counts.end());

  const fs::path dir = make_bench_folder("ranks");
  if (dir.empty()) {
    std::fprintf(stderr, "error: bench --ranks: cannot create a folder in %s: %s\n",
                 fs::temp_directory_path().string().c_str(), std::strerror(errno));
    return 1;
  }
  const std::vector<std::string> options = launcher_options();
  std::vector<std::string> launch_words = {launcher};
  launch_words.insert(launch_words.end(), options.begin(), options.end());

  // every launch's rows, by plate, rank count and round; the rounds alternate the order of the rank
  // counts (reversed every other round), so that neither count always runs on a machine the other
  // has just warmed or tired
  std::map<std::tuple<int, int, int>, PlateRow> rows;  // (n, ranks, round)
  std::string mumps_version, mumps_library;            // as the launched runs report them
  const int rounds = std::max(1, opt.solve_rounds);
  int code = 0;
  for (int round = 0; round < rounds && code == 0 && !stop; ++round) {
    std::vector<int> order = counts;
    if (round % 2 == 1) std::reverse(order.begin(), order.end());
    for (int k : order) {
      if (stop) break;
      const std::string tag = std::to_string(k) + "_" + std::to_string(round + 1);
      const fs::path json = dir / ("ranks_" + tag + ".json"), log = dir / ("ranks_" + tag + ".log");
      std::vector<std::string> argv = launch_words;
      argv.insert(argv.end(), {"-n", std::to_string(k)});
      if (k == 1) argv.clear();  // one process as a user starts it
      argv.insert(argv.end(), {self.string(), "bench", "--solve", "--backend", "mumps", "--max-n",
                               std::to_string(opt.solve_max_n), "--repeat", std::to_string(opt.repeat), "--json",
                               json.string()});
      std::fprintf(stderr, "bench --ranks: round %d of %d, %d rank(s): %s\n", round + 1, rounds, k, joined(argv).c_str());
      int spawn_error = 0;
      const int status = run_and_wait(argv, log.string(), &spawn_error);
      if (status < 0) {
        std::fprintf(stderr, "error: bench --ranks: cannot start %s: %s\n", launcher.c_str(), std::strerror(spawn_error));
        code = 2;
        break;
      }
      if (stop) break;
      std::string why;
      if (WIFSIGNALED(status)) why = "was killed by signal " + std::to_string(WTERMSIG(status));
      else if (WEXITSTATUS(status) != 0) why = "exited with code " + std::to_string(WEXITSTATUS(status));
      nlohmann::json root;
      if (why.empty()) {
        try {
          root = nlohmann::json::parse(read_text_or_empty(json));
          mumps_version = root.at("mumps_version");
          mumps_library = root.at("mumps_library");
          for (const nlohmann::json& p : root.at("plate")) {
            PlateRow r;
            r.n = p.at("n");
            r.dofs = p.at("dofs");
            r.ranks = p.at("ranks");
            r.assembly_ms = p.at("assembly_ms");
            r.factorize_solve_ms = p.at("mumps_factorize_solve_ms");
            r.newton_ms = p.at("newton_iteration_ms");
            r.gflop = 1e-9 * p.at("mumps_flops").get<double>();
            r.mb_largest = p.at("mumps_memory_mb_largest_rank");
            r.mb_total = p.at("mumps_memory_mb_all_ranks");
            // MUMPS must have spanned the ranks launched (a launcher of another MPI starts K lone processes)
            if (r.ranks != k) why = "factorized over " + std::to_string(r.ranks) + " rank(s), not " + std::to_string(k);
            if (r.factorize_solve_ms < 0) why = "could not factorize the " + std::to_string(r.n) + " x " + std::to_string(r.n) + " plate";
            rows[{r.n, k, round}] = r;
          }
        } catch (const std::exception& e) {
          why = std::string("left no readable ") + json.string() + " (" + e.what() + ")";
        }
      }
      if (!why.empty()) {
        std::fprintf(stderr, "error: bench --ranks: the %d-rank launch of round %d %s; its output (%s):\n%s\n", k,
                     round + 1, why.c_str(), log.string().c_str(), read_text_or_empty(log).c_str());
        code = 1;
        break;
      }
    }
  }
  if (stop) code = 130;

  // the rounds that measured every rank count of a plate (an interrupted run may have left a round
  // part-done: its rows are not used)
  std::map<int, std::vector<int>> complete_rounds;  // n -> the rounds that measured it on every count
  for (const auto& [key, r] : rows) {  // ordered by n, rank count, round: each n's rounds ascending
    const auto [n, k, round] = key;
    if (k != counts.front()) continue;
    bool all = true;
    for (int c : counts) all = all && rows.count({n, c, round});
    if (all) complete_rounds[n].push_back(round);
  }
  if (complete_rounds.empty()) return code;
  std::printf("Static Newton iteration on n x n plates (CB shell, hr + ans, 5 DoF) with MUMPS over MPI ranks, wall "
              "time, best of %d (1 from n = 128); each rank count one launch of `%s -n K flexframe bench --solve "
              "--backend mumps` (1 rank: flexframe alone, its element loop threaded), one after the other; %d "
              "alternated round(s), times the median over rounds; speed-up: the time on 1 rank / on K ranks in the "
              "same round, median (and range) over rounds; MUMPS %s (%s)\n\n",
              opt.repeat, joined(launch_words).c_str(), rounds, mumps_version.c_str(), mumps_library.c_str());
  std::printf("| n | DoFs | ranks | assembly [ms] | factorize + solve [ms] | Newton iteration [ms] | MUMPS Gflop | MUMPS MB "
              "per rank (largest) | MUMPS MB, all ranks | factorize + solve speed-up | Newton iteration speed-up |\n"
              "|---|---|---|---|---|---|---|---|---|---|---|\n");
  nlohmann::ordered_json table = nlohmann::ordered_json::array();
  for (const auto& [n, used] : complete_rounds)
    for (int k : counts) {
      std::vector<double> assembly, fs, newton, fs_ratio, newton_ratio;
      const PlateRow& first = rows.at({n, k, used.front()});
      for (int round : used) {
        const PlateRow &r = rows.at({n, k, round}), &one = rows.at({n, 1, round});
        assembly.push_back(r.assembly_ms);
        fs.push_back(r.factorize_solve_ms);
        newton.push_back(r.newton_ms);
        fs_ratio.push_back(one.factorize_solve_ms / r.factorize_solve_ms);
        newton_ratio.push_back(one.newton_ms / r.newton_ms);
      }
      const auto range = [k](const std::vector<double>& v) {
        if (v.size() < 2 || k == 1) return std::string();  // one rank against itself is 1 in every round
        const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
        char text[64];
        std::snprintf(text, sizeof text, " (%.2f–%.2f)", *lo, *hi);
        return std::string(text);
      };
      std::printf("| %d | %d | %d | %.4g | %.4g | %.4g | %.3g | %.0f | %.0f | %.2f%s | %.2f%s |\n", n, first.dofs, k,
                  median_of(assembly), median_of(fs), median_of(newton), first.gflop, first.mb_largest,
                  first.mb_total, median_of(fs_ratio), range(fs_ratio).c_str(), median_of(newton_ratio),
                  range(newton_ratio).c_str());
      table.push_back({{"n", n}, {"dofs", first.dofs}, {"ranks", k}, {"rounds", used.size()},
                       {"assembly_ms", median_of(assembly)}, {"factorize_solve_ms", median_of(fs)},
                       {"newton_iteration_ms", median_of(newton)}, {"mumps_gflop", first.gflop},
                       {"mumps_memory_mb_largest_rank", first.mb_largest},
                       {"mumps_memory_mb_all_ranks", first.mb_total}, {"factorize_solve_speedup", median_of(fs_ratio)},
                       {"newton_iteration_speedup", median_of(newton_ratio)},
                       {"factorize_solve_speedup_per_round", fs_ratio},
                       {"newton_iteration_speedup_per_round", newton_ratio}});
    }
  std::fflush(stdout);
  if (code == 0 && !opt.out_file.empty()) {
    const nlohmann::ordered_json root = {{"launcher", launch_words}, {"ranks", counts}, {"repeat", opt.repeat},
                                         {"rounds", rounds}, {"mumps_version", mumps_version},
                                         {"mumps_library", mumps_library}, {"plate", table}};
    if (!write_bench_json(opt.out_file, root.dump(2) + "\n")) code = 1;
  }
  if (code == 0) fs::remove_all(dir, ec);  // a failed launch keeps its log for the reader
  return code;
}

}  // namespace ff::app
