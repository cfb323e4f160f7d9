#pragma once
/// \file shell_model.h
/// Assembly of CB shell elements into a static problem (shell_model.md). Node DoFs seen by the
/// solver: translations as increments along a fixed orthonormal basis T_u of the node
/// (x <- x + T_u du), rotations as increments about a fixed basis T_r for 6-DoF nodes
/// (R <- exp((T_r dphi)~) R) and as the two local bending increments for 5-DoF nodes
/// (R <- R exp([t1 t2 0]~)). T_u = T_r = I unless a restraint asks for other directions; a node
/// basis puts every restrained direction on a slot of its own, so restraints in any directions
/// (cylindrical, the node's frame, symmetry planes of any normal) are exact (shell_model.md §R).
/// A 5-DoF node restrained about one tangent direction b gets e1 = d x b (d the director), so
/// "rotate only about e1" is the exact local restraint t2 = 0.

#include <Eigen/Sparse>
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/assembly/block_pattern.h"
#include "core/assembly/dof_map.h"
#include "core/assembly/effect_counter.h"
#include "core/assembly/element_threads.h"
#include "core/mesh/shell_mesh.h"
#include "core/model/simulation.h"
#include "core/shell/cb_shell.h"
#include "core/shell/shell_elements.h"
#include "core/shell/error_indicator.h"
#include "core/shell/shell_stress.h"
#include "core/shell/loads.h"
#include "core/solve/static_problem.h"
#include "core/solve/tangent_parts.h"

namespace ff::shell {

/// Restrained global DoFs of a node (bit mask).
enum Restraint : unsigned { kUx = 1, kUy = 2, kUz = 4, kRx = 8, kRy = 16, kRz = 32, kAllTranslations = 7,
                            kAllRotations = 56, kClamped = 63 };

/// Consistent nodal forces of a dead traction t per unit area of the bilinear quad x[0..3] in its
/// reference position (shell_model.md eq. P5), 2 x 2 Gauss points.
std::array<Vec3, 4> surface_traction_forces(const std::array<Vec3, 4>& x, const Vec3& t);
/// Consistent nodal forces of a dead pressure p on the bilinear quad x[0..3] in its reference
/// position, p (g_xi x g_eta) (shell_model.md eq. P2), 2 x 2 Gauss points: what a dead
/// PressureLoad applies in the static and the dynamic model alike.
std::array<Vec3, 4> dead_pressure_forces(const std::array<Vec3, 4>& x, double p);

/// One restrained direction of a node (shell_model.md eq. R1): the component of the node's
/// translation (or, with rotation = true, of its rotation increments) along `direction` is held
/// at zero, or for a translation at lambda * value (a prescribed displacement, eq. R4).
struct DirectionRestraint {
  int node = -1;
  Vec3 direction = Vec3::UnitZ();  ///< world components; normalized by the model
  bool rotation = false;
  double value = 0.0;              ///< prescribed displacement along direction at lambda = 1
  int source = -1;                 ///< index of the scene entry it came from (error messages)
};

/// A node on a symmetry plane (eq. R3): no translation along the normal, rotation only about it.
struct SymmetryPlane {
  int node = -1;
  Vec3 normal = Vec3::UnitX();  ///< world components; normalized by the model
  int source = -1;
};

struct ShellModelSpec {
  mesh::ShellMesh mesh;
  ShellSection section;
  ShellOptions options;
  /// Parts of other materials: quad q has sections[quad_section[q]] and its drilling factor
  /// drilling_factors[quad_section[q]]; empty quad_section: every quad has `section` and options.
  std::vector<ShellSection> sections;
  std::vector<double> drilling_factors;
  std::vector<int> quad_section;
  /// Per quad of `mesh`: the world direction its fibre angles (and stress axes) are measured from
  /// (ShellSection::reference_direction, laminate.md section 2); empty: zero vectors, each
  /// element's own xi direction.
  std::vector<Vec3> quad_reference_direction;
  std::vector<std::pair<int, unsigned>> restraints;  ///< node, Restraint mask (global directions)
  std::vector<std::pair<int, int>> symmetry;         ///< node, axis (0, 1, 2) of the plane normal
  std::vector<DirectionRestraint> directions;        ///< restraints in any direction, prescribed values
  std::vector<SymmetryPlane> symmetry_planes;        ///< symmetry planes of any normal
  std::vector<NodalLoad> loads;
  std::vector<PressureLoad> pressures;
};

/// What the ShellModel constructor refuses, with the part of the spec it comes from, so a scene
/// can point at its own entry (`source` of the restraint or plane; the quad for an element).
class ShellSpecError : public std::invalid_argument {
 public:
  /// element: the section's thickness does not fit the element's curvature (it forms at a
  /// thinner section); mid_surface: the quad and its directors carry no shell at any thickness
  enum class Part { restraint, symmetry, pressure, element, mid_surface };
  ShellSpecError(Part part, int source, const std::string& what)
      : std::invalid_argument(what), part_(part), source_(source) {}
  Part part() const { return part_; }
  int source() const { return source_; }

 private:
  Part part_;
  int source_;
};

/// Peak resident memory [bytes] of a shell run on `nodes` nodes, `six_dof_fraction` of them with
/// 6 DoFs, estimated before anything is built so that `check` can refuse a mesh that cannot fit.
/// Fitted to measured peaks (shell_model.cpp, where the measurements are); about 20 % either way.
double estimated_peak_bytes(int nodes, double six_dof_fraction);

/// What changes while a ShellModel is solved; the model object itself is the constant structure
/// (spec, elements, node bases, DoFs, sparsity). A saved attempt is a copy of this state.
struct ShellState {
  std::vector<NodePose> poses;  ///< X_WN of every node: the configuration
};

/// The buffers one assembly fills and the next overwrites: no attempt needs them back.
struct ShellWorkspace {
  std::vector<Vec24> element_force;    ///< per element, corner-local (the parallel loop's output)
  std::vector<Mat24> element_tangent;  ///< per element, in solver rows
  std::vector<Vec6> node_force;        ///< per node, node-local internal force
  std::vector<Vec3> reaction;          ///< per node, world components (last evaluate)
};

class ShellModel final : public ff::StaticProblem {
 public:
  /// Throws std::invalid_argument with a plain explanation for restraints that cannot be exact.
  explicit ShellModel(ShellModelSpec spec);

  int size() const override { return dofs_.size(); }
  void evaluate(double lambda, Eigen::VectorXd& residual, Eigen::SparseMatrix<double>* tangent,
                Eigen::VectorXd* load) override;
  void update(const Eigen::VectorXd& delta) override;
  void save_state() override { saved_ = state_; }
  void restore_state() override { state_ = saved_; }
  /// The configuration, and setting it (the same nodes; a state of another analysis of the same
  /// structure, or one saved earlier).
  const ShellState& state() const { return state_; }
  void set_state(const ShellState& state);
  double dof_scale(int i) const override { return dofs_.unknown(i).slot >= 3 ? rotation_scale_ : 1.0; }
  /// Dead forces and pressures and prescribed displacements are conservative; follower loads and
  /// moments (not conservative on finite rotations) are not (tests/unit/test_tangent_symmetry.cpp).
  bool tangent_symmetric_at_equilibrium() const override;
  /// Over ranks: each rank adds its elements' and owned nodes' terms and only the interface
  /// entries are summed over the ranks (core/solve/distributed.md §5); whole again with `false`.
  const std::vector<int>* assemble_tangent_in_parts(bool on) override;

  const std::vector<NodePose>& poses() const { return state_.poses; }
  const ShellModelSpec& spec() const { return spec_; }
  /// The elements, in quad order of spec().mesh (their sections, as built).
  const ShellElements& elements() const { return elements_; }
  int dofs_of_node(int node) const { return six_dof_[node] ? 6 : 5; }
  /// Global displacement of a node from its reference position.
  Vec3 node_displacement(int node) const { return state_.poses[node].p - spec_.mesh.points[node]; }
  /// Reaction at a node at the last evaluate(): f_int - lambda f_ext on its translations, world
  /// components (zero up to the residual at a free node in equilibrium; the support force where
  /// translations are restrained or prescribed).
  Vec3 node_reaction(int node) const { return work_.reaction[node]; }
  /// Moves the prescribed translations to lambda * value (eq. R4); evaluate() does it itself.
  void apply_prescribed(double lambda);
  /// Coordinate magnitude behind DoF i (static_problem.h): |x_I|_inf for a translation, 1 for a
  /// rotation.
  double state_magnitude(int i) const override;
  /// Nodes whose director was moved into a symmetry plane it missed by less than
  /// kSymmetryDirectorSnap, and the largest such angle [rad].
  int snapped_directors() const { return snapped_directors_; }
  double largest_director_snap() const { return largest_snap_; }
  /// A director within this angle [rad] of a symmetry plane is moved into it (eq. R3');
  /// beyond it the plane is refused for a 5-DoF node.
  static constexpr double kSymmetryDirectorSnap = 1e-3;
  /// Display strain per node (cb_shell.md eq. V3, averaged over the adjacent elements).
  std::vector<double> nodal_surface_strain() const;
  /// What the elements can report (shell_stress.h): the ply fields up to the most plies of a
  /// section, the failure index when a ply has strengths.
  StressLayout stress_layout() const { return shell::stress_layout(elements_); }
  /// Every field of stress_fields(stress_layout()) per node: each element's value at its
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
  /// Equation index of (node, slot) or -1 when restrained; slots 0-2 translations along the
  /// columns of translation_basis(node), 3-5 rotations (about rotation_basis(node) for 6-DoF nodes,
  /// about the node's own e1, e2 for 5-DoF nodes).
  int equation(int node, int slot) const { return dofs_.equation(node, slot); }
  const Mat3& translation_basis(int node) const { return basis_u_[node]; }
  const Mat3& rotation_basis(int node) const { return basis_r_[node]; }
  /// What evaluate() ran so far, only effects that ran: "elastic" (element evaluations; seconds of
  /// the element loop, scatter and rotating-basis terms, timed once per assembly), "hr", "ans",
  /// "drilling" (element evaluations in which the term was on; timed inside "elastic"),
  /// "point_loads" (nodal loads applied), "pressure_dead", "pressure_follower" (loaded quads).
  /// There is no inertia: a static model has no mass matrix.
  std::vector<EffectStat> effect_stats() const;
  /// Threads of the element loop from now on (the Simulation passes what the program was given).
  void set_threads(const assembly::ElementThreads& threads) { threads_ = threads; }
  /// A matrix of the structure from one 24 x 24 matrix per element in the element's own local
  /// increments (cb_shell.h: per corner [δu; δθ] in the corner frame), written by
  /// `element_matrix(k, corner poses)` at the current state and turned into the solver's rows
  /// exactly as the elastic tangent is (its corner-to-node and node-basis turns; restrained slots
  /// dropped): `out` gets the tangent's sparsity pattern. The mass matrix of a modal analysis
  /// (shell_eigen.md (E1)).
  void assemble_element_matrices(const std::function<void(int, const ElementPoses&, Mat24&)>& element_matrix,
                                 Eigen::SparseMatrix<double>& out) const;

 private:
  ShellModelSpec spec_;
  ShellState state_, saved_;  // the changing part; the rest of the members are constant after construction
  ShellWorkspace work_;
  std::vector<NodePose> reference_;     // initial node poses (display strain)
  std::vector<std::uint8_t> six_dof_;   // per node: 1 when it has 6 DoFs
  // node bases (eq. R2): slot directions of translations and 6-DoF rotations, world components;
  // identity unless a restraint needs other directions (then has_basis_ = 1)
  std::vector<Mat3> basis_u_, basis_r_;
  std::vector<std::uint8_t> has_basis_;
  struct Prescribed {
    int node, slot;
    double value;  // along basis_u_ column `slot` at lambda = 1
  };
  std::vector<Prescribed> prescribed_;
  std::vector<int> prescribed_of_;       // 3 per node: index into prescribed_ or -1
  std::vector<std::uint8_t> element_prescribed_;  // element has a prescribed corner
  int snapped_directors_ = 0;
  double largest_snap_ = 0.0;
  assembly::DofMap dofs_;
  assembly::ElementThreads threads_;
  ShellElements elements_;  // the constant elements (their results: work_)
  double rotation_scale_ = 1.0;
  // tangent pattern built once; per element the value index of each (corner dof, corner dof)
  // entry (-1 when restrained), so assembly is a scatter-add without triplets
  assembly::BlockPattern pattern_;
  std::vector<std::array<int, 576>> scatter_;
  std::vector<std::array<int, 36>> node_scatter_;  // value indices of each node's own 6 x 6 block
  std::vector<std::array<Vec3, 4>> dead_pressure_;  // per spec_.pressures: fixed nodal forces (reference)
  assembly::EffectCounter elastic_, point_loads_, dead_pressure_stat_, follower_pressure_stat_;
  long long dead_pressures_ = 0, follower_pressures_ = 0;  // loaded quads of each kind
  long long assemblies_ = 0;  // hr / ans / drilling ran in every element of every assembly
  ElementShare element_share_;  // the elements this rank evaluates (element_share())
  TangentParts tangent_parts_;  // who adds and holds which entries over ranks (built when first asked)
  bool in_parts_ = false;       // the tangent is assembled in parts (assemble_tangent_in_parts)
  bool adds_node_tangent(int I) const { return !in_parts_ || tangent_parts_.adds_node(I); }
  bool adds_element_tangent(int k) const { return !in_parts_ || element_share_.rank_of(k) == element_share_.rank(); }
  const ElementShare& element_share();
  void build_pattern();
  void build_node_bases(std::vector<unsigned>& fixed);
  // one assembly's inputs and outputs, handed to each term
  struct Assembly {
    double lambda;
    Eigen::VectorXd& r;
    Eigen::SparseMatrix<double>* K;
    Eigen::VectorXd* load;
    double* values;        // K's values (null without K)
    bool prescribed_load;  // load wanted and some displacement prescribed (eq. R4)
  };
  // the terms of evaluate(), each an effect with its own counter
  void elastic_term(Assembly& a);
  void to_solver_rows(const ShellElement& e, Mat24& m) const;
  void point_load_term(Assembly& a);
  void pressure_term(Assembly& a, bool follower);
  Vec3 rows_u(int I, const Vec3& v) const;
  Vec3 rows_r(int I, const Vec3& v) const;
  Mat3 block_uu(int I, const Mat3& b, int J) const;
  void add_to_node(Assembly& a, int I, int si, int sj, double v) const;
  void add_prescribed_load(Assembly& a, int I, int si, int J, int sj, double k) const;
};

}  // namespace ff::shell
