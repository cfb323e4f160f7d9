#include "core/solve/equilibrate.h"

#include <algorithm>
#include <cmath>

namespace ff {

namespace {
// the row and column maxima of |D_r A D_c|, over every part when `combine` joins the parts
void scaled_maxima(std::size_t nnz, const int* rows, const int* cols, int base, const double* values,
                   bool symmetric_lower, const std::vector<double>& row_scale, const std::vector<double>& col_scale,
                   std::vector<double>& row_max, std::vector<double>& col_max, CombineMaxima combine) {
  std::fill(row_max.begin(), row_max.end(), 0.0);
  if (symmetric_lower) {  // (i, j) and its mirror (j, i); the column maxima are the row maxima
    for (std::size_t k = 0; k < nnz; ++k) {
      const int i = rows[k] - base, j = cols[k] - base;
      const double a = std::abs(values[k]) * row_scale[i] * row_scale[j];
      row_max[i] = std::max(row_max[i], a);
      row_max[j] = std::max(row_max[j], a);
    }
    if (combine) combine(row_max.data(), row_max.size());
    col_max = row_max;
    return;
  }
  std::fill(col_max.begin(), col_max.end(), 0.0);
  for (std::size_t k = 0; k < nnz; ++k) {
    const int i = rows[k] - base, j = cols[k] - base;
    const double a = std::abs(values[k]) * row_scale[i] * col_scale[j];
    row_max[i] = std::max(row_max[i], a);
    col_max[j] = std::max(col_max[j], a);
  }
  if (combine) {
    combine(row_max.data(), row_max.size());
    combine(col_max.data(), col_max.size());
  }
}

// every non-empty row and column maximum within [lo, hi]
bool within(const std::vector<double>& row_max, const std::vector<double>& col_max, double lo, double hi) {
  for (std::size_t i = 0; i < row_max.size(); ++i) {
    if (row_max[i] > 0.0 && (row_max[i] < lo || row_max[i] > hi)) return false;
    if (col_max[i] > 0.0 && (col_max[i] < lo || col_max[i] > hi)) return false;
  }
  return true;
}
}  // namespace

int equilibrate_inf_norm(int n, std::size_t nnz, const int* rows, const int* cols, int base, const double* values,
                         bool symmetric_lower, std::vector<double>& row_scale, std::vector<double>& col_scale,
                         double tolerance, int max_sweeps, CombineMaxima combine_maxima) {
  row_scale.assign(n, 1.0);
  col_scale.assign(n, 1.0);
  std::vector<double> row_max(n), col_max(n);
  int sweep = 0;
  for (; sweep < max_sweeps; ++sweep) {
    scaled_maxima(nnz, rows, cols, base, values, symmetric_lower, row_scale, col_scale, row_max, col_max,
                  combine_maxima);
    if (within(row_max, col_max, 1.0 - tolerance, 1.0 + tolerance)) break;
    for (int i = 0; i < n; ++i) {
      if (row_max[i] > 0.0) row_scale[i] /= std::sqrt(row_max[i]);
      if (col_max[i] > 0.0) col_scale[i] /= std::sqrt(col_max[i]);
    }
  }
  return sweep;
}

bool scaling_still_balances(int n, std::size_t nnz, const int* rows, const int* cols, int base, const double* values,
                            bool symmetric_lower, const std::vector<double>& row_scale,
                            const std::vector<double>& col_scale, double spread, CombineMaxima combine_maxima) {
  if (static_cast<int>(row_scale.size()) != n || static_cast<int>(col_scale.size()) != n) return false;
  std::vector<double> row_max(n), col_max(n);
  scaled_maxima(nnz, rows, cols, base, values, symmetric_lower, row_scale, col_scale, row_max, col_max,
                combine_maxima);
  return within(row_max, col_max, 1.0 / spread, spread);
}

}  // namespace ff
