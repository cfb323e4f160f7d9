#pragma once
/// \file tangent_parts.h
/// Which rank adds, holds and hands the linear solver which entries of a tangent assembled in
/// parts over the ranks sharing the solvers (core/solve/distributed.md §5, eqs. D1–D4). Each rank
/// evaluates its share of the elements (rank_share) and adds the node-level terms of the nodes it
/// owns; an entry added by one rank only is complete there, and the entries several ranks add (the
/// interface between the shares) are summed over the ranks, their compact list only. Every rank
/// builds the same layout from the same replicated model, with no communication.

#include <vector>

#include "core/solve/solver_ranks.h"

namespace ff {

class TangentParts {
 public:
  TangentParts() = default;
  /// A layout of a tangent with `nonzeros` value positions, `nodes` nodes and `elements` elements
  /// shared over the ranks in rank_share order, seen from rank `rank` of `ranks` (by default this
  /// process among those sharing the solvers). Add every element, then every node, then finish().
  TangentParts(int nonzeros, int nodes, int elements, int rank = linear_solver_rank(), int ranks = linear_solver_ranks());
  /// Element k adds to `positions` (−1 entries skipped) and holds `nodes`.
  void add_element(int k, const int* positions, int count, const int* nodes, int node_count);
  /// Node I's own block, which its owner adds to (D2): the lowest rank among its elements', rank 0
  /// for a node of no element.
  void add_node(int I, const int* positions, int count);
  /// Entries only rank 0 adds (terms that belong to no element or node: joints, bodies, ...).
  void add_first_rank(const int* positions, int count);
  /// Fixes held() and the shared list (D3).
  void finish();

  bool built() const { return built_; }
  /// This rank adds the terms of element k / of node I's own block.
  bool adds_element(int k) const { return k >= share_.begin && k < share_.end; }
  bool adds_node(int I) const { return owns_node_[I] != 0; }
  RankShare element_share() const { return share_; }
  /// The positions this rank holds complete after sum_shared() and alone hands the solver: those
  /// whose lowest adding rank it is (D3), ascending. Mirror-closed when every element's and node's
  /// positions are (a square block of unknowns).
  const std::vector<int>& held() const { return held_; }
  /// Positions added by more than one rank (the same list on every rank).
  const std::vector<int>& shared() const { return shared_; }
  /// Sums the values at the shared positions over the ranks, in place (D4): afterwards every rank
  /// holds the complete value of every entry it added.
  void sum_shared(double* values);

 private:
  void touch(int position, int rank);
  bool built_ = false;
  int me_ = 0, ranks_ = 1, elements_ = 0;
  RankShare share_;
  std::vector<int> lowest_, highest_;  // while building: the lowest and highest rank adding to a position
  std::vector<int> node_rank_;         // while building: the lowest rank of a node's elements
  std::vector<char> owns_node_;
  std::vector<int> held_, shared_;
  std::vector<double> buffer_;
};

}  // namespace ff
