#include "core/solve/solver_ranks.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <thread>

#ifdef FF_MUMPS_MPI
// the C API only: Open MPI's deprecated C++ bindings would need libmpi_cxx
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

#include "core/solve/solver_ranks_mpi.h"

namespace ff {

int launched_ranks() {
  for (const char* key : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* v = std::getenv(key)) {
      const int n = std::atoi(v);
      if (n > 0) return n;
    }
  return 1;
}

int launched_rank() {
  for (const char* key : {"OMPI_COMM_WORLD_RANK", "PMI_RANK"})
    if (const char* v = std::getenv(key)) return std::max(0, std::atoi(v));
  return 0;
}

#ifdef FF_MUMPS_MPI

namespace {
std::mutex g_mutex;
bool g_world = false;   // solvers made from now on share MPI_COMM_WORLD
bool g_started = false;  // MPI was started here

void finish_at_exit() { finish_solver_mpi(); }
}  // namespace

bool distributed_linear_solver_built() { return true; }

bool ensure_solver_mpi() {
  std::lock_guard lock(g_mutex);
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  if (initialised || finalised) return initialised && !finalised;
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_MULTIPLE, &provided);
  g_started = true;
  std::atexit(finish_at_exit);
  return true;
}

bool share_linear_solvers_over_world() {
  if (!ensure_solver_mpi()) return false;
  std::lock_guard lock(g_mutex);
  g_world = true;
  return true;
}

int linear_solver_rank() {
  if (!g_world) return 0;
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  return rank;
}

int linear_solver_ranks() {
  if (!g_world) return 1;
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  return size;
}

int solver_communicator_fortran() {
  ensure_solver_mpi();
  return static_cast<int>(MPI_Comm_c2f(g_world ? MPI_COMM_WORLD : MPI_COMM_SELF));
}

void broadcast_from_first_rank(double* values, int n) {
  if (g_world && n > 0) MPI_Bcast(values, n, MPI_DOUBLE, 0, MPI_COMM_WORLD);
}

void broadcast_from_first_rank(int* values, int n) {
  if (g_world && n > 0) MPI_Bcast(values, n, MPI_INT, 0, MPI_COMM_WORLD);
}

namespace {
// an in-place Allreduce of n doubles over the solvers' ranks, in slices of at most 2^30 values
// (MPI counts are int)
void reduce_over_ranks(double* values, std::size_t n, MPI_Op op) {
  constexpr std::size_t slice = std::size_t{1} << 30;
  if (g_world && linear_solver_ranks() > 1)
    for (std::size_t at = 0; at < n; at += slice)
      MPI_Allreduce(MPI_IN_PLACE, values + at, static_cast<int>(std::min(slice, n - at)), MPI_DOUBLE, op,
                    MPI_COMM_WORLD);
}
}  // namespace

void sum_over_ranks(double* values, std::size_t n) { reduce_over_ranks(values, n, MPI_SUM); }

double largest_over_ranks(double value) {
  if (g_world && linear_solver_ranks() > 1) MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return value;
}

void largest_over_ranks(double* values, std::size_t n) { reduce_over_ranks(values, n, MPI_MAX); }

int smallest_over_ranks(int value) {
  if (g_world && linear_solver_ranks() > 1) MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return value;
}

void end_all_ranks(int code) {
  if (g_world && linear_solver_ranks() > 1) {
    // MPI_Abort makes the launcher end the job at once, and Open MPI's mpirun may then drop what
    // it had not yet forwarded of this rank's stdout (an interrupted bench's last table row was
    // lost once in a loaded test run, while the stderr line written after it arrived): the
    // caller flushed both streams, and half a second lets the launcher forward them first
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    MPI_Abort(MPI_COMM_WORLD, code);
  }
}

void finish_solver_mpi() {
  std::lock_guard lock(g_mutex);
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  if (initialised && !finalised && (g_started || g_world)) MPI_Finalize();
}

#else  // sequential MUMPS or none: one process

bool distributed_linear_solver_built() { return false; }
bool ensure_solver_mpi() { return false; }
bool share_linear_solvers_over_world() { return false; }
int linear_solver_rank() { return 0; }
int linear_solver_ranks() { return 1; }
int solver_communicator_fortran() { return -987654; }  // MUMPS's USE_COMM_WORLD for its sequential stand-in
void broadcast_from_first_rank(double*, int) {}
void broadcast_from_first_rank(int*, int) {}
void sum_over_ranks(double*, std::size_t) {}
double largest_over_ranks(double value) { return value; }
void largest_over_ranks(double*, std::size_t) {}
int smallest_over_ranks(int value) { return value; }
void end_all_ranks(int) {}
void finish_solver_mpi() {}

#endif

namespace {
std::atomic<bool> g_solvers_left{false};
const std::atomic<bool>* g_stop_source = nullptr;
std::atomic<bool>* g_stop_shared = nullptr;
std::atomic<std::atomic<bool>*> g_stop_also{nullptr};
}  // namespace

void share_stop_over_ranks(const std::atomic<bool>* source, std::atomic<bool>* shared) {
  g_stop_source = source;
  g_stop_shared = shared;
}

void also_stop_with_ranks(std::atomic<bool>* flag) { g_stop_also.store(flag); }

void synchronize_stop_over_ranks() {
  if (!g_stop_source || !g_stop_shared || linear_solver_ranks() < 2) return;
  int stop = linear_solver_rank() == 0 && g_stop_source->load() ? 1 : 0;
  broadcast_from_first_rank(&stop, 1);
  if (!stop) return;
  g_stop_shared->store(true);
  if (std::atomic<bool>* also = g_stop_also.load()) also->store(true);
}

void leave_shared_solvers() { g_solvers_left.store(true, std::memory_order_relaxed); }
bool shared_solvers_left() { return g_solvers_left.load(std::memory_order_relaxed); }

RankShare rank_share(int count) { return rank_share(count, linear_solver_rank(), linear_solver_ranks()); }

RankShare rank_share(int count, int rank, int ranks) {
  const long long c = count;
  return {static_cast<int>(c * rank / ranks), static_cast<int>(c * (rank + 1) / ranks)};
}

}  // namespace ff
