#pragma once
/// \file solver_ranks.h
/// The processes (MPI ranks) that share one linear system. Without MPI, or in a process not
/// started by mpirun, that is the process alone and nothing here does anything.
///
/// With MUMPS's MPI build (configure FLEXFRAME_MUMPS=mpi) a program started on K ranks may call
/// share_linear_solvers_over_world(): from then on every SparseLinearSolver with the mumps backend
/// factorizes over all K ranks. The design is SPMD with a replicated model (core/solve/distributed.md):
/// every rank builds the same model and makes the same sequence of solver calls; each assembles
/// its part of the matrix and hands MUMPS the entries it holds (distributed input, no gather on one
/// rank; tangent_parts.h); the solution
/// is computed on rank 0 and broadcast, so every rank takes the same Newton update and stays in step.
/// Only the MPI C API is used, and only in solver_ranks.cpp and sparse_solver.cpp.

#include <atomic>
#include <cstddef>

namespace ff {

/// True when this build's MUMPS is the MPI one (FLEXFRAME_MUMPS=mpi).
bool distributed_linear_solver_built();

/// Ranks of the world when started by mpirun (Open MPI) or a PMI launcher such as srun, read from
/// the environment before any MPI call; 1 otherwise.
int launched_ranks();

/// This process's rank among those the launcher started (OMPI_COMM_WORLD_RANK or PMI_RANK), read
/// from the environment before any MPI call; 0 otherwise.
int launched_rank();

/// Starts MPI (thread level "multiple": the solver runs on a worker thread) unless it runs already,
/// and ends it at exit. Called by the MUMPS backend before its first instance, so a one-process
/// program (the tests) needs no call of its own. Returns false without MPI in this build.
bool ensure_solver_mpi();

/// Makes every linear solver created from now on share MPI_COMM_WORLD (all ranks must then make
/// the same solver calls in the same order). False, and nothing changed, when this build's MUMPS is
/// sequential. The solvers created before keep the communicator they were made with.
bool share_linear_solvers_over_world();

/// This process's rank among those sharing the solvers (0 when alone) and their number (1 when alone).
int linear_solver_rank();
int linear_solver_ranks();

/// Broadcasts n doubles / ints from rank 0 of the solvers' communicator (no-op when alone).
void broadcast_from_first_rank(double* values, int n);
void broadcast_from_first_rank(int* values, int n);

/// Sums `n` doubles over the ranks sharing the solvers, in place, the same result on every rank
/// (MPI_Allreduce; no-op when alone). The element loops of a model shared over ranks evaluate
/// each rank's share of the elements and sum their residuals with it (distributed.md §2), and the
/// interface entries of a matrix in parts (§5).
void sum_over_ranks(double* values, std::size_t n);

/// The largest of one value over the ranks, and the smallest, the same on every rank (no-op alone):
/// for decisions from values each rank holds only a part of (a check over its own entries).
double largest_over_ranks(double value);
int smallest_over_ranks(int value);
/// The element-wise largest of `n` doubles over the ranks, in place (no-op alone): row and column
/// maxima of a matrix whose entries are spread over the ranks (a scaling, distributed.md (D7)).
void largest_over_ranks(double* values, std::size_t n);

/// The contiguous share [begin, end) of `count` items that this rank evaluates: all of them when
/// alone, otherwise an equal share per rank in rank order.
struct RankShare {
  int begin = 0, end = 0;
};
RankShare rank_share(int count);
/// The same for rank `rank` of `ranks`.
RankShare rank_share(int count, int rank, int ranks);

/// Ends every rank at once with exit code `code` (MPI_Abort): rank 0 calls it when it stops early,
/// since the other ranks may wait in a collective call for it; half a second first, for the
/// launcher to forward what was written. Returns when alone.
void end_all_ranks(int code);

/// One stop decision for all ranks: from now on every MUMPS call shared over the ranks (each is
/// joined by all of them) first copies rank 0's `source` flag into `shared` on every rank, so
/// every rank sees a stop (rank 0's Ctrl-C) at the same point of the same solver sequence and
/// they end together instead of parting ways in the next shared call. The run and the benches
/// watch `shared` on every rank. No effect in one process.
void share_stop_over_ranks(const std::atomic<bool>* source, std::atomic<bool>* shared);
/// One more flag set with `shared` at the same call (null: none): a run whose solver watches a
/// flag of its own (it also stops on a failed output) registers it, so that it too changes only
/// at that call, never between two of them.
void also_stop_with_ranks(std::atomic<bool>* flag);
/// The copy share_stop_over_ranks describes; called by the MUMPS backend at each shared call.
void synchronize_stop_over_ranks();

/// From now on no solver shared over ranks makes another call that every rank must join: their
/// MUMPS instances are not ended (JOB = −2) but left to the process's end. For a rank that stops
/// on its own (rank 0's run ended by a failed output, while the others may still be stepping): it
/// ends every rank next (end_all_ranks), and its solvers' closing calls would wait for ranks that
/// never make them.
void leave_shared_solvers();
bool shared_solvers_left();

/// Ends MPI normally, when this module started it or the world shares the solvers (no-op otherwise).
void finish_solver_mpi();

}  // namespace ff
