// nested_dissection_positions: a permutation that keeps a node's unknowns together and, on a
// 2-D grid, fills the factor much less than the natural (banded) order. The oracle for the fill
// is a plain elimination game on the graph (every eliminated vertex joins its remaining
// neighbours into a clique), independent of METIS and of any factorization code.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <set>

#include "core/solve/nested_dissection.h"
#include "tests/support/sparse_grid.h"

namespace ff {
namespace {

// entries of L (below the diagonal) when the unknowns are eliminated in the order `position`
long long fill_of_order(const SparseMatrixD& a, const std::vector<int>& position) {
  const int n = static_cast<int>(a.cols());
  std::vector<std::set<int>> adj(n);
  for (int j = 0; j < n; ++j)
    for (SparseMatrixD::InnerIterator it(a, j); it; ++it)
      if (it.row() != j) adj[it.row()].insert(j), adj[j].insert(static_cast<int>(it.row()));
  std::vector<int> sequence(n);
  for (int i = 0; i < n; ++i) sequence[position[i]] = i;
  std::vector<bool> gone(n, false);
  long long entries = 0;
  for (int v : sequence) {
    std::vector<int> rest;
    for (int w : adj[v])
      if (!gone[w]) rest.push_back(w);
    entries += static_cast<long long>(rest.size());
    for (int x : rest)
      for (int y : rest)
        if (x != y) adj[x].insert(y);
    gone[v] = true;
  }
  return entries;
}

TEST(NestedDissection, IsAPermutationKeepingEachNodesUnknownsTogether) {
  const SparseMatrixD k = shell_grid_matrix(6);  // 7 × 7 nodes, 6 unknowns each
  std::vector<int> group;
  EXPECT_EQ(supervariables(k, group), 49);  // one per node
  for (int i = 0; i < k.cols(); ++i) { EXPECT_EQ(group[i], group[i - i % 6]) << i; }

  const std::vector<int> position = nested_dissection_positions(k);
  ASSERT_EQ(position.size(), static_cast<std::size_t>(k.cols()));
  std::vector<int> sorted = position;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < k.cols(); ++i) { ASSERT_EQ(sorted[i], i); }
  for (int node = 0; node < 49; ++node) {
    const auto [lo, hi] = std::minmax_element(position.begin() + 6 * node, position.begin() + 6 * node + 6);
    EXPECT_EQ(*hi - *lo, 5) << "node " << node << "'s unknowns are not consecutive";
  }
}

TEST(NestedDissection, FillsLessThanTheBandedOrderOnAGrid) {
  // 2-D grid, natural order: fill ~ n^1.5 per unknown row; nested dissection: ~ N log N overall
  const SparseMatrixD k = shell_grid_matrix(14);
  std::vector<int> natural(k.cols());
  std::iota(natural.begin(), natural.end(), 0);
  const long long banded = fill_of_order(k, natural);
  const long long dissected = fill_of_order(k, nested_dissection_positions(k));
  EXPECT_LT(dissected, 0.8 * banded) << banded << " " << dissected;
}

TEST(NestedDissection, DistinctPatternsAreDistinctSupervariables) {
  // a 1-D chain: no two unknowns share a closed neighbourhood, except the two ends of a pair
  SparseMatrixD a(4, 4);
  a.insert(0, 0) = a.insert(1, 1) = a.insert(2, 2) = a.insert(3, 3) = 1.0;
  a.insert(1, 0) = a.insert(2, 1) = a.insert(3, 2) = 1.0;
  a.makeCompressed();
  std::vector<int> group;
  EXPECT_EQ(supervariables(a, group), 4);
  SparseMatrixD b(3, 3);  // unknowns 0 and 1 coupled to each other and to 2 alike
  b.insert(0, 0) = b.insert(1, 1) = b.insert(2, 2) = 1.0;
  b.insert(1, 0) = b.insert(2, 0) = b.insert(2, 1) = 1.0;
  b.makeCompressed();
  EXPECT_EQ(supervariables(b, group), 1);  // all three share {0, 1, 2}
  EXPECT_EQ(nested_dissection_positions(b).size(), 3u);
}

}  // namespace
}  // namespace ff
