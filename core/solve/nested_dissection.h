#pragma once
/// \file nested_dissection.h
/// FlexFrame's uses of METIS: a mesh's partition for the ranks of one model (partition_mesh_elements,
/// below), and a fill-reducing ordering by METIS's nested dissection (METIS_NodeND), computed by FlexFrame
/// and handed to MUMPS as a given ordering (ICNTL(7) = 1, PERM_IN) when FLEXFRAME_MUMPS_ORDERING=metis:
/// Debian's sequential MUMPS is built without METIS and orders with SCOTCH otherwise, which costs
/// 12-14 % more factorization flops on the shell plates (docs/performance.md, the last section). Not
/// the default: with it MUMPS missed the null pivot of a mechanism that SCOTCH's order revealed.
///
/// Shell matrices come in node blocks (5 or 6 unknowns with identical columns): the graph METIS
/// orders is the quotient graph of those blocks ("supervariables", columns with identical
/// patterns), so it is 5-6× smaller and the unknowns of one node stay together in the order.
#include <array>
#include <vector>

#include <Eigen/SparseCore>

namespace ff {

/// The elimination position of each unknown (0-based: position[i] = k when unknown i is the k-th
/// pivot) for the symmetric pattern of `a` (CSC; all entries or one triangle: only the pattern
/// of a + aᵀ is read, values and the diagonal are ignored). Empty when METIS fails (the caller
/// then lets MUMPS order).
std::vector<int> nested_dissection_positions(const Eigen::SparseMatrix<double>& a);

/// Columns of `a + aᵀ` (with the diagonal) grouped by identical pattern: group[i] is unknown i's
/// supervariable, numbered 0.. in order of first appearance; returns the number of groups.
int supervariables(const Eigen::SparseMatrix<double>& a, std::vector<int>& group);

/// METIS's partition of a mesh's elements into `parts` compact parts of nearly equal size
/// (METIS_PartMeshDual: the dual graph, elements adjacent when they share an edge, cut as little as
/// it can): part[k] of element k, from 0. `elements` lists each element's nodes (a repeated node, a
/// triangle stored as a degenerate quad, counts once). Empty when METIS fails or `parts` exceeds
/// the elements (the caller then shares by index). Deterministic: the same input gives the same
/// parts in every process (a fixed seed), which the ranks that compute it each rely on.
std::vector<int> partition_mesh_elements(const std::vector<std::array<int, 4>>& elements, int nodes, int parts);

}  // namespace ff
