#pragma once
/// \file dof_map.h
/// The unknowns of a model of nodes: six slots per node (0-2 translations, 3-5 rotations, in the
/// node's own convention; see core/assembly/README.md), each either an unknown with its equation
/// index or absent (restrained, prescribed, or a 5-DoF node's drilling slot). Unknowns are numbered
/// node by node, slots ascending, so every model of the same nodes and restraints numbers alike.
#include <functional>
#include <vector>

namespace ff::assembly {

class DofMap {
 public:
  struct Slot {
    int node, slot;
  };
  DofMap() = default;
  /// is_unknown(node, slot) says which of the 6 slots of each node are unknowns.
  DofMap(int node_count, const std::function<bool(int node, int slot)>& is_unknown);

  int size() const { return static_cast<int>(unknowns_.size()); }
  int node_count() const { return static_cast<int>(equation_.size() / 6); }
  /// Equation index of (node, slot), or -1 when the slot is no unknown.
  int equation(int node, int slot) const { return equation_[6 * node + slot]; }
  /// The (node, slot) of unknown k.
  const Slot& unknown(int k) const { return unknowns_[k]; }
  const std::vector<Slot>& unknowns() const { return unknowns_; }

 private:
  std::vector<int> equation_;  // 6 per node
  std::vector<Slot> unknowns_;
};

}  // namespace ff::assembly
