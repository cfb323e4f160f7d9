#pragma once
/// \file dynamic_problem.h
/// What the Lie-group generalized-α integrator (generalized_alpha.h) needs from a model: a
/// configuration on a Lie group moved by local increments, velocities in the Lie algebra (plain
/// vectors of the same size), the residual of the equations of motion with Lagrange multipliers
/// and the holonomic constraints Φ(q) = 0 (index 3). Derivation: core/solve/generalized_alpha.md.

#include <Eigen/Core>
#include <vector>

#include "core/solve/sparse_solver.h"

namespace ff {

/// Weights of the iteration matrix S = mass·M + damping·C + stiffness·K (generalized_alpha.md (G6)).
struct IterationWeights {
  double mass = 1.0;
  double damping = 0.0;
  double stiffness = 1.0;
};

class DynamicProblem {
 public:
  virtual ~DynamicProblem() = default;
  virtual int size() const = 0;              ///< n: velocity unknowns (local increments)
  virtual int constraint_count() const = 0;  ///< m: rows of Φ
  /// q ← q_n ∘ exp(step), step = n local increments (the configuration at the end of a step).
  virtual void configure(const Eigen::VectorXd& step) = 0;
  virtual void commit() = 0;    ///< q_n ← q (the step is accepted)
  virtual void rollback() = 0;  ///< q ← q_n
  /// Residual r = F_inertia(q, v, v̇) + F_int(q) − F_ext(q, t) + Gᵀλ (size n) and Φ(q) (size m).
  /// With `w` non-null also S (n × n, the same sparsity pattern on every call) and B = ∂Φ/∂q
  /// (m × n, constant pattern), with respect to the configured step (generalized_alpha.md (G9)).
  virtual void evaluate(double t, const Eigen::VectorXd& v, const Eigen::VectorXd& vdot, const Eigen::VectorXd& lambda,
                        Eigen::VectorXd& r, Eigen::VectorXd& phi, const IterationWeights* w, SparseMatrixD* S,
                        SparseMatrixD* B) = 0;
  /// ∂r/∂λ = Gᵀ when it differs from B: G holds the constraint-force directions in local
  /// increments at q, while B = ∂Φ/∂x is taken with respect to the step x, so on a Lie group
  /// B = G T(x) (generalized_alpha.md (G9)). Null when G = B. Valid after an evaluate() that
  /// returned B; same sparsity pattern as B.
  virtual const SparseMatrixD* constraint_force_directions() const { return nullptr; }
  /// Over the ranks sharing the solvers (core/solve/distributed.md §5): `on` asks the problem to
  /// assemble S in parts from now on (each rank its own terms, the entries several ranks add summed
  /// over just those) and returns the positions of S's value array this rank then holds in full;
  /// the values elsewhere are partial. r, Φ and B stay whole on every rank. `off` returns to the
  /// whole S (and nullptr); nullptr also when the problem always assembles all of S (the default).
  virtual const std::vector<int>* assemble_matrix_in_parts(bool on) { return nullptr; }
};

}  // namespace ff
