#pragma once
/// \file static_problem.h
/// What the nonlinear static solvers (static_newton.h, static_arclength.h) need from a model.
/// Equations and conventions: core/solve/static_solvers.md §1.

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <optional>
#include <vector>

namespace ff {

/// Residual r(q, λ) = f_int(q) − λ f_ref(q) on the n free DoFs, with q on a manifold (node poses
/// in SE(3), rotations, ...). The solvers never see q: they read residuals, tangents and loads at
/// the current state and move the state with update(δ). Increments δ, residuals and tangents are
/// all expressed in the same n tangent coordinates (per node [u(3), θ(3)] in the local frame for
/// shells), so every vector operation a solver does happens in the tangent space of one state.
///
/// Ownership and threading: the solver holds a reference for the duration of one solve() and calls
/// every method from the thread that called solve(). The problem owns its state.
class StaticProblem {
 public:
  virtual ~StaticProblem() = default;

  /// Number of free DoFs n (constant during a solve).
  virtual int size() const = 0;

  /// At the current state and load factor λ:
  ///  - residual  r = f_int(q) − λ f_ref(q), size n (resized by the callee if needed);
  ///  - tangent   K = ∂r/∂q along update(): K δ = d/dε r(q ⊕ εδ, λ)|ε=0, n×n, may be non-symmetric
  ///              (follower loads contribute −λ ∂f_ref/∂q). Only when tangent != nullptr. The solver
  ///              passes the same matrix object on every call, so a problem may keep the sparsity
  ///              pattern and overwrite values; it must be compressed (makeCompressed()) on return.
  ///              A pattern that stays the same keeps the symbolic factorization (sparse_solver.h).
  ///  - load      f_ref(q), size n; ∂r/∂λ = −f_ref. Only when load != nullptr.
  /// Non-finite values are allowed (e.g. an inverted element): the solver treats them as a failed
  /// iteration and cuts the step back.
  virtual void evaluate(double lambda, Eigen::VectorXd& residual, Eigen::SparseMatrix<double>* tangent,
                        Eigen::VectorXd* load) = 0;

  /// q ← q ⊕ δ (e.g. H_I ← H_I exp(Δh_I) per node, core/lie/lie.md). δ has size n.
  virtual void update(const Eigen::VectorXd& delta) = 0;

  /// One saved state: save_state() overwrites it, restore_state() returns to it and may be called
  /// several times after one save (cut-backs, rejected arc-length steps, λ_max landing).
  virtual void save_state() = 0;
  virtual void restore_state() = 0;

  /// Weight s_i that makes DoF i displacement-like in norms and in the arc-length constraint
  /// (e.g. a rotation times a characteristic length). Residual entries are weighted by 1/s_i, so
  /// the pair stays work-conjugate. Default 1.
  virtual double dof_scale(int i) const { return 1.0; }

  /// Displacement of DoF i from the reference configuration, for the arc-length displacement limit
  /// and the step reports. nullopt (default): the solver uses the sum of the increments δ_i it
  /// applied, exact on a vector space and for a rotation about a fixed axis.
  virtual std::optional<double> displacement(int i) const { return std::nullopt; }

  /// True when K − Kᵀ vanishes wherever r = 0, as for conservative loads on a local-frame
  /// parametrization: the solver may then factor the symmetric part ½(K + Kᵀ), which differs from
  /// K by O(||r||), so Newton keeps its quadratic rate (static_solvers.md §7.1). Default false.
  virtual bool tangent_symmetric_at_equilibrium() const { return false; }

  /// Magnitude of the state coordinate behind DoF i (e.g. |x|_inf of a node for a translation,
  /// 1 for a rotation angle): the state is known to about eps × this, so the residual cannot be
  /// computed more accurately than the change such an error makes (the round-off floor of the
  /// convergence test, static_solvers.md eq. 3'). 0 (default): no floor is estimated.
  virtual double state_magnitude(int i) const { return 0.0; }

  /// Over the ranks sharing the solvers (solver_ranks.h; core/solve/distributed.md §5): `on` asks
  /// the problem to assemble its tangent in parts from now on, each rank adding its own terms and
  /// the entries several ranks add summed over just those ranks, and returns the positions of the
  /// tangent's value array this rank then holds in full and alone hands the linear solver
  /// (SparseLinearSolver::hold_positions_over_ranks); the values elsewhere are partial. `off`
  /// returns to the whole tangent on every rank (and nullptr). nullptr also when the problem
  /// always assembles the whole tangent (the default) or runs alone.
  virtual const std::vector<int>* assemble_tangent_in_parts(bool on) { return nullptr; }
};

}  // namespace ff
