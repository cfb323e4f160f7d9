#pragma once
/// \file error_indicator.h
/// Where the mesh is too coarse: a recovered-resultant (Zienkiewicz-Zhu, superconvergent patch
/// recovery) estimate of the energy-norm error per CB shell element (error_indicator.md). The
/// element's resultants at its 2 x 2 points are compared with a smoothed field fitted over the
/// patches of elements around its corners; the difference, measured in the section's compliance,
/// is the element's error. Not used by the solver: a field for frames and a number for the summary.

#include <vector>

#include "core/model/simulation.h"
#include "core/shell/shell_elements.h"

namespace ff::shell {

struct RecoveredErrorIndicator {
  std::vector<double> element_error2;   ///< eta_e^2 per element, (Z7)
  std::vector<double> element_energy2;  ///< ||r_h||_e^2 per element (twice its resultant energy), (Z7)
  std::vector<double> element;          ///< the indicator i_e per element, (Z9): its RMS is `relative`
  std::vector<double> nodal;            ///< per node: the mean i_e of the elements on it (0 off the shells)
  double error2 = 0.0;                  ///< sum of eta_e^2
  double energy2 = 0.0;                 ///< sum of ||r_h||_e^2
  double relative = 0.0;                ///< (Z8): the global relative energy-norm error
  int worst = -1;                       ///< the element with the largest eta_e (-1: no elements)
};

/// The indicator of `elements` at node poses `current`, their reference poses `reference` (node
/// count = reference.size()). Rigid motions of `current` leave it unchanged: the resultants are
/// material (second Piola-Kirchhoff) and the recovery works on the reference geometry.
RecoveredErrorIndicator recovered_error_indicator(const ShellElements& elements, const std::vector<NodePose>& reference,
                                                  const std::vector<NodePose>& current);

/// What a run reports of `indicator` (core/model/simulation.h FieldErrorEstimate).
FieldErrorEstimate summarize(const RecoveredErrorIndicator& indicator, const ShellElements& elements,
                             const std::vector<NodePose>& reference);

/// The field's name on frames and in results.h5, and its one-line description.
inline constexpr const char* kErrorIndicatorField = "error_indicator";
inline constexpr const char* kErrorIndicatorDescription =
    "recovered-stress error indicator: the element's energy-norm error over the RMS element's, whose RMS is the "
    "global relative error (error_indicator.md Z9); refine where it is large";

/// The patches are split at folds: elements on a node join its patch only when their normals are
/// within this angle of the element being recovered (error_indicator.md (Z5)).
inline constexpr double kRecoveryFoldAngleDeg = 30.0;

}  // namespace ff::shell
