#include "core/assembly/block_pattern.h"

#include <algorithm>

namespace ff::assembly {

void BlockPattern::build(const DofMap& dofs) {
  std::vector<Eigen::Triplet<double>> trip;
  trip.reserve(36 * blocks_.size());
  for (const auto& [I, J] : blocks_)
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        const int a = dofs.equation(I, i), b = dofs.equation(J, j);
        if (a >= 0 && b >= 0) trip.emplace_back(a, b, 1.0);
      }
  pattern_.resize(dofs.size(), dofs.size());
  pattern_.setFromTriplets(trip.begin(), trip.end());
  pattern_.makeCompressed();
  blocks_.clear();
  blocks_.shrink_to_fit();
}

int BlockPattern::value_index(int row, int col) const {
  const int* inner = pattern_.innerIndexPtr();
  const int* begin = inner + pattern_.outerIndexPtr()[col];
  const int* end = inner + pattern_.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, row);
  return (it != end && *it == row) ? static_cast<int>(it - inner) : -1;
}

std::array<int, 576> BlockPattern::element_scatter(const DofMap& dofs, const std::array<int, 4>& nodes) const {
  std::array<int, 576> idx;
  for (int c = 0; c < 4; ++c)
    for (int d = 0; d < 4; ++d)
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) {
          const int a = dofs.equation(nodes[c], i), b = dofs.equation(nodes[d], j);
          idx[(6 * c + i) * 24 + 6 * d + j] = (a >= 0 && b >= 0) ? value_index(a, b) : -1;
        }
  return idx;
}

std::array<int, 36> BlockPattern::node_scatter(const DofMap& dofs, int node) const {
  std::array<int, 36> idx;
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const int a = dofs.equation(node, i), b = dofs.equation(node, j);
      idx[6 * i + j] = (a >= 0 && b >= 0) ? value_index(a, b) : -1;
    }
  return idx;
}

void BlockPattern::zeroed(Eigen::SparseMatrix<double>& K) const {
  // copying the pattern's index arrays at every assembly was 1-1.5 % of a static run
  const Eigen::Index n = pattern_.outerSize(), nnz = pattern_.nonZeros();
  const bool same = K.rows() == pattern_.rows() && K.cols() == pattern_.cols() && K.isCompressed() &&
                    K.nonZeros() == nnz &&
                    std::equal(K.outerIndexPtr(), K.outerIndexPtr() + n + 1, pattern_.outerIndexPtr()) &&
                    std::equal(K.innerIndexPtr(), K.innerIndexPtr() + nnz, pattern_.innerIndexPtr());
  if (!same) K = pattern_;
  std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
}

}  // namespace ff::assembly
