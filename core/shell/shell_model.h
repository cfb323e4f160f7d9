#pragma once
/// \file shell_model.h
/// Assembly of CB shell elements into a static problem (shell_model.md). Node DoFs seen by the
/// solver: translations as global increments (x <- x + dx), rotations as global increments for
/// 6-DoF nodes (R <- exp(dphi~) R) and as the two local bending increments for 5-DoF nodes
/// (R <- R exp([t1 t2 0]~)). Global restraints on translations and on 6-DoF rotations are therefore
/// exact; a 5-DoF node on a symmetry plane gets e1 = plane normal so "rotate only about the
/// normal" is the exact local restraint t2 = 0.

#include <Eigen/Sparse>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/mesh/shell_mesh.h"
#include "core/model/simulation.h"
#include "core/shell/cb_shell.h"
#include "core/solve/static_problem.h"

namespace ff::shell {

/// Restrained global DoFs of a node (bit mask).
enum Restraint : unsigned { kUx = 1, kUy = 2, kUz = 4, kRx = 8, kRy = 16, kRz = 32, kAllTranslations = 7,
                            kAllRotations = 56, kClamped = 63 };

struct NodalLoad {
  int node = -1;
  Vec3 force = Vec3::Zero();   ///< global components at lambda = 1 (follower: node-frame components)
  Vec3 moment = Vec3::Zero();  ///< global components at lambda = 1 (follower: node-frame components)
  bool follower = false;
};

/// Uniform pressure on one quad of the mesh, p times the mid-surface area element
/// g_xi x g_eta (shell_model.md eq. P1): positive along the quad's normal, i.e. towards the
/// director's side of a counter-clockwise quad (core/mesh/README.md convention 1).
struct PressureLoad {
  int quad = -1;
  double pressure = 0.0;  ///< force per unit area at lambda = 1
  /// false: dead load, normal and area of the reference configuration; true: normal and area of
  /// the current configuration (load stiffness in the tangent, non-symmetric in general)
  bool follower = false;
};

struct ShellModelSpec {
  mesh::ShellMesh mesh;
  ShellSection section;
  ShellOptions options;
  std::vector<std::pair<int, unsigned>> restraints;  ///< node, Restraint mask (global directions)
  std::vector<std::pair<int, int>> symmetry;         ///< node, axis (0, 1, 2) of the plane normal
  std::vector<NodalLoad> loads;
  std::vector<PressureLoad> pressures;
};

class ShellModel final : public ff::StaticProblem {
 public:
  /// Throws std::invalid_argument with a plain explanation for restraints that cannot be exact.
  explicit ShellModel(ShellModelSpec spec);

  int size() const override { return static_cast<int>(free_.size()); }
  void evaluate(double lambda, Eigen::VectorXd& residual, Eigen::SparseMatrix<double>* tangent,
                Eigen::VectorXd* load) override;
  void update(const Eigen::VectorXd& delta) override;
  void save_state() override { saved_ = poses_; }
  void restore_state() override { poses_ = saved_; }
  double dof_scale(int i) const override { return free_[i].slot >= 3 ? rotation_scale_ : 1.0; }

  const std::vector<NodePose>& poses() const { return poses_; }
  const ShellModelSpec& spec() const { return spec_; }
  int dofs_of_node(int node) const { return six_[node] ? 6 : 5; }
  /// Global displacement of a node from its reference position.
  Vec3 node_displacement(int node) const { return poses_[node].x - spec_.mesh.points[node]; }
  /// Display strain per node (cb_shell.md eq. S3, averaged over the adjacent elements).
  std::vector<double> nodal_surface_strain() const;
  /// Equation index of (node, slot) or -1 when restrained; slots 0-2 translations, 3-5 rotations.
  int equation(int node, int slot) const { return eq_[6 * node + slot]; }
  /// What evaluate() ran so far, only effects that ran: "elastic" (element evaluations; seconds of
  /// the element loop, scatter and rotating-basis terms, timed once per assembly), "hr", "ans",
  /// "drilling" (element evaluations in which the term was on; timed inside "elastic"),
  /// "point_loads" (nodal loads applied), "pressure_dead", "pressure_follower" (loaded quads).
  /// There is no inertia: a static model has no mass matrix.
  std::vector<EffectStat> effect_stats() const;

 private:
  struct Dof {
    int node, slot;
  };
  struct Element {
    std::array<int, 4> nodes;
    std::array<Mat3, 4> corner;  // C = R0_I^T R0_corner (identity unless the corner's director differs)
    std::unique_ptr<CbShellElement> el;
  };
  ShellModelSpec spec_;
  std::vector<NodePose> poses_, saved_;
  std::vector<NodePose> reference_;     // initial node poses (display strain)
  std::vector<std::uint8_t> six_;       // node has 6 DoFs
  std::vector<int> eq_;                 // 6 per node, -1 restrained/absent
  std::vector<Dof> free_;
  std::vector<Element> elements_;
  double rotation_scale_ = 1.0;
  // tangent pattern built once; per element the value index of each (corner dof, corner dof)
  // entry (-1 when restrained), so assembly is a scatter-add without triplets
  Eigen::SparseMatrix<double> pattern_;
  std::vector<std::array<int, 576>> scatter_;
  std::vector<std::array<Vec3, 4>> dead_pressure_;  // per spec_.pressures: fixed nodal forces (reference)
  std::vector<Vec24> el_force_;   // per-element results of the parallel element loop
  std::vector<Mat24> el_tangent_;
  struct Counter {
    long long evaluations = 0;
    double seconds = 0.0;
  };
  Counter elastic_, point_loads_, dead_pressure_stat_, follower_pressure_stat_;
  long long dead_pressures_ = 0, follower_pressures_ = 0;  // loaded quads of each kind
  long long assemblies_ = 0;  // hr / ans / drilling ran in every element of every assembly
  void build_pattern();
  int value_index(int row, int col) const;
};

}  // namespace ff::shell
