#pragma once
/// \file shell_elements.h
/// The CB shell elements of a structure and the one element loop every analysis drives: the
/// static model (shell_model.h) and the dynamic one (multibody_model.h) build their elements here
/// and evaluate them through for_each(), each with its own per-element kernel (elastic only, or
/// elastic, inertia and gravity) and its own conversion to solver rows. The set is the constant
/// part of a model; the per-element results the kernels write are the model's work buffers.

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/assembly/element_threads.h"
#include "core/mesh/shell_mesh.h"
#include "core/shell/cb_shell.h"
#include "core/shell/cb_shell_inertia.h"

namespace ff::shell {

/// One element: its nodes (model-wide ids), the turn of each corner's director frame from its
/// node's frame, its kernels and what it is made of.
struct ShellElement {
  std::array<int, 4> nodes;
  /// C = R0_I^T R0_corner: identity unless the corner's director differs from the node's (a fold)
  std::array<Mat3, 4> corner;
  bool plain = true;  ///< every corner identity: the corner frame is the node frame
  double thickness = 0.0;
  int part = 0;       ///< the body or part it belongs to (error messages)
  std::unique_ptr<CbShellElement> elastic;
  std::unique_ptr<CbShellInertia> inertia;  ///< null when the analysis has no inertia
};

/// Why an element could not be formed: at its quad (of the mesh given to add_mesh) and part;
/// `thickness_at_fault` when it forms with a far thinner section (the thickness does not fit the
/// element's curvature), else its mid-surface carries no shell at any thickness.
class ShellElementError : public std::invalid_argument {
 public:
  ShellElementError(int quad, int part, bool thickness_at_fault, const std::string& what)
      : std::invalid_argument(what), quad_(quad), part_(part), thickness_at_fault_(thickness_at_fault) {}
  int quad() const { return quad_; }
  int part() const { return part_; }
  bool thickness_at_fault() const { return thickness_at_fault_; }

 private:
  int quad_, part_;
  bool thickness_at_fault_;
};

class ShellElements {
 public:
  /// The elements of every quad of `m`, its node i being model node node_offset + i, quad q of
  /// section sections[q], options[q] and density densities[q] (one entry: every quad), with its
  /// inertia where the density is > 0. reference_directions[q] (world; empty: none) becomes quad
  /// q's ShellSection::reference_direction, the direction its fibre angles and stress axes are
  /// measured from (laminate.md section 2). Throws ShellElementError for a quad that cannot be formed.
  void add_mesh(const mesh::ShellMesh& m, int node_offset, const std::vector<ShellSection>& sections,
                const std::vector<ShellOptions>& options, const std::vector<double>& densities, int part,
                const std::vector<Vec3>& reference_directions);

  int size() const { return static_cast<int>(elements_.size()); }
  const ShellElement& operator[](int k) const { return elements_[k]; }
  const std::vector<ShellElement>& all() const { return elements_; }

  /// The corner poses of element e at the node poses X_WN (corner frame R_WN C, node position).
  static void corner_poses(const ShellElement& e, const std::vector<NodePose>& X_WN, ElementPoses& cur) {
    for (int c = 0; c < 4; ++c) {
      const NodePose& X = X_WN[e.nodes[c]];
      cur[c] = {e.plain ? X.R : Mat3(X.R * e.corner[c]), X.p};  // C = I: no product
    }
  }

  /// The element loop of every analysis: kernel(k, element, corner poses) for every element, on
  /// `threads` threads (core/assembly/element_threads.h), each element exactly once and always
  /// on the same split of the range, so results never depend on the thread count. A kernel
  /// writes only element k's own buffers; the caller sums them afterwards in element order.
  template <class Kernel>
  void for_each(const assembly::ElementThreads& threads, const std::vector<NodePose>& X_WN, Kernel&& kernel) const {
    assembly::for_each_chunk(threads, size(), [&](int begin, int end) {
      ElementPoses cur;
      for (int k = begin; k < end; ++k) {
        corner_poses(elements_[k], X_WN, cur);
        kernel(k, elements_[k], cur);
      }
    });
  }
  /// The same for the elements listed only (a rank's share, core/solve/tangent_parts.h ElementShare).
  template <class Kernel>
  void for_each_of(const assembly::ElementThreads& threads, const std::vector<int>& listed,
                   const std::vector<NodePose>& X_WN, Kernel&& kernel) const {
    assembly::for_each_chunk(threads, static_cast<int>(listed.size()), [&](int begin, int end) {
      ElementPoses cur;
      for (int q = begin; q < end; ++q) {
        const int k = listed[q];
        corner_poses(elements_[k], X_WN, cur);
        kernel(k, elements_[k], cur);
      }
    });
  }
  /// The nodes of every element, in element order (for a partition of the mesh).
  std::vector<std::array<int, 4>> connectivity() const {
    std::vector<std::array<int, 4>> out(elements_.size());
    for (std::size_t k = 0; k < elements_.size(); ++k) out[k] = elements_[k].nodes;
    return out;
  }

 private:
  std::vector<ShellElement> elements_;
};

}  // namespace ff::shell
