#pragma once
/// \file multibody_model.h
/// Flexible multibody system on SE(3) local frames (cb_shell_dynamics.md): CB shell bodies
/// (elastic + inertia + optional gravity), rigid bodies, and joints as holonomic constraints with
/// Lagrange multipliers. Every node's unknowns are local increments: [δu; δθ] (6) or
/// [δu; δθ1; δθ2] (5-DoF shell nodes without drilling). Implements ff::DynamicProblem for the
/// Lie-group generalized-α integrator.

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/assembly/block_pattern.h"
#include "core/assembly/dof_map.h"
#include "core/assembly/effect_counter.h"
#include "core/assembly/element_threads.h"
#include "core/lie/se3.h"
#include "core/mesh/shell_mesh.h"
#include "core/model/simulation.h"
#include "core/shell/cb_shell.h"
#include "core/shell/cb_shell_inertia.h"
#include "core/shell/shell_elements.h"
#include "core/shell/error_indicator.h"
#include "core/shell/shell_stress.h"
#include "core/shell/loads.h"
#include "core/solve/dynamic_problem.h"
#include "core/solve/tangent_parts.h"

namespace ff::shell {

struct ShellBodySpec {
  std::string name;
  mesh::ShellMesh mesh;
  ShellSection section;
  ShellOptions options;
  double density = 1.0;
  /// A body joined from parts of several materials (a scene's [[junction]]): quad q has
  /// sections[quad_material[q]], densities[..] and drilling_factors[..]; empty: every quad has
  /// section, density and options.drilling_factor.
  std::vector<int> quad_material;
  std::vector<ShellSection> sections;
  std::vector<double> densities, drilling_factors;
  /// Per quad of `mesh`: the world direction its fibre angles (and stress axes) are measured from
  /// (ShellSection::reference_direction, laminate.md section 2); empty: zero vectors, each
  /// element's own xi direction.
  std::vector<Vec3> quad_reference_direction;
};

struct RigidBodySpec {
  std::string name;
  NodePose pose;                      ///< X_WB: centre of mass and body axes in W
  double mass = 1.0;
  Mat3 inertia = Mat3::Identity();    ///< about the centre of mass, body axes
};

/// Points carried by the nodes coincide: p_WA + R_WA o_a = p_WB + R_WB o_b (b >= 0) or
/// p_WA + R_WA o_a = target (b < 0), A and B the frames of nodes a and b, as rows in A: (D11'), (D12').
/// A ground point at node a's own reference position with no offset is a pin instead: the model drops
/// a's translations from the unknowns and the constraint from spec().positions. Offsets o are in the
/// node frames (zero for shell nodes; a rigid body's joint point relative to its centre of mass).
/// Node ids are model-wide.
struct PositionConstraint {
  int a = -1, b = -1;
  Vec3 target = Vec3::Zero();
  Vec3 a_offset = Vec3::Zero(), b_offset = Vec3::Zero();
};
/// (R_WA â)·(R_WB p̂) = 0, or (R_WA â)·p_W = 0 with a fixed global p_W when b < 0: (D13).
struct PerpendicularConstraint {
  int a = -1, b = -1;
  Vec3 a_local = Vec3::UnitX(), b_vector = Vec3::UnitY();
};

/// A force and a moment at one node (model-wide id; a rigid body's node is its centre of mass),
/// dead (world components) or follower (node-frame components), times history.factor(t)
/// (cb_shell_dynamics.md §8, (D16)-(D19)). At a 5-DoF node the moment's component along the
/// director does no work (that spin is not a rotation of the shell) and is dropped.
struct TimedNodalLoad {
  NodalLoad load;
  LoadHistory history;
};
/// A pressure on quad load.quad of shell body `body` (its index in MultibodySpec::shells), times
/// history.factor(t). Dead only: fixed nodal forces from the reference geometry (D20); a follower
/// pressure is refused.
struct TimedPressure {
  int body = 0;
  PressureLoad load;
  LoadHistory history;
};

/// A support of a shell node (a scene's [[bc]] in dynamics): its translations, its rotations or
/// both held at their reference values, exactly, by leaving them out of the unknowns.
struct NodeSupport {
  int node = -1;
  bool translations = false, rotations = false;
};

struct MultibodySpec {
  std::vector<ShellBodySpec> shells;
  std::vector<RigidBodySpec> rigid;
  std::vector<PositionConstraint> positions;
  std::vector<PerpendicularConstraint> perpendiculars;
  bool gravity = false;
  Vec3 g = Vec3(0, 0, -9.81);
  std::vector<TimedNodalLoad> loads;
  std::vector<TimedPressure> pressures;
  std::vector<NodeSupport> supports;
};

/// Energies and momenta of a state (D15).
struct MotionSummary {
  double kinetic = 0.0, strain = 0.0, gravity_potential = 0.0;
  /// −Σ f(t) F̄·(x − x0) of the dead forces (nodal and pressure) at the summary's time (D21); dead
  /// moments and follower loads have no potential and are not in it
  double load_potential = 0.0;
  Vec3 linear_momentum = Vec3::Zero(), angular_momentum = Vec3::Zero();
  double total() const { return kinetic + strain + gravity_potential + load_potential; }
};

/// A time at which a load's history jumps (a step's start, a pulse's end: jump) or only bends (a
/// ramp's start and end).
struct LoadSwitch {
  double time = 0.0;
  bool jump = false;
};

/// What the MultibodyModel constructor refuses about one body, with the body's index in
/// MultibodySpec::shells (or ::rigid), so a scene can point at that body's own key.
class BodySpecError : public std::invalid_argument {
 public:
  enum class Part { shell_element, shell_density, rigid_mass, rigid_inertia };
  BodySpecError(Part part, int body, const std::string& what, int quad = -1)
      : std::invalid_argument(what), part_(part), body_(body), quad_(quad) {}
  Part part() const { return part_; }
  int body() const { return body_; }
  int quad() const { return quad_; }  ///< shell_element, shell_density: the body's quad at fault, or -1

 private:
  Part part_;
  int body_;
  int quad_;
};

/// What the MultibodyModel constructor refuses about one load, with its index in
/// MultibodySpec::loads (nodal_load) or ::pressures (pressure), so a scene can point at its entry.
class LoadSpecError : public std::invalid_argument {
 public:
  enum class Part { nodal_load, pressure };
  LoadSpecError(Part part, int index, const std::string& what) : std::invalid_argument(what), part_(part), index_(index) {}
  Part part() const { return part_; }
  int index() const { return index_; }

 private:
  Part part_;
  int index_;
};

/// What changes while a MultibodyModel is solved; the model object itself is the constant
/// structure (bodies, elements, constraints, DoFs, sparsity). A committed step is a copy of it, and
/// a rejected attempt goes back to that copy.
struct MultibodyState {
  std::vector<NodePose> poses;  ///< X_WN of every node: the configuration
  std::vector<Vec6> node_step;  ///< the configured step of each node from the committed poses (G3)
  bool step_is_zero = true;     ///< poses are the committed ones: every T_SE3 is the identity
};

class MultibodyModel final : public ff::DynamicProblem {
 public:
  /// Throws std::invalid_argument with a plain explanation for specs that cannot be simulated
  /// (BodySpecError when one body is at fault, LoadSpecError when one load is).
  explicit MultibodyModel(MultibodySpec spec);
  ~MultibodyModel() override;

  int size() const override { return dofs_.size(); }
  int constraint_count() const override { return constraint_rows_; }
  /// Also keeps each node's step for the exact iteration matrix (generalized_alpha.md (G8)).
  void configure(const Eigen::VectorXd& step) override;
  void commit() override {
    state_.step_is_zero = true;
    committed_ = state_;
  }
  void rollback() override { state_ = committed_; }
  const MultibodyState& state() const { return state_; }
  /// true (default): S and B are the exact derivatives with respect to the step (position terms
  /// times T_SE3(step), (G8)-(G9)); false: the shell paper's matrix without T (Newton then
  /// converges linearly). For comparisons and tests.
  void set_exact_iteration_matrix(bool exact) { exact_matrix_ = exact; }
  const SparseMatrixD* constraint_force_directions() const override { return b_has_T_ ? &force_directions_ : nullptr; }
  void evaluate(double t, const Eigen::VectorXd& v, const Eigen::VectorXd& vdot, const Eigen::VectorXd& lambda,
                Eigen::VectorXd& r, Eigen::VectorXd& phi, const IterationWeights* w, SparseMatrixD* S,
                SparseMatrixD* B) override;
  /// Each rank adds its elements' entries and the node-level terms of the nodes it owns; the
  /// joints' couplings between two nodes are rank 0's (core/solve/distributed.md §5).
  const std::vector<int>* assemble_matrix_in_parts(bool on) override;

  int node_count() const { return static_cast<int>(state_.poses.size()); }
  /// First model-wide node id of shell body `b` (its nodes are consecutive), rigid body node ids.
  int shell_node_offset(int b) const { return shell_offset_[b]; }
  int rigid_node(int r) const { return rigid_offset_ + r; }
  const std::vector<NodePose>& poses() const { return state_.poses; }
  const NodePose& reference_pose(int node) const { return reference_[node]; }
  int dofs_of_node(int node) const { return six_dof_[node] ? 6 : 5; }
  int equation(int node, int slot) const { return dofs_.equation(node, slot); }  ///< -1 when absent
  /// Local 6-vector of node `node` from a solver vector (zero in the absent drilling slot).
  Vec6 node_vector(const Eigen::VectorXd& x, int node) const;
  Vec3 node_displacement(int node) const { return state_.poses[node].p - reference_[node].p; }
  /// Energies and momenta with velocities v; the load potential at time t (D21).
  MotionSummary summary(const Eigen::VectorXd& v, double t = 0.0) const;
  /// The times of MultibodySpec::loads' and ::pressures' histories where the load jumps or bends,
  /// ascending, each once (a jump wins over a bend at the same time): a simulation lands a step on
  /// each and restarts its integrator after a jump.
  std::vector<LoadSwitch> load_switches() const;
  /// Largest |Φ_i| of the current configuration (length units for positions, cosines for axes).
  double constraint_violation() const;
  const MultibodySpec& spec() const { return spec_; }
  /// The shell elements of every body, bodies in order, each in its mesh's quad order.
  const ShellElements& elements() const { return elements_; }
  /// Gravity g [m/s^2] from now on (a scene's [[timeline]] gravity); used only when spec().gravity.
  void set_gravity(const Vec3& g) { spec_.g = g; }
  double total_mass() const;
  /// Display strain per node (cb_shell.md eq. V3, averaged over the adjacent elements); 0 at
  /// rigid-body nodes.
  std::vector<double> nodal_surface_strain() const;
  /// What the elements can report (shell_stress.h): the ply fields up to the most plies of a
  /// section, the failure index when a ply has strengths.
  StressLayout stress_layout() const { return shell::stress_layout(elements_); }
  /// Every field of stress_fields(stress_layout()) per node (0 at rigid-body nodes): each element's value at its
  /// centre, averaged over the elements around the node (shell_stress.h).
  std::vector<std::vector<double>> nodal_stress_fields() const {
    return shell::nodal_stress_fields(elements_, stress_layout(), state_.poses);
  }
  /// The recovered-resultant error indicator at the current state (error_indicator.h).
  RecoveredErrorIndicator error_indicator() const {
    return recovered_error_indicator(elements_, reference_, state_.poses);
  }
  /// Where that indicator's error is, for the run's summary.
  FieldErrorEstimate field_error_estimate() const { return summarize(error_indicator(), elements_, reference_); }
  /// Field number `field` of stress_fields(stress_layout()) at one node, equal to
  /// nodal_stress_fields()[field][node], from the elements around the node only (a probe).
  double nodal_stress(int node, std::size_t field) const {
    return shell::nodal_stress_value(elements_, stress_layout(), field, node, state_.poses);
  }
  /// Effects that ran with their counters: "elastic", "inertia", "gravity" (element evaluations),
  /// "hr", "ans", "drilling" (element evaluations with the term on, timed inside "elastic" as in
  /// ShellModel), "rigid_body", "joints" (assemblies), "point_loads" (nodal loads evaluated),
  /// "pressure_dead" (loaded quads evaluated), as in ShellModel.
  std::vector<EffectStat> effect_stats() const;
  /// Threads of the element loop from now on (the Simulation passes what the program was given).
  void set_threads(const assembly::ElementThreads& threads) { threads_ = threads; }

 private:
  void build_pattern();
  void check_loads();
  /// r -= f(t) F_ext and its position derivative, (D16)-(D20)
  template <class AddPositionBlock>
  void add_external_loads(double t, Eigen::VectorXd& r, const IterationWeights* w, AddPositionBlock&& add_position_block);
  // one assembly's inputs and outputs, handed to each term of evaluate()
  struct Assembly {
    double t;
    const Eigen::VectorXd& v;
    const Eigen::VectorXd& vdot;
    const Eigen::VectorXd& lambda;
    Eigen::VectorXd& r;
    Eigen::VectorXd& phi;
    const IterationWeights* w;
    SparseMatrixD* S;
    SparseMatrixD* B;
    double* values;  // S's values (null without S)
    bool tangent;    // S wanted
    bool with_T;     // position columns times T_SE3(step) (G9)
  };
  void shell_element_term(Assembly& as);
  void rigid_body_term(Assembly& as);
  void joint_term(Assembly& as);
  void add(Assembly& as, int I, int si, int J, int sj, double x) const;
  void add_block(Assembly& as, int I, int oi, int J, int oj, const Mat3& blk) const;
  void add_position_block(Assembly& as, int I, int oi, int J, int oj, const Mat3& blk) const;

  MultibodySpec spec_;
  std::vector<NodePose> reference_;
  MultibodyState state_, committed_;  // the changing part; work buffers below, the rest is constant
  std::vector<ff::lie::Mat6> step_tangent_;  // work: T_SE3(step_I), per node, when a matrix is evaluated (G8)
  bool exact_matrix_ = true;
  SparseMatrixD force_directions_;  // constraint-force directions G (local increments): B = G T (G9)
  bool b_has_T_ = false;  // the last B returned differs from G (force_directions_)
  std::vector<int> pinned_;  // nodes held in space by ground points: translations not unknowns (supports: not listed, no effect to count)
  std::vector<std::uint8_t> six_dof_;  // per node: 1 when it has the drilling rotation
  assembly::DofMap dofs_;
  std::vector<int> shell_offset_;
  int rigid_offset_ = 0;
  int constraint_rows_ = 0;  // m: rows of Φ
  assembly::ElementThreads threads_;
  ShellElements elements_;  // the constant elements; results_ are their work buffers
  assembly::BlockPattern pattern_;
  SparseMatrixD b_pattern_;
  std::vector<std::array<int, 576>> scatter_;
  struct ElementResult {
    Vec24 r;
    Mat24 S;
  };
  std::vector<ElementResult> results_;  // work: the element loop's output
  std::vector<std::array<double, 2>> timed_seconds_;  // work:  // elastic, inertia [s] of every 8th element (effect_stats)
  std::vector<std::array<Vec3, 4>> dead_pressure_;  // per spec_.pressures: nodal forces, world, at f = 1 (D20)
  std::vector<std::array<int, 4>> pressure_nodes_;   // per spec_.pressures: model-wide corner node ids
  assembly::EffectCounter elastic_, inertia_, gravity_, joints_, rigid_, point_loads_, dead_pressure_stat_;
  long long assemblies_ = 0;
  ElementShare element_share_;  // the elements this rank evaluates (element_share())
  const ElementShare& element_share();
  TangentParts matrix_parts_;  // who adds and holds which entries of S over ranks (built when first asked)
  bool in_parts_ = false;      // S is assembled in parts (assemble_matrix_in_parts)
  long long hr_elements_ = 0, ans_elements_ = 0, drilling_elements_ = 0;  // elements with the term on
};

}  // namespace ff::shell
