#pragma once
/// \file blas_single_rhs.h
/// One-column BLAS-3 calls done as the BLAS-2 calls they are. A sparse direct solver's solve
/// phase with one right-hand side calls dgemm and dtrsm with a single column for every front;
/// OpenBLAS 0.3.21 (Debian 12) packs the whole panel into its blocked layout for each of them,
/// which on the shell dynamics costs more than the arithmetic (docs/performance.md, "one
/// right-hand side"). dgemv and a triangular solve read the panel once in place. The app's
/// flexframe binary routes MUMPS's, UMFPACK's and CHOLMOD's dgemm_/dtrsm_ through these
/// (app/blas_interpose.cpp); every other call goes to the BLAS unchanged. FLEXFRAME_BLAS_ROUTING=off in the environment
/// turns the routing off (before/after measurements).

namespace ff::blas {

/// C = α op(A) op(B) + β C for n = 1 (one column of C) by dgemv. Arguments as in dgemm (column
/// major, leading dimensions). Returns false, touching nothing, when the call is not of that kind.
bool gemm_one_column(char transa, char transb, int m, int n, int k, double alpha, const double* A, int lda,
                     const double* B, int ldb, double beta, double* C, int ldc);

/// Solves op(A) X = α B (side 'L', n = 1: Eigen's triangular solver on the column) or
/// X op(A) = α B (side 'R', m = 1: dtrsv on the strided row) in place in B. Arguments as in
/// dtrsm. Returns false, touching nothing, when the call is not of that kind.
bool trsm_one_column(char side, char uplo, char transa, char diag, int m, int n, double alpha, const double* A,
                     int lda, double* B, int ldb);

/// Calls that took the one-column path in this process (a run can report whether the routing is on).
long long one_column_calls();

}  // namespace ff::blas
