#pragma once
/// \file solver_ranks_mpi.h
/// For sparse_solver.cpp only: the Fortran handle of the communicator a new MUMPS instance uses
/// (MPI_COMM_SELF, or MPI_COMM_WORLD once shared; the sequential build's stand-in value otherwise).
namespace ff {
int solver_communicator_fortran();
}
