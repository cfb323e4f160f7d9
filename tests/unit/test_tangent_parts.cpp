// A tangent assembled in parts over ranks (core/solve/tangent_parts.h, distributed.md §5,
// eqs. D1-D4), with the ranks simulated in one process: each simulated rank adds what its layout
// says it adds, the shared entries are summed over the ranks, and every rank must then hold the
// whole assembly's value at each position it hands the solver, the held lists covering every
// position once. 5 ranks over 42 elements (METIS's parts), and one node has no element. And the
// element shares: every element one rank's, compact parts whatever the element order.
#include <gtest/gtest.h>

#include <Eigen/SparseCore>
#include <algorithm>
#include <array>
#include <random>
#include <vector>

#include "core/assembly/block_pattern.h"
#include "core/assembly/dof_map.h"
#include "core/solve/solver_ranks.h"
#include "core/solve/sparse_solver.h"
#include "core/solve/tangent_parts.h"

using namespace ff;

namespace {

// a 7 x 6 grid of quads in row order, plus one node of no element (a body's, say)
struct Grid {
  static constexpr int nx = 7, ny = 6;
  int nodes = (nx + 1) * (ny + 1) + 1;
  std::vector<std::array<int, 4>> quads;
  assembly::DofMap dofs;
  assembly::BlockPattern pattern;
  std::vector<std::array<int, 576>> element_scatter;
  std::vector<std::array<int, 36>> node_scatter;
  Grid() {
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const int a = j * (nx + 1) + i;
        quads.push_back({a, a + 1, a + nx + 2, a + nx + 1});
      }
    // the first row clamped, every third node with 5 DoFs
    dofs = assembly::DofMap(nodes, [](int node, int slot) { return node > nx && !(node % 3 == 0 && slot == 5); });
    for (const auto& q : quads) pattern.add_element(q);
    for (int I = 0; I < nodes; ++I) pattern.add_block(I, I);
    pattern.build(dofs);
    for (const auto& q : quads) element_scatter.push_back(pattern.element_scatter(dofs, q));
    for (int I = 0; I < nodes; ++I) node_scatter.push_back(pattern.node_scatter(dofs, I));
  }
  int nonzeros() const { return static_cast<int>(pattern.pattern().nonZeros()); }
  ElementShare share(int rank, int ranks) const { return ElementShare(quads, nodes, rank, ranks); }
  TangentParts layout(const ElementShare& share) const {
    TangentParts parts(nonzeros(), nodes, share);
    for (std::size_t k = 0; k < quads.size(); ++k)
      parts.add_element(static_cast<int>(k), element_scatter[k].data(), 576, quads[k].data(), 4);
    for (int I = 0; I < nodes; ++I) parts.add_node(I, node_scatter[I].data(), 36);
    parts.finish();
    return parts;
  }
};

}  // namespace

TEST(TangentParts, EachRankHoldsTheWholeValueOfItsPositionsAndTheRanksHoldEachPositionOnce) {
  const Grid grid;
  const int ranks = 5, nnz = grid.nonzeros();
  std::mt19937 g(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::array<double, 576>> element_values(grid.quads.size());
  for (auto& e : element_values)
    for (double& v : e) v = u(g);
  std::vector<std::array<double, 36>> node_values(grid.nodes);
  for (auto& n : node_values)
    for (double& v : n) v = u(g);

  // the whole assembly, as one process makes it
  std::vector<double> whole(nnz, 0.0);
  for (std::size_t k = 0; k < grid.quads.size(); ++k)
    for (int q = 0; q < 576; ++q)
      if (grid.element_scatter[k][q] >= 0) whole[grid.element_scatter[k][q]] += element_values[k][q];
  for (int I = 0; I < grid.nodes; ++I)
    for (int q = 0; q < 36; ++q)
      if (grid.node_scatter[I][q] >= 0) whole[grid.node_scatter[I][q]] += node_values[I][q];

  // each rank its part (D1, D2), then the shared entries summed over the ranks (D4)
  std::vector<ElementShare> shares;
  std::vector<TangentParts> layouts;
  std::vector<std::vector<double>> part(ranks, std::vector<double>(nnz, 0.0));
  std::vector<int> adders(nnz, 0);
  for (int r = 0; r < ranks; ++r) shares.push_back(grid.share(r, ranks));
  for (int r = 0; r < ranks; ++r) {
    layouts.push_back(grid.layout(shares[r]));
    std::vector<char> added(nnz, 0);
    for (std::size_t k = 0; k < grid.quads.size(); ++k)
      if (shares[r].rank_of(static_cast<int>(k)) == r)
        for (int q = 0; q < 576; ++q)
          if (const int p = grid.element_scatter[k][q]; p >= 0) part[r][p] += element_values[k][q], added[p] = 1;
    for (int I = 0; I < grid.nodes; ++I)
      if (layouts[r].adds_node(I))
        for (int q = 0; q < 36; ++q)
          if (const int p = grid.node_scatter[I][q]; p >= 0) part[r][p] += node_values[I][q], added[p] = 1;
    for (int p = 0; p < nnz; ++p) adders[p] += added[p];
  }
  const std::vector<int>& shared = layouts[0].shared();
  for (int r = 1; r < ranks; ++r) { EXPECT_EQ(layouts[r].shared(), shared); }  // one list for the Allreduce
  std::vector<char> is_shared(nnz, 0);
  for (int p : shared) is_shared[p] = 1;
  for (int p = 0; p < nnz; ++p) { EXPECT_EQ(is_shared[p] != 0, adders[p] > 1) << "position " << p; }
  EXPECT_GT(shared.size(), 0u);
  EXPECT_LT(shared.size(), static_cast<std::size_t>(nnz) / 2);  // the interface, not the matrix
  for (int p : shared) {
    double sum = 0.0;
    for (int r = 0; r < ranks; ++r) sum += part[r][p];
    for (int r = 0; r < ranks; ++r) part[r][p] = sum;
  }

  // (D3): every position held once, each rank's held values are the whole assembly's, mirrors held
  const Eigen::SparseMatrix<double>& pattern = grid.pattern.pattern();
  std::vector<int> holder(nnz, -1);
  for (int r = 0; r < ranks; ++r) {
    const std::vector<int>& held = layouts[r].held();
    EXPECT_TRUE(std::is_sorted(held.begin(), held.end()));
    for (int p : held) {
      EXPECT_EQ(holder[p], -1) << "position " << p << " held twice";
      holder[p] = r;
      EXPECT_NEAR(part[r][p], whole[p], 1e-13) << "rank " << r << ", position " << p;
    }
  }
  for (int p = 0; p < nnz; ++p) { EXPECT_GE(holder[p], 0) << "position " << p << " held by no rank"; }
  for (int j = 0; j < pattern.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(pattern, j); it; ++it) {
      const int p = static_cast<int>(&it.value() - pattern.valuePtr());
      const int m = grid.pattern.value_index(j, static_cast<int>(it.row()));
      ASSERT_GE(m, 0);
      EXPECT_EQ(holder[m], holder[p]) << "the mirror of a held entry is held elsewhere";
    }
  // the node of no element is rank 0's
  const int lonely = grid.nodes - 1;
  EXPECT_TRUE(layouts[0].adds_node(lonely));
  for (int r = 1; r < ranks; ++r) { EXPECT_FALSE(layouts[r].adds_node(lonely)); }
}

TEST(TangentParts, OneRankHoldsEverythingAndSharesNothing) {
  const Grid grid;
  const ElementShare one = grid.share(0, 1);
  const TangentParts alone = grid.layout(one);
  EXPECT_EQ(one.mine().size(), grid.quads.size());
  EXPECT_EQ(static_cast<int>(alone.held().size()), grid.nonzeros());
  EXPECT_TRUE(alone.shared().empty());
}

TEST(TangentParts, ASolverOfOneProcessRefusesAMatrixInParts) {
  // a part of a matrix factorized alone would be a wrong matrix, not a slow one
  SparseLinearSolver solver(default_linear_backend());
  ASSERT_EQ(solver.ranks(), 1);
  const LinearStatus s = solver.hold_positions_over_ranks({0, 1, 2});
  EXPECT_EQ(s.code, LinearStatus::Code::invalid_input);
  EXPECT_EQ(solver.hold_positions_over_ranks({}).code, LinearStatus::Code::invalid_input);  // none held is still a part
  EXPECT_FALSE(solver.held_in_parts());
}

namespace {
// positions two or more ranks add to, over `ranks` shares of a grid whose quads come in `order`
double interface_fraction(int ranks, bool shuffled) {
  Grid grid;
  if (shuffled) {  // a mesh file's order: no locality at all
    std::mt19937 g(5);
    std::shuffle(grid.quads.begin(), grid.quads.end(), g);
    grid.element_scatter.clear();
    for (const auto& q : grid.quads) grid.element_scatter.push_back(grid.pattern.element_scatter(grid.dofs, q));
  }
  const ElementShare share = grid.share(0, ranks);
  return static_cast<double>(grid.layout(share).shared().size()) / grid.nonzeros();
}
}  // namespace

TEST(TangentParts, ElementSharesAreBalancedAndCompactWhateverTheElementOrder) {
  const Grid grid;
  const int count = static_cast<int>(grid.quads.size());
  for (int ranks : {2, 3, 5}) {
    std::vector<int> size(ranks, 0);
    std::vector<char> seen(count, 0);
    for (int r = 0; r < ranks; ++r) {
      const ElementShare share = grid.share(r, ranks);
      for (int k : share.mine()) {
        EXPECT_EQ(share.rank_of(k), r);
        EXPECT_FALSE(seen[k]) << "element " << k << " in two shares";
        seen[k] = 1;
        ++size[r];
      }
    }
    for (int k = 0; k < count; ++k) { EXPECT_TRUE(seen[k]) << "element " << k << " in no share"; }
    for (int r = 0; r < ranks; ++r) { EXPECT_NEAR(size[r], static_cast<double>(count) / ranks, 0.15 * count / ranks + 1) << ranks; }
  }
  // METIS's parts of a shuffled grid are as compact as of the ordered one: contiguous index ranges
  // of the shuffled order would put most entries on the interface
  for (int ranks : {2, 5}) {
    const double ordered = interface_fraction(ranks, false), shuffled = interface_fraction(ranks, true);
    EXPECT_LT(shuffled, 0.45) << ranks << " ranks";
    EXPECT_LT(shuffled, 1.5 * ordered + 0.02) << ranks << " ranks";
  }
}
