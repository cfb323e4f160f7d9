#pragma once
/// \file block_pattern.h
/// The sparsity pattern of a tangent made of 6 x 6 node blocks (element corners, a node with
/// itself, joint pairs), built once per model; assembly is then a scatter-add into the values of
/// a copy, through the value index of every entry (no triplets, no allocation per assembly).
#include <Eigen/SparseCore>
#include <array>
#include <utility>
#include <vector>

#include "core/assembly/dof_map.h"

namespace ff::assembly {

class BlockPattern {
 public:
  /// Every (node I, node J) block that may hold entries. Call before build().
  void add_block(int I, int J) { blocks_.emplace_back(I, J); }
  /// All blocks among the nodes of one element.
  template <std::size_t N>
  void add_element(const std::array<int, N>& nodes) {
    for (int I : nodes)
      for (int J : nodes) add_block(I, J);
  }
  /// Compresses the pattern over the unknowns of `dofs`.
  void build(const DofMap& dofs);

  int size() const { return static_cast<int>(pattern_.rows()); }
  /// Position of entry (row, col) in the values of a matrix with this pattern, or -1.
  int value_index(int row, int col) const;
  /// Value index of every entry of a 4-node element's 24 x 24 block, row-major over
  /// (corner c, slot i) x (corner d, slot j); -1 where a slot is no unknown.
  std::array<int, 576> element_scatter(const DofMap& dofs, const std::array<int, 4>& nodes) const;
  /// Value index of every entry of node I's own 6 x 6 block, row-major over (slot i) x (slot j);
  /// -1 where a slot is no unknown.
  std::array<int, 36> node_scatter(const DofMap& dofs, int node) const;
  /// K = the pattern with all values zero; a K that already has the pattern keeps its index
  /// arrays and only has its values cleared.
  void zeroed(Eigen::SparseMatrix<double>& K) const;
  const Eigen::SparseMatrix<double>& pattern() const { return pattern_; }

 private:
  std::vector<std::pair<int, int>> blocks_;
  Eigen::SparseMatrix<double> pattern_;
};

}  // namespace ff::assembly
