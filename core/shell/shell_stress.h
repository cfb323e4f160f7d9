#pragma once
/// \file shell_stress.h
/// Stress fields of a structure's CB shell elements for output (laminate.md section 6): the
/// section stresses at the bottom, middle and top surfaces, von Mises, the in-plane principal
/// stresses, the resultants N, M, Q and, for laminates, each ply's stresses in its fibre axes and
/// its Tsai-Wu index. Recovered per element at its corners (CbShellElement::stresses: the bilinear
/// field through the element's 2 x 2 points, extrapolated, as contour plots of finite element codes
/// do) and written per node as the mean of the adjacent elements' corner values (a node no element
/// with that ply touches gets 0). The derived values (von Mises, principal, Tsai-Wu) are formed at
/// the corners before averaging. Not used by the solver.

#include <string>
#include <vector>

#include "core/shell/shell_elements.h"

namespace ff::shell {

struct StressField {
  std::string name;         ///< e.g. "von_mises", "sigma11_top", "N11", "ply2_sigma1"
  std::string description;  ///< one line, for results.h5 and the reference
};

/// What a set of elements can report: the ply fields up to the largest ply count, the failure
/// index when any ply has strengths.
struct StressLayout {
  int max_plies = 0;
  bool failure_index = false;
};
StressLayout stress_layout(const ShellElements& elements);

/// The fields of a layout, in the order nodal_stress_fields returns them.
std::vector<StressField> stress_fields(const StressLayout& layout);

/// Every field of stress_fields(layout) per node (node count = X_WN.size()), at the node poses
/// X_WN of a model whose elements are `elements`.
std::vector<std::vector<double>> nodal_stress_fields(const ShellElements& elements, const StressLayout& layout,
                                                     const std::vector<NodePose>& X_WN);

/// Field number `field` of stress_fields(layout) at node `node`, by the rule of nodal_stress_fields
/// and equal to its value there bit for bit, evaluating only the elements around the node (a scan
/// of the node numbers finds them): what a probe reads.
double nodal_stress_value(const ShellElements& elements, const StressLayout& layout, std::size_t field, int node,
                          const std::vector<NodePose>& X_WN);

/// von Mises stress of a station [s11, s22, s12, s13, s23], (L11).
double von_mises(const Vec5& s);
/// In-plane principal stresses (larger first) of a station.
std::array<double, 2> principal_stresses(const Vec5& s);

}  // namespace ff::shell
