#pragma once
/// \file tangent_parts.h
/// Which rank adds, holds and hands the linear solver which entries of a tangent assembled in
/// parts over the ranks sharing the solvers (core/solve/distributed.md §5, eqs. D1–D4). Each rank
/// evaluates its share of the elements (ElementShare) and adds the node-level terms of the nodes it
/// owns; an entry added by one rank only is complete there, and the entries several ranks add (the
/// interface between the shares) are summed over the ranks, their compact list only. Every rank
/// builds the same layout from the same replicated model, with no communication.

#include <array>
#include <cstddef>
#include <vector>

#include "core/solve/solver_ranks.h"

namespace ff {

/// The elements each rank evaluates when a model is shared over ranks (distributed.md (D1)):
/// METIS's partition of the mesh into one compact part per rank, so the entries two ranks add (the
/// interface Γ) are few whatever the element order of the mesh file (contiguous index ranges left
/// 20–24 % of a Gmsh mesh's entries on the interface of two ranks, 2 % of a structured grid's);
/// contiguous index ranges when METIS cannot split the mesh (fewer elements than ranks). Alone:
/// every element. Every rank computes the same partition from the same mesh.
class ElementShare {
 public:
  ElementShare() = default;  ///< no elements
  /// The share of rank `rank` of `ranks` of the elements (their nodes) of a mesh of `nodes` nodes.
  ElementShare(const std::vector<std::array<int, 4>>& elements, int nodes, int rank, int ranks);
  /// The elements this rank evaluates, ascending (alone: every element).
  const std::vector<int>& mine() const { return mine_; }
  /// Whether this share was made for a mesh of `elements` elements over `ranks` ranks (a model
  /// makes its share again when either changes).
  bool made_for(std::size_t elements, int ranks) const {
    return static_cast<std::size_t>(elements_) == elements && ranks_ == ranks;
  }
  int rank_of(int element) const { return rank_of_.empty() ? 0 : rank_of_[element]; }
  int rank() const { return rank_; }
  int ranks() const { return ranks_; }
  /// Over more than one rank (built with ranks > 1).
  bool shared() const { return ranks_ > 1; }

 private:
  int rank_ = 0, ranks_ = 1, elements_ = 0;
  std::vector<int> rank_of_;  // per element (empty alone)
  std::vector<int> mine_;
};

class TangentParts {
 public:
  TangentParts() = default;
  /// A layout of a tangent with `nonzeros` value positions and `nodes` nodes whose elements are
  /// shared as `share` says, seen from its rank. Add every element, then every node, then finish().
  TangentParts(int nonzeros, int nodes, const ElementShare& share);
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
  /// This rank adds the terms of node I's own block (its elements' are ElementShare::rank_of's).
  bool adds_node(int I) const { return owns_node_[I] != 0; }
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
  int me_ = 0;
  const ElementShare* share_ = nullptr;  // while building: the elements' ranks
  std::vector<int> lowest_, highest_;  // while building: the lowest and highest rank adding to a position
  std::vector<int> node_rank_;         // while building: the lowest rank of a node's elements
  std::vector<char> owns_node_;
  std::vector<int> held_, shared_;
  std::vector<double> buffer_;
};

}  // namespace ff
