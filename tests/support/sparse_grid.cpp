#include "tests/support/sparse_grid.h"

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <random>

namespace ff {

SparseMatrixD shell_grid_matrix(int n, double asymmetry, unsigned seed) {
  constexpr int kDof = 6;
  const int side = n + 1, nodes = side * side, size = kDof * nodes;
  // neighbours of a node (itself included), in increasing node order
  auto neighbours = [side](int node, std::array<int, 9>& out) {
    const int r = node / side, s = node % side;
    int count = 0;
    for (int dr = -1; dr <= 1; ++dr)
      for (int ds = -1; ds <= 1; ++ds)
        if (r + dr >= 0 && r + dr < side && s + ds >= 0 && s + ds < side) out[count++] = (r + dr) * side + s + ds;
    return count;
  };

  // pattern: column 6J+k holds the 6 DoFs of every neighbour of J
  SparseMatrixD a(size, size);
  std::vector<int> outer(size + 1, 0);
  std::array<int, 9> nb{};
  for (int node = 0; node < nodes; ++node) {
    const int count = neighbours(node, nb);
    for (int k = 0; k < kDof; ++k) outer[kDof * node + k + 1] = kDof * count;
  }
  for (int c = 0; c < size; ++c) outer[c + 1] += outer[c];
  a.resizeNonZeros(outer[size]);
  std::copy(outer.begin(), outer.end(), a.outerIndexPtr());
  for (int node = 0; node < nodes; ++node) {
    const int count = neighbours(node, nb);
    for (int k = 0; k < kDof; ++k) {
      int p = outer[kDof * node + k];
      for (int m = 0; m < count; ++m)
        for (int kk = 0; kk < kDof; ++kk) a.innerIndexPtr()[p++] = kDof * nb[m] + kk;
    }
  }
  std::fill(a.valuePtr(), a.valuePtr() + a.nonZeros(), 0.0);

  // add the element blocks in place
  std::mt19937 gen(seed);
  auto uniform = [&gen] { return 2.0 * (static_cast<double>(gen()) / 4294967296.0) - 1.0; };
  Eigen::Matrix<double, 24, 24> b, e;
  for (int r = 0; r < n; ++r)
    for (int s = 0; s < n; ++s) {
      const std::array<int, 4> en{r * side + s, r * side + s + 1, (r + 1) * side + s + 1, (r + 1) * side + s};
      for (int i = 0; i < 24; ++i)
        for (int j = 0; j < 24; ++j) b(i, j) = uniform();
      e = 0.5 * (b + b.transpose()) + (0.5 * asymmetry) * (b - b.transpose());
      for (int i = 0; i < 24; ++i) e(i, i) = e.row(i).cwiseAbs().sum() - std::abs(e(i, i)) + 1.0;
      for (int jn = 0; jn < 4; ++jn) {
        const int count = neighbours(en[jn], nb);
        for (int in = 0; in < 4; ++in) {
          int rank = 0;
          while (rank < count && nb[rank] != en[in]) ++rank;
          for (int kj = 0; kj < kDof; ++kj) {
            double* col = a.valuePtr() + outer[kDof * en[jn] + kj] + kDof * rank;
            for (int ki = 0; ki < kDof; ++ki) col[ki] += e(kDof * in + ki, kDof * jn + kj);
          }
        }
      }
    }
  return a;
}

}  // namespace ff
