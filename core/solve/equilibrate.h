#pragma once
/// \file equilibrate.h
/// Row and column scaling of a sparse matrix given as coordinates, for a direct solver that takes
/// a scaling from its caller (MUMPS with ICNTL(8) = -1 on one process; over MPI ranks MUMPS gets
/// the scaled entries, distributed.md (D7)). static_solvers.md §7.2 says why the scaling is
/// computed here, once per several factorizations, and not by MUMPS at every one.

#include <cstddef>
#include <vector>

namespace ff {

/// Iterative infinity-norm equilibration (Ruiz 2001, "A scaling algorithm to equilibrate both rows
/// and columns norms in matrices", RAL-TR-2001-034, Algorithm 1): with D_r, D_c starting at I,
/// repeat r_i = max_j |(D_r A D_c)_ij|, c_j = max_i |(D_r A D_c)_ij| and
/// D_r ← D_r diag(r)^(−1/2), D_c ← D_c diag(c)^(−1/2) until every row and column maximum of the
/// scaled matrix lies within `tolerance` of 1 or `max_sweeps` sweeps are done. The entries are
/// (rows[k], cols[k], values[k]) for k < nnz, indices counted from `base` (0, or 1 for MUMPS). With `symmetric_lower` the entries are the
/// lower triangle of a symmetric matrix: each also stands for its mirror, and one scaling D serves
/// both sides (row_scale = col_scale), so D A D stays symmetric. An empty row or column keeps
/// the scale 1. Returns the number of sweeps made.
/// The entries may be one part of a matrix whose parts are spread over processes, each entry in
/// exactly one part: `combine_maxima(m, n)` then replaces the n maxima m of this part by the
/// element-wise largest over the parts (an MPI_MAX reduction), and every part computes the scaling
/// of the whole matrix, bit for bit, since a maximum does not depend on the order it is taken in.
using CombineMaxima = void (*)(double* maxima, std::size_t n);
int equilibrate_inf_norm(int n, std::size_t nnz, const int* rows, const int* cols, int base, const double* values,
                         bool symmetric_lower, std::vector<double>& row_scale, std::vector<double>& col_scale,
                         double tolerance = 0.1, int max_sweeps = 20, CombineMaxima combine_maxima = nullptr);

/// True when a scaling computed for earlier values still brings every non-empty row and column
/// maximum of the current D_r A D_c within [1/spread, spread]: one pass over the entries, a
/// fraction of a new equilibration. Same entry conventions as equilibrate_inf_norm.
bool scaling_still_balances(int n, std::size_t nnz, const int* rows, const int* cols, int base, const double* values,
                            bool symmetric_lower, const std::vector<double>& row_scale,
                            const std::vector<double>& col_scale, double spread,
                            CombineMaxima combine_maxima = nullptr);

}  // namespace ff
