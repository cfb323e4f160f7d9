// One model over MPI ranks (core/solve/distributed.md): `mpirun -n 2 flexframe run` against the
// same run in one process, and a rank killed mid-run (MUMPS's MPI build, -DFLEXFRAME_MUMPS=mpi);
// with the sequential MUMPS, the refusal. FF_MPIEXEC is the launcher CMake found.

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <memory>
#include <thread>

#include "app/io/results.h"
#include "cli_support.h"
#include "core/solve/solver_ranks.h"

namespace ff::cli::test {
namespace {

// The flexframe built with MUMPS's MPI build: this build's own when it is one, else the one the
// suite builds beside it (CMake: FLEXFRAME_TEST_RANKS, tests/cli/CMakeLists.txt); "" when none
std::string mpi_flexframe() {
  if (distributed_linear_solver_built()) return flexframe_exe();
#ifdef FF_MPI_FLEXFRAME
  if (fs::exists(FF_MPI_FLEXFRAME)) return FF_MPI_FLEXFRAME;
#endif
  return "";
}

// two ranks on a machine of any size, also as root (the suite runs as root in CI)
std::vector<std::string> two_ranks() {
  setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 0);
  setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 0);
  return {FF_MPIEXEC, "-n", "2", "--oversubscribe"};
}

// the flexframe processes mpirun `launcher_pid` started, by process id (rank 0 first, in practice)
std::vector<int> flexframe_children(int launcher_pid) {
  std::vector<int> pids;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const std::string stat = read_text(e.path().string() + "/stat");
    const auto open = stat.find('('), close = stat.rfind(')');
    if (open == std::string::npos || close == std::string::npos) continue;
    int parent = 0;
    char state = 0;
    if (stat.substr(open + 1, close - open - 1) == "flexframe" &&
        std::sscanf(stat.c_str() + close + 1, " %c %d", &state, &parent) == 2 && parent == launcher_pid)
      pids.push_back(std::stoi(name));
  }
  std::sort(pids.begin(), pids.end());
  return pids;
}

// the MPI rank of a process mpirun started (its OMPI_COMM_WORLD_RANK), -1 when unknown
int rank_of(int pid) {
  const std::string env = read_text("/proc/" + std::to_string(pid) + "/environ");
  const std::string key = std::string("OMPI_COMM_WORLD_RANK=");
  for (std::size_t p = 0; p < env.size(); p = env.find('\0', p) + 1) {
    if (env.compare(p, key.size(), key) == 0) return std::atoi(env.c_str() + p + key.size());
    if (env.find('\0', p) == std::string::npos) break;
  }
  return -1;
}

// The pids of ranks 0 and 1 of a two-rank job, once rank 0 has written `text` to `log_file` (by
// default its progress line, every 2 s when not on a terminal, saying the solver is stepping);
// empty when the job ended first or the ranks are not 0 and 1
std::vector<int> ranks_once_stepping(Child& c, const std::string& log_file, const std::string& text = "steps") {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(120 * slowdown());
  while (c.running() && std::chrono::steady_clock::now() < deadline && read_text(log_file).find(text) == std::string::npos)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  if (!c.running()) return {};
  std::vector<int> pids = flexframe_children(c.pid());
  if (pids.size() != 2) return {};
  if (rank_of(pids[0]) != 0) std::swap(pids[0], pids[1]);
  if (rank_of(pids[0]) != 0 || rank_of(pids[1]) != 1) return {};
  return pids;
}

// The main job's dynamics (double pendulum of shells) on two ranks, solver only: tens of seconds
Child main_job_on_two_ranks(const std::string& exe, const std::string& dir, const std::string& out) {
  return Child({"run", "double_pendulum_shells", "--no-frames", "--no-plots", "--out", out}, dir + "/run", "", two_ranks(),
               exe);
}

// summary.json's "status" and "reason" of the run written to `out` ("" when absent)
std::pair<std::string, std::string> summary_status(const std::string& out) {
  std::string err;
  const std::optional<Json> summary = read_summary(out, &err);
  const Json* status = summary ? summary->get("status") : nullptr;
  const Json* reason = summary ? summary->get("reason") : nullptr;
  return {status && status->is_string() ? status->string : "", reason && reason->is_string() ? reason->string : ""};
}

std::size_t count_of(const std::string& text, const std::string& word) {
  std::size_t n = 0;
  for (auto p = text.find(word); p != std::string::npos; p = text.find(word, p + 1)) ++n;
  return n;
}

// A two-rank job refused as bad input: it ended (no rank left waiting) with exit 2, `message`
// said once (by rank 0) and no MPI error on the way
void expect_refused_once(const ProcResult& r, const std::string& message) {
  EXPECT_FALSE(r.timed_out) << r.describe();
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_EQ(count_of(r.err, message), 1u) << r.describe();
  EXPECT_EQ(r.err.find("MPI_ERR"), std::string::npos) << r.describe();
}

ProcResult run_on(const std::vector<std::string>& launcher, const std::vector<std::string>& args,
                  const std::string& log_prefix, const std::string& exe = flexframe_exe()) {
  Child c(args, log_prefix, "", launcher, exe);
  return c.wait(240.0);
}

// the largest displacement |x - X| of a frame, and the largest difference of two frames' displacements
double largest(const std::vector<double>& v) {
  double m = 0.0;
  for (double x : v) m = std::max(m, std::abs(x));
  return m;
}

// `args` (a run of the MPI build `exe`) on one process into dir/one and on two ranks into dir/two:
// both exit 0, rank 0 alone reports (the other rank's stdout goes nowhere), and `h1`, `h2` read
// their results.h5
void run_on_one_process_and_two_ranks(const std::string& exe, std::vector<std::string> args, const std::string& dir,
                                      std::unique_ptr<io::ResultReader>& h1, std::unique_ptr<io::ResultReader>& h2) {
  std::vector<std::string> one = args, two = std::move(args);
  one.insert(one.end(), {"--out", dir + "/one"});
  two.insert(two.end(), {"--out", dir + "/two"});
  const ProcResult r1 = run_on({}, one, dir + "/one", exe);
  ASSERT_EQ(r1.exit_code, 0) << r1.describe();
  const ProcResult r2 = run_on(two_ranks(), two, dir + "/two", exe);
  ASSERT_EQ(r2.exit_code, 0) << r2.describe();
  EXPECT_EQ(count_of(r2.out, "outputs:"), 1u) << r2.out;
  std::string err;
  h1 = io::ResultReader::open(dir + "/one/results.h5", &err);
  ASSERT_TRUE(h1) << err;
  h2 = io::ResultReader::open(dir + "/two/results.h5", &err);
  ASSERT_TRUE(h2) << err;
  EXPECT_EQ(h1->outcome().status, RunStatus::completed) << h1->outcome().reason;
  EXPECT_EQ(h2->outcome().status, RunStatus::completed) << h2->outcome().reason;
}

// `args` (a run) on one process and on two ranks: both complete, rank 0 alone reports, they take
// the same Newton corrections and matrix updates (a wrong matrix converges to the same state, but
// not in the same corrections), and every frame's displacements agree to `relative` of the
// run's largest one (and the load factors)
void expect_two_ranks_run_the_model_of_one(const std::vector<std::string>& args, double relative) {
  const std::string exe = mpi_flexframe();
  if (exe.empty()) GTEST_SKIP() << "no flexframe with MUMPS's MPI build (configure with FLEXFRAME_TEST_RANKS=ON)";
  const std::string dir = fresh_test_dir();
  std::unique_ptr<io::ResultReader> h1, h2;
  run_on_one_process_and_two_ranks(exe, args, dir, h1, h2);
  if (testing::Test::HasFatalFailure()) return;
  std::string err;
  const std::optional<Json> s1 = read_summary(dir + "/one", &err), s2 = read_summary(dir + "/two", &err);
  ASSERT_TRUE(s1 && s2) << err;
  for (const char* count : {"steps", "newton_iterations", "jacobian_updates"}) {
    const Json *c1 = s1->get(count), *c2 = s2->get(count);
    ASSERT_TRUE(c1 && c2 && c1->is_number() && c2->is_number()) << count;
    EXPECT_EQ(c1->number, c2->number) << count;
  }

  ASSERT_EQ(h1->frame_count(), h2->frame_count());
  ASSERT_GE(h1->frame_count(), 2u);  // the reference state and a computed one at least
  // against the run's largest displacement: a vibration passes through frames of almost none
  std::vector<double> differences;
  double scale = 0.0;
  for (std::size_t i = 0; i < h1->frame_count(); ++i) {
    const Frame a = h1->frame(i), b = h2->frame(i);
    ASSERT_EQ(a.points.size(), b.points.size());
    std::vector<double> ua(a.points.size()), diff(a.points.size());
    for (std::size_t k = 0; k < a.points.size(); ++k) {
      ua[k] = a.points[k] - a.base_points[k];
      diff[k] = (b.points[k] - b.base_points[k]) - ua[k];
    }
    differences.push_back(largest(diff));
    scale = std::max(scale, largest(ua));
    EXPECT_NEAR(a.load_factor, b.load_factor, relative * std::max(1.0, std::abs(a.load_factor))) << "frame " << i;
  }
  ASSERT_GT(scale, 0.0);
  for (std::size_t i = 0; i < differences.size(); ++i)
    EXPECT_LE(differences[i], relative * scale) << "frame " << i << " of a run whose largest displacement is " << scale;
}

// A static shell path (arc-length, LDLᵀ and LU factorizations) run on one process and on two ranks,
// each rank assembling its part of the tangent (core/solve/distributed.md §5): the same steps and
// every frame's displacements equal to 1e-10 relative to the largest one. And a plate meshed by
// Gmsh from a .geo part, whose element order is not spatial: the ranks take METIS's parts (D1).
TEST(CliRanks, TwoRanksRunTheModelOfOne) {
  expect_two_ranks_run_the_model_of_one(
      {"run", "hinged_roof_h127", "--no-frames", "--no-plots", "--quiet", "--set", "solver.max_steps=12"}, 1e-10);
  expect_two_ranks_run_the_model_of_one({"run", "clamped_plate_pressure_geo", "--no-frames", "--no-plots", "--quiet"},
                                        1e-10);
}

// A model so small that one rank holds no entry of the tangent: a 2 x 2 plate clamped all round,
// whose one free node's block is rank 0's. That rank's part is empty, not the whole matrix; when an
// empty list meant "whole", the ranks parted ways in the solver's checks and the job hung.
TEST(CliRanks, ARankThatHoldsNoEntryStillTakesPart) {
  expect_two_ranks_run_the_model_of_one({"run", "clamped_plate_pressure", "--no-frames", "--no-plots", "--quiet", "--set",
                                         "part[0].n1=2", "--set", "part[0].n2=2"},
                                        1e-10);
}

// Dynamics with the iteration matrix in parts (core/solve/distributed.md §5): the main job (two
// shells, a hinge between them and one to the ground: joint couplings rank 0 adds, the diagonal
// reductions of (D6)) for 0.1 s of the lazy matrix policy, and a static preload Newton before a
// release (a fresh stiffness matrix every correction: without the interface sums (D4) it does not
// converge on two ranks). Every frame as on one process to 1e-10 of its largest displacement.
TEST(CliRanks, TwoRanksRunTheDynamicsOfOne) {
  expect_two_ranks_run_the_model_of_one({"run", "double_pendulum_shells", "--no-frames", "--no-plots", "--quiet", "--set",
                                         "solver.end=0.1"},
                                        1e-10);
  expect_two_ranks_run_the_model_of_one({"run", "cantilever_preload_release", "--no-frames", "--no-plots", "--quiet",
                                         "--set", "solver.end=0.05"},
                                        1e-10);
}

// A modal analysis on one process of the MPI build and on two ranks: both complete, with the same
// frequencies (to round-off). The one process failed in 3 runs of 3 at one time (and in none of
// 12 later: a race): MPI, started lazily before the first MUMPS instance, forked Open MPI's helper
// daemon while results.h5 was open, the daemon held the file's lock until it closed its inherited
// files, and the mode outputs could not read results.h5 back ("unable to lock file"). MPI now
// starts before any file is opened.
TEST(CliRanks, ModalAnalysisOnOneProcessAndOnTwoRanks) {
  const std::string exe = mpi_flexframe();
  if (exe.empty()) GTEST_SKIP() << "no flexframe with MUMPS's MPI build (configure with FLEXFRAME_TEST_RANKS=ON)";
  std::unique_ptr<io::ResultReader> h1, h2;
  run_on_one_process_and_two_ranks(exe, {"run", "modal_clamped_plate", "--no-frames", "--no-plots", "--quiet"},
                                   fresh_test_dir(), h1, h2);
  if (HasFatalFailure()) return;
  const ModeSet *m1 = h1->modes(), *m2 = h2->modes();
  ASSERT_TRUE(m1 && m2);
  ASSERT_EQ(m1->modes.size(), m2->modes.size());
  ASSERT_FALSE(m1->modes.empty());
  for (std::size_t i = 0; i < m1->modes.size(); ++i)
    EXPECT_NEAR(m1->modes[i].value, m2->modes[i].value, 1e-9 * m1->modes[i].value) << "mode " << i + 1;
}

// Under mpirun the benches of one process are refused at once (exit 2, the benches that do run
// named), on every rank alike. Before, `bench --effects` on two ranks ended in MPI_ERR_TRUNCATE:
// its rounds stop on timings, which differ between ranks, and the ranks parted ways in a shared
// element-loop sum.
TEST(CliRanks, BenchesOfOneProcessAreRefusedUnderRanks) {
  const std::string exe = mpi_flexframe();
  if (exe.empty()) GTEST_SKIP() << "no flexframe with MUMPS's MPI build (configure with FLEXFRAME_TEST_RANKS=ON)";
  const std::string dir = fresh_test_dir();
  expect_refused_once(run_on(two_ranks(), {"bench", "--effects", "--plate", "4"}, dir + "/effects", exe),
                      "error: under mpirun, bench takes --solve, --scene, --modes or --estimate");
}

// Under mpirun the verbs of one process (replay here; check, compare, scenes, policies, gui alike)
// are refused on every rank, with one message: before, each rank ran the same replay into the same
// folder, and the second was refused by the folder's lock while the first wrote.
TEST(CliRanks, VerbsOfOneProcessAreRefusedUnderRanks) {
  const std::string dir = fresh_test_dir();
  const std::string stored = dir + "/stored";
  const ProcResult made =
      run_flexframe({"run", "clamped_plate_pressure", "--no-frames", "--no-plots", "--quiet", "--out", stored}, dir + "/made");
  ASSERT_EQ(made.exit_code, 0) << made.describe();
  expect_refused_once(run_on(two_ranks(), {"replay", stored, "--no-frames", "--out", dir + "/replay"}, dir + "/replay"),
                      "error: flexframe replay runs as one process");
  EXPECT_FALSE(fs::exists(dir + "/replay")) << "a refused replay wrote its folder";
}

// A bad scene key under two ranks: every rank meets it, rank 0 alone reports it (file, key), and
// the job ends with exit 2 before anything is written. Before, each rank printed the same error.
TEST(CliRanks, BadSceneKeyIsReportedOnceOverRanks) {
  const std::string exe = mpi_flexframe();
  if (exe.empty()) GTEST_SKIP() << "no flexframe with MUMPS's MPI build (configure with FLEXFRAME_TEST_RANKS=ON)";
  const std::string dir = fresh_test_dir();
  expect_refused_once(
      run_on(two_ranks(), {"run", "hinged_roof_h127", "--set", "solver.bogus=1", "--out", dir + "/out"}, dir + "/bad", exe),
      "unknown key 'solver.bogus'");
  EXPECT_FALSE(fs::exists(dir + "/out")) << "a refused scene wrote its folder";
}

// One of two ranks killed mid-run: the run ends (no rank waits forever), not as completed, and
// rank 0's results.h5 holds the frames it had stored, readable by replay. Rank 0 closed the file
// itself within the launcher's grace between SIGTERM and SIGKILL, its solver thread blocked in a
// MUMPS call for the dead rank: the outcome in results.h5, summary.json and replay's report names
// the launcher's SIGTERM (not the writer's "did not finish" of a process killed before closing).
TEST(CliRanks, KilledRankLeavesReadableResults) {
  const std::string exe = mpi_flexframe();
  if (exe.empty()) GTEST_SKIP() << "no flexframe with MUMPS's MPI build (configure with FLEXFRAME_TEST_RANKS=ON)";
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  Child c = main_job_on_two_ranks(exe, dir, out);
  ASSERT_TRUE(c.started());
  const std::vector<int> ranks = ranks_once_stepping(c, dir + "/run.stderr.txt");
  ASSERT_EQ(ranks.size(), 2u) << "no two stepping ranks 0 and 1";
  // a few seconds more and results.h5 has been flushed (at least once a second) with frames in it
  std::this_thread::sleep_for(std::chrono::seconds(3));
  ASSERT_TRUE(c.running()) << "the run ended before a rank could be killed";
  const int rank_zero = ranks[0], rank_one = ranks[1];
  ASSERT_EQ(kill(rank_one, SIGKILL), 0);
  const ProcResult r = c.wait(120.0);
  std::string err;
  EXPECT_FALSE(r.timed_out) << "a rank kept waiting after the other was killed\n" << r.describe();
  EXPECT_NE(r.exit_code, 0) << r.describe();
  // the launcher may return while rank 0 is still closing its results file (its main thread a
  // zombie while its writer thread runs on): rank 0 must end too, every thread of it
  const std::string status_file = "/proc/" + std::to_string(rank_zero) + "/status";
  auto ended = [&] {
    const std::string st = read_text(status_file);  // "" once reaped
    return st.empty() || (st.find("State:\tZ") != std::string::npos && st.find("Threads:\t1\n") != std::string::npos);
  };
  const auto gone_by = std::chrono::steady_clock::now() + std::chrono::duration<double>(30 * slowdown());
  while (!ended() && std::chrono::steady_clock::now() < gone_by) std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_TRUE(ended()) << "rank 0 outlived the launcher by 30 s:\n" << read_text(status_file);

  const auto h = io::ResultReader::open(out + "/results.h5", &err);
  ASSERT_TRUE(h) << err;
  EXPECT_GE(h->frame_count(), 2u);
  EXPECT_EQ(h->outcome().status, RunStatus::interrupted) << h->outcome().reason;
  const std::string launcher = "stopped by SIGTERM from the MPI launcher at step ";
  EXPECT_NE(h->outcome().reason.find(launcher), std::string::npos) << h->outcome().reason;
  EXPECT_NE(h->outcome().reason.find("another rank may have died"), std::string::npos) << h->outcome().reason;
  // the step named is that of the last frame in the file
  const Frame last = h->frame(h->frame_count() - 1);
  EXPECT_NE(h->outcome().reason.find(launcher + std::to_string(last.step) + ","), std::string::npos)
      << h->outcome().reason << " (last stored frame: step " << last.step << ")";
  EXPECT_EQ(summary_status(out), std::make_pair(std::string("interrupted"), h->outcome().reason));
  const ProcResult replay = run_flexframe({"replay", out, "--no-frames", "--out", dir + "/replay"}, dir + "/replay");
  EXPECT_EQ(replay.exit_code, 0) << replay.describe();
  EXPECT_NE(replay.out.find(launcher), std::string::npos) << replay.describe();
}

// Ctrl-C reaching rank 0 alone: its run stops at the next step and writes its results, and then it
// ends every rank (exit 130). Before, it hung: destroying its model made MUMPS's closing call,
// which every rank must make, while the other rank was still stepping.
TEST(CliRanks, InterruptedRankZeroEndsEveryRank) {
  const std::string exe = mpi_flexframe();
  if (exe.empty()) GTEST_SKIP() << "no flexframe with MUMPS's MPI build (configure with FLEXFRAME_TEST_RANKS=ON)";
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  Child c = main_job_on_two_ranks(exe, dir, out);
  ASSERT_TRUE(c.started());
  const std::vector<int> ranks = ranks_once_stepping(c, dir + "/run.stderr.txt");
  ASSERT_EQ(ranks.size(), 2u) << "the run ended before rank 0 could be interrupted";
  ASSERT_EQ(kill(ranks[0], SIGINT), 0);
  const ProcResult r = c.wait(60.0);
  EXPECT_FALSE(r.timed_out) << "the ranks did not end after rank 0 was interrupted\n" << r.describe();
  EXPECT_EQ(r.exit_code, 130) << r.describe();
  std::string err;
  const auto h = io::ResultReader::open(out + "/results.h5", &err);
  ASSERT_TRUE(h) << err;
  EXPECT_EQ(h->outcome().status, RunStatus::interrupted);
  EXPECT_NE(h->outcome().reason.find("interrupted by the user"), std::string::npos) << h->outcome().reason;
  EXPECT_EQ(summary_status(out).first, "interrupted");
}

// The same for `bench --scene` over two ranks: Ctrl-C reaching rank 0 alone, during the second
// scene, ends every rank with exit 130 and the interrupted run's row. Before, rank 0's timed run
// ended its MUMPS instances (a call every rank joins) while the other rank was still stepping,
// and the job hung (MUMPS reported INFO(1) = -3 on the way).
TEST(CliRanks, InterruptedBenchOverRanksEndsEveryRank) {
  const std::string exe = mpi_flexframe();
  if (exe.empty()) GTEST_SKIP() << "no flexframe with MUMPS's MPI build (configure with FLEXFRAME_TEST_RANKS=ON)";
  const std::string dir = fresh_test_dir();
  Child c({"bench", "--scene", "hinged_roof_h127", "--scene", "double_pendulum_shells", "--repeat", "1"}, dir + "/bench", "",
          two_ranks(), exe);
  ASSERT_TRUE(c.started());
  // the first scene's row is written (and flushed) when it is done: the second is running then
  const std::vector<int> ranks = ranks_once_stepping(c, dir + "/bench.stdout.txt", "| hinged_roof_h127 | completed");
  ASSERT_EQ(ranks.size(), 2u) << "the bench ended before rank 0 could be interrupted";
  std::this_thread::sleep_for(std::chrono::seconds(1));
  ASSERT_EQ(kill(ranks[0], SIGINT), 0);
  const ProcResult r = c.wait(60.0);
  EXPECT_FALSE(r.timed_out) << "the ranks did not end after rank 0 was interrupted\n" << r.describe();
  EXPECT_EQ(r.exit_code, 130) << r.describe();
  EXPECT_NE(r.out.find("| double_pendulum_shells | interrupted |"), std::string::npos) << r.describe();
  EXPECT_EQ(r.err.find("ERROR RETURN"), std::string::npos) << r.describe();  // no MUMPS call left unmatched
}

// `bench --solve --ranks 1,2` on the smallest plates: one table with a row per plate and rank count,
// MUMPS over as many ranks as launched (its own report), times and memory that make sense, and the
// speed-up computed against the one-rank row of the same run.
TEST(CliRanks, BenchOverRanksPrintsOneTable) {
  const std::string exe = mpi_flexframe();
  if (exe.empty()) GTEST_SKIP() << "no flexframe with MUMPS's MPI build (configure with FLEXFRAME_TEST_RANKS=ON)";
  const std::string dir = fresh_test_dir();
  two_ranks();  // the launcher's variables for root
  setenv("FLEXFRAME_MPIEXEC_ARGS", "--oversubscribe", 1);
  const ProcResult r = run_on({}, {"bench", "--solve", "--ranks", "1,2", "--max-n", "32", "--repeat", "1", "--json",
                                   dir + "/ranks.json"},
                              dir + "/bench", exe);
  unsetenv("FLEXFRAME_MPIEXEC_ARGS");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  for (const char* row : {"| 16 | 1360 | 1 |", "| 16 | 1360 | 2 |", "| 32 | 5280 | 1 |", "| 32 | 5280 | 2 |"})
    EXPECT_EQ(count_of(r.out, row), 1u) << row << "\n" << r.out;
  EXPECT_NE(r.out.find("speed-up"), std::string::npos) << r.out;

  std::string err;
  const std::optional<Json> root = parse_json(read_text(dir + "/ranks.json"), &err);
  ASSERT_TRUE(root) << err;
  const Json* plates = root->get("plate");
  ASSERT_TRUE(plates && plates->kind == Json::Kind::array);
  ASSERT_EQ(plates->array.size(), 4u);
#ifdef FF_MPI_MUMPS_DIR
  // the MPI flexframe runs MUMPS from the folder scripts/build_mumps --mpi made, as configured (a
  // configure that kept an earlier cached find of Debian's libdmumps would link 5.5.1 instead)
  if (std::string configured = FF_MPI_MUMPS_DIR; !configured.empty()) {
    const Json* library = root->get("mumps_library");
    ASSERT_TRUE(library && library->kind == Json::Kind::string);
    EXPECT_EQ(library->string.rfind(fs::canonical(configured).string() + "/lib/", 0), 0u) << library->string;
  }
#endif
  auto number = [](const Json& row, const char* key) {
    const Json* v = row.get(key);
    EXPECT_TRUE(v && v->is_number()) << key;
    return v && v->is_number() ? v->number : std::nan("");
  };
  for (std::size_t i = 0; i < 4; i += 2) {  // rows by plate, then rank count: (n, 1 rank), (n, 2 ranks)
    const Json &one = plates->array[i], &two = plates->array[i + 1];
    EXPECT_EQ(number(one, "n"), number(two, "n"));
    EXPECT_EQ(number(one, "ranks"), 1.0);
    EXPECT_EQ(number(two, "ranks"), 2.0);
    for (const Json* row : {&one, &two}) {
      const double fs = number(*row, "factorize_solve_ms"), newton = number(*row, "newton_iteration_ms");
      EXPECT_GT(fs, 0.0);
      EXPECT_LT(fs, 60e3);
      EXPECT_GE(newton, fs);  // the iteration is assembly + factorization + solve
      EXPECT_GT(number(*row, "mumps_gflop"), 0.0);
      const double largest = number(*row, "mumps_memory_mb_largest_rank"), total = number(*row, "mumps_memory_mb_all_ranks");
      EXPECT_GT(largest, 0.0);
      EXPECT_GE(total, largest);
      EXPECT_LE(total, number(*row, "ranks") * largest);
    }
    EXPECT_EQ(number(one, "factorize_solve_speedup"), 1.0);
    EXPECT_NEAR(number(two, "factorize_solve_speedup"),
                number(one, "factorize_solve_ms") / number(two, "factorize_solve_ms"), 1e-12);
    EXPECT_NEAR(number(two, "newton_iteration_speedup"),
                number(one, "newton_iteration_ms") / number(two, "newton_iteration_ms"), 1e-12);
  }
}

// `--rounds R` alternates the launches (1 then 2 ranks, then 2 then 1, ...) and reports medians:
// each speed-up the median of the rounds' own ratios, which the JSON keeps one by one; `--rounds`
// without `--ranks` is refused
TEST(CliRanks, BenchOverRanksAlternatesItsRounds) {
  const std::string exe = mpi_flexframe();
  if (exe.empty()) GTEST_SKIP() << "no flexframe with MUMPS's MPI build (configure with FLEXFRAME_TEST_RANKS=ON)";
  const std::string dir = fresh_test_dir();
  two_ranks();
  setenv("FLEXFRAME_MPIEXEC_ARGS", "--oversubscribe", 1);
  const ProcResult r = run_on({}, {"bench", "--solve", "--ranks", "2", "--rounds", "3", "--max-n", "16", "--repeat",
                                   "1", "--json", dir + "/rounds.json"},
                              dir + "/bench", exe);
  unsetenv("FLEXFRAME_MPIEXEC_ARGS");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  // the launch order, as announced on stderr: 1, 2 | 2, 1 | 1, 2
  std::vector<std::size_t> at;
  for (const char* launch : {"round 1 of 3, 1 rank(s)", "round 1 of 3, 2 rank(s)", "round 2 of 3, 2 rank(s)",
                             "round 2 of 3, 1 rank(s)", "round 3 of 3, 1 rank(s)", "round 3 of 3, 2 rank(s)"}) {
    at.push_back(r.err.find(launch));
    ASSERT_NE(at.back(), std::string::npos) << launch << "\n" << r.err;
  }
  EXPECT_TRUE(std::is_sorted(at.begin(), at.end())) << r.err;

  std::string err;
  const std::optional<Json> root = parse_json(read_text(dir + "/rounds.json"), &err);
  ASSERT_TRUE(root) << err;
  ASSERT_TRUE(root->get("rounds") && root->get("rounds")->number == 3.0);
  const Json* plates = root->get("plate");
  ASSERT_TRUE(plates && plates->kind == Json::Kind::array);
  ASSERT_EQ(plates->array.size(), 2u);  // 16 x 16 on 1 and on 2 ranks
  const Json& two = plates->array[1];
  ASSERT_EQ(two.get("ranks")->number, 2.0);
  for (const char* key : {"factorize_solve_speedup", "newton_iteration_speedup"}) {
    const Json* per_round = two.get(std::string(key) + "_per_round");
    ASSERT_TRUE(per_round && per_round->kind == Json::Kind::array) << key;
    ASSERT_EQ(per_round->array.size(), 3u) << key;
    std::vector<double> v;
    for (const Json& x : per_round->array) v.push_back(x.number);
    std::sort(v.begin(), v.end());
    EXPECT_GT(v.front(), 0.0) << key;
    EXPECT_EQ(two.get(key)->number, v[1]) << key;  // the median of three
  }

  const ProcResult bad = run_on({}, {"bench", "--solve", "--rounds", "3"}, dir + "/bad", exe);
  EXPECT_EQ(bad.exit_code, 2) << bad.describe();
  EXPECT_NE(bad.err.find("--rounds"), std::string::npos) << bad.err;
}

// The sequential MUMPS has no ranks to time: `bench --solve --ranks 2` says so and how to build the
// MPI one (exit 2), and launches nothing
TEST(CliRanks, SequentialBuildRefusesBenchOverRanks) {
  if (distributed_linear_solver_built()) GTEST_SKIP() << "MPI build: see CliRanks.BenchOverRanksPrintsOneTable";
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_on({}, {"bench", "--solve", "--ranks", "2", "--max-n", "16"}, dir + "/bench");
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("bench --ranks needs a flexframe built with MUMPS's MPI build"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find("-DFLEXFRAME_MUMPS=mpi"), std::string::npos) << r.describe();
  EXPECT_EQ(r.out.find("| n |"), std::string::npos) << r.describe();
}

// A study under mpirun still spreads its variants over the ranks, each variant a process of its
// own: with MUMPS's MPI build that child starts MPI alone, which the launcher's inherited
// variables made fail before (every variant "exited with code 1 without a result").
TEST(CliRanks, StudyVariantsRunUnderTwoRanks) {
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_on(two_ranks(), {"study", "hinged_roof_h127", "--vary", "solver.max_steps=2,3", "--metric",
                                            "w_final", "--out", dir + "/out"},
                              dir + "/study");
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  const std::string table = read_text(dir + "/out/study.md");
  EXPECT_EQ(count_of(table, "| solver.max_steps="), 2u) << table;
  EXPECT_EQ(count_of(table, "without a result"), 0u) << table;
  EXPECT_EQ(count_of(table, "incomplete: step budget"), 2u) << table;
}

// The sequential MUMPS cannot share a model: `run` under a two-rank mpirun says so and how to build
// the MPI one (exit 2), instead of running two copies that write the same folder.
TEST(CliRanks, SequentialBuildRefusesRanks) {
  if (distributed_linear_solver_built()) GTEST_SKIP() << "MPI build: see CliRanks.TwoRanksRunTheModelOfOne";
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_on(two_ranks(), {"run", "clamped_plate_pressure", "--no-frames", "--no-plots", "--quiet",
                                            "--out", dir + "/out"},
                              dir + "/run");
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("-DFLEXFRAME_MUMPS=mpi"), std::string::npos) << r.describe();
  EXPECT_FALSE(fs::exists(dir + "/out/results.h5"));
}

}  // namespace
}  // namespace ff::cli::test
