#pragma once
/// \file node_frames.h
/// Node frames at fold corners (core/mesh/shell_mesh.h): a quad whose corner director differs
/// from its node's uses the node frame turned onto its own director. C = R_N0C = R_WN0ᵀ R_WC (N0: the
/// node's reference frame, C: the corner's) maps the corner's local 6-vectors to the node's
/// (blockdiag(C, C)) and back (its transpose).
#include <Eigen/Dense>

namespace ff::assembly {

/// The rotation taking unit a to unit b about their common normal (identity when parallel).
Eigen::Matrix3d align(const Eigen::Vector3d& a, const Eigen::Vector3d& b);
struct CornerFrame {
  Eigen::Matrix3d frame;  ///< R_WC = align(R_WN0 e3, corner director) R_WN0
  Eigen::Matrix3d turn;   ///< C = R_N0C = R_WN0ᵀ R_WC (≈ identity, not exactly, at a plain corner)
};
/// The frame a quad uses at its corner on node frame R_WN0 with the given (unit or not) director.
CornerFrame corner_frame(const Eigen::Matrix3d& R_WN0, const Eigen::Vector3d& corner_director);

}  // namespace ff::assembly
