#pragma once
/// \file sparse_grid.h
/// Synthetic matrices with the sparsity of a shell stiffness: 4-node quads on an n×n grid,
/// 6 DoF per node (DoF 6·node + k, nodes numbered row by row), random 24×24 element blocks that
/// are diagonally dominant (so the assembled matrix is non-singular) and, for asymmetry > 0,
/// slightly non-symmetric. For linear-solver tests and the benchmark in tests/bench/.

#include "core/solve/sparse_solver.h"

namespace ff {

/// (n+1)² nodes, 6(n+1)² unknowns, up to 54 non-zeros per column. Element block
/// A = S + asymmetry·W with S symmetric, W skew, entries in [-1, 1], then
/// A_ii += Σ_j |A_ij| + 1. Deterministic for a given seed.
SparseMatrixD shell_grid_matrix(int n, double asymmetry = 0.05, unsigned seed = 1);

}  // namespace ff
