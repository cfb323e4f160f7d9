#pragma once
/// \file surface_strain.h
/// A strain measure for colouring frames (not used by the solver): the largest absolute principal
/// in-plane Green-Lagrange strain over the bottom, middle and top surfaces at an element's centre
/// (cb_shell.md, eq. S1-S3). Zero under any rigid motion.

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

}  // namespace ff::shell
