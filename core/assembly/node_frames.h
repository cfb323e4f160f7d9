#pragma once
/// \file node_frames.h
/// Node frames at fold corners (core/mesh/shell_mesh.h): a quad whose corner director differs
/// from its node's uses the node frame turned onto its own director. C = R0_Iᵀ R0_corner maps the
/// corner's local 6-vectors to the node's (blockdiag(C, C)) and back (its transpose).
#include <Eigen/Dense>

namespace ff::assembly {

/// The rotation taking unit a to unit b about their common normal (identity when parallel).
Eigen::Matrix3d align(const Eigen::Vector3d& a, const Eigen::Vector3d& b);
struct CornerFrame {
  Eigen::Matrix3d frame;  ///< R0_corner = align(R0 e3, corner director) R0, world components
  Eigen::Matrix3d turn;   ///< C = R0ᵀ R0_corner (≈ identity, not exactly, at a plain corner)
};
/// The frame a quad uses at its corner on node frame R0 with the given (unit or not) director.
CornerFrame corner_frame(const Eigen::Matrix3d& node_frame, const Eigen::Vector3d& corner_director);

}  // namespace ff::assembly
