#pragma once
/// \file surface_strain.h
/// A strain measure for colouring frames (not used by the solver): the largest absolute principal
/// in-plane Green-Lagrange strain over the bottom, middle and top surfaces at an element's centre
/// (cb_shell.md, eqs. V1-V3). Zero under any rigid motion.

#include <array>
#include <cstdint>
#include <vector>

#include "core/shell/cb_shell.h"

namespace ff::shell {

/// reference and current corner poses (directors = third columns), thickness h0.
double max_surface_strain(const ElementPoses& reference, const ElementPoses& current, double thickness);

/// Nodal values as the mean of the adjacent elements' values (nodes without elements get 0).
std::vector<double> average_to_nodes(const std::vector<double>& element_values,
                                     const std::vector<std::array<int, 4>>& element_nodes, int node_count);

/// Nodal display strain of a model's elements: each element needs `nodes` (4 node ids) and
/// `corner` (4 corner rotations C = R_NC, director frame R_WC = R_WN C); `thickness(element)` gives h0.
/// X_WN0 and X_WN: every node's reference and current pose.
template <class Elements, class Thickness>
std::vector<double> nodal_surface_strain(const Elements& elements, const std::vector<NodePose>& X_WN0,
                                         const std::vector<NodePose>& X_WN, Thickness thickness) {
  std::vector<double> values(elements.size());
  std::vector<std::array<int, 4>> nodes(elements.size());
  for (std::size_t k = 0; k < elements.size(); ++k) {
    const auto& e = elements[k];
    ElementPoses ref, cur;
    for (int c = 0; c < 4; ++c) {
      const int I = e.nodes[c];
      ref[c] = {X_WN0[I].R * e.corner[c], X_WN0[I].p};
      cur[c] = {X_WN[I].R * e.corner[c], X_WN[I].p};
    }
    values[k] = max_surface_strain(ref, cur, thickness(e));
    nodes[k] = e.nodes;
  }
  return average_to_nodes(values, nodes, static_cast<int>(X_WN.size()));
}

}  // namespace ff::shell
