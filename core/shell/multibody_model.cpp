#include "core/shell/multibody_model.h"

#include <atomic>
#include <mutex>

#include "core/assembly/element_threads.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "core/assembly/node_frames.h"
#include "core/lie/se3.h"
#include "core/shell/shell_model.h"  // dead_pressure_forces
#include "core/shell/surface_strain.h"
#include "core/solve/solver_ranks.h"

namespace ff::shell {

namespace {
using Mat6 = Eigen::Matrix<double, 6, 6>;
using assembly::Clock;
using assembly::seconds_since;
using lie::hat;
}  // namespace

MultibodyModel::~MultibodyModel() = default;

MultibodyModel::MultibodyModel(MultibodySpec spec) : spec_(std::move(spec)) {
  // nodes: every shell body's mesh nodes, then one node per rigid body
  for (int body = 0; body < static_cast<int>(spec_.shells.size()); ++body) {
    const ShellBodySpec& b = spec_.shells[body];
    shell_offset_.push_back(static_cast<int>(reference_.size()));
    const mesh::ShellMesh& m = b.mesh;
    if (m.quad_count() == 0) throw std::invalid_argument("shell body '" + b.name + "' has no elements");
    if (!(b.density > 0) && b.quad_material.empty())
      throw BodySpecError(BodySpecError::Part::shell_density, body, "shell body '" + b.name + "' needs a positive density");
    for (std::size_t q = 0; q < b.quad_material.size(); ++q)
      if (!(b.densities.at(b.quad_material[q]) > 0))
        throw BodySpecError(BodySpecError::Part::shell_density, body,
                            "shell body '" + b.name + "', quad " + std::to_string(q) + ": needs a positive density",
                            static_cast<int>(q));
    for (int i = 0; i < m.node_count(); ++i) {
      reference_.push_back({m.frames[i], m.points[i]});
      six_dof_.push_back(b.options.drilling || (i < static_cast<int>(m.fold.size()) && m.fold[i]) ? 1 : 0);
    }
  }
  rigid_offset_ = static_cast<int>(reference_.size());
  for (int body = 0; body < static_cast<int>(spec_.rigid.size()); ++body) {
    const RigidBodySpec& r = spec_.rigid[body];
    if (!(r.mass > 0))
      throw BodySpecError(BodySpecError::Part::rigid_mass, body, "rigid body '" + r.name + "' needs a positive mass");
    Eigen::SelfAdjointEigenSolver<Mat3> es(0.5 * (r.inertia + r.inertia.transpose()));
    if (!(es.eigenvalues().minCoeff() > 0))
      throw BodySpecError(BodySpecError::Part::rigid_inertia, body,
                          "rigid body '" + r.name + "' needs a positive definite inertia tensor");
    reference_.push_back(r.pose);
    six_dof_.push_back(1);
  }
  const int nn = static_cast<int>(reference_.size());
  auto check_node = [&](int id, const char* what) {
    if (id < 0 || id >= nn) throw std::invalid_argument(std::string(what) + ": node " + std::to_string(id) + " does not exist");
  };
  for (const PositionConstraint& c : spec_.positions) {
    check_node(c.a, "position constraint");
    if (c.b >= 0) check_node(c.b, "position constraint");
  }
  for (const PerpendicularConstraint& c : spec_.perpendiculars) {
    check_node(c.a, "rotation constraint");
    if (c.b >= 0) check_node(c.b, "rotation constraint");
    for (int id : {c.a, c.b})
      if (id >= 0 && !six_dof_[id])
        throw std::invalid_argument("a rotational joint row acts on node " + std::to_string(id) +
                                    ", which has 5 DoFs (no drilling): its frame's spin about the director is not "
                                    "a physical rotation. Enable the drilling effect for that shell, join rigid "
                                    "bodies, or use a revolute joint along an edge (positions only)");
  }
  // a ground point at a node's own reference position, without offset, pins the node: its
  // translations leave the unknowns (x ← x + R δu never moves it) instead of adding three
  // constraint rows, whose reaction stiffness turns with the node and ages a frozen matrix
  std::vector<std::uint8_t> pinned(nn, 0);
  std::vector<PositionConstraint> rows;
  for (const PositionConstraint& c : spec_.positions) {
    const bool pin = c.b < 0 && c.a < rigid_offset_ && c.a_offset.isZero(0.0) &&
                     (c.target - reference_[c.a].p).norm() <= 1e-12 * std::max(1.0, c.target.norm());
    if (pin && !pinned[c.a]) pinned_.push_back(c.a);
    if (pin) pinned[c.a] = 1;
    else rows.push_back(c);
  }
  spec_.positions = std::move(rows);
  // supports (MultibodySpec::supports): held translations and rotations leave the unknowns too, so
  // x <- x + R du and R <- R exp(dtheta) never move them: exact whatever the node's frame
  std::vector<std::uint8_t> held_rotation(nn, 0);
  for (const NodeSupport& h : spec_.supports) {
    check_node(h.node, "support");
    if (h.node >= rigid_offset_) throw std::invalid_argument("a support acts on shell nodes; node " + std::to_string(h.node) + " is a rigid body's");
    if (h.translations) pinned[h.node] = 1;
    if (h.rotations) held_rotation[h.node] = 1;
  }
  dofs_ = assembly::DofMap(nn, [&](int i, int slot) {
    return slot >= (pinned[i] ? 3 : 0) && slot < (six_dof_[i] ? 6 : 5) && !(held_rotation[i] && slot >= 3);
  });
  constraint_rows_ = 3 * static_cast<int>(spec_.positions.size()) + static_cast<int>(spec_.perpendiculars.size());

  for (int b = 0; b < static_cast<int>(spec_.shells.size()); ++b) {
    const ShellBodySpec& body = spec_.shells[b];
    const mesh::ShellMesh& m = body.mesh;
    std::vector<ShellSection> sections{body.section};
    std::vector<ShellOptions> options{body.options};
    std::vector<double> densities{body.density};
    if (!body.quad_material.empty()) {  // a body joined from parts of several materials
      sections.clear(), options.clear(), densities.clear();
      for (int k : body.quad_material) {
        sections.push_back(body.sections.at(k));
        densities.push_back(body.densities.at(k));
        options.push_back(body.options);
        options.back().drilling_factor = body.drilling_factors.at(k);
      }
    }
    try {
      elements_.add_mesh(m, shell_offset_[b], sections, options, densities, b, body.quad_reference_direction);
    } catch (const ShellElementError& err) {
      throw BodySpecError(BodySpecError::Part::shell_element, b, "shell body '" + body.name + "', " + err.what(),
                          err.quad());
    }
    const long long quads = m.quad_count();
    hr_elements_ += body.options.hr * quads, ans_elements_ += body.options.ans * quads,
        drilling_elements_ += body.options.drilling * quads;
  }
  state_.poses = reference_;
  committed_ = state_;
  check_loads();
  build_pattern();
}

void MultibodyModel::check_loads() {
  const int nn = node_count();
  auto finite = [](const Vec3& x) { return x.allFinite(); };
  for (int k = 0; k < static_cast<int>(spec_.loads.size()); ++k) {
    const TimedNodalLoad& tl = spec_.loads[k];
    auto refuse = [&](const std::string& why) {
      throw LoadSpecError(LoadSpecError::Part::nodal_load, k, "nodal load " + std::to_string(k) + ": " + why);
    };
    if (tl.load.node < 0 || tl.load.node >= nn)
      refuse("node " + std::to_string(tl.load.node) + " does not exist (the model has " + std::to_string(nn) + " nodes)");
    if (!finite(tl.load.force) || !finite(tl.load.moment)) refuse("its force and moment must be finite");
    if (*tl.history.defect()) refuse(tl.history.defect());
  }
  dead_pressure_.resize(spec_.pressures.size());
  pressure_nodes_.resize(spec_.pressures.size());
  for (int k = 0; k < static_cast<int>(spec_.pressures.size()); ++k) {
    const TimedPressure& tp = spec_.pressures[k];
    auto refuse = [&](const std::string& why) {
      throw LoadSpecError(LoadSpecError::Part::pressure, k, "pressure " + std::to_string(k) + ": " + why);
    };
    if (tp.body < 0 || tp.body >= static_cast<int>(spec_.shells.size()))
      refuse("shell body " + std::to_string(tp.body) + " does not exist");
    const mesh::ShellMesh& m = spec_.shells[tp.body].mesh;
    if (tp.load.quad < 0 || tp.load.quad >= m.quad_count())
      refuse("quad " + std::to_string(tp.load.quad) + " does not exist (shell body '" + spec_.shells[tp.body].name +
             "' has " + std::to_string(m.quad_count()) + " quads)");
    if (tp.load.follower)
      refuse("a follower pressure is not available in dynamics (only dead pressures, fixed by the reference "
             "geometry, are)");
    if (!std::isfinite(tp.load.pressure)) refuse("its value must be finite");
    if (*tp.history.defect()) refuse(tp.history.defect());
    std::array<Vec3, 4> x;
    for (int c = 0; c < 4; ++c) {
      const int I = m.quads[tp.load.quad][c];
      x[c] = m.points[I];
      pressure_nodes_[k][c] = shell_offset_[tp.body] + I;
    }
    dead_pressure_[k] = dead_pressure_forces(x, tp.load.pressure);
  }
}

// cb_shell_dynamics.md §8. A dead world force f at node I: r_u -= Rᵀf (D17), ∂/∂θ = −(Rᵀf)~ (D18);
// a dead world moment m: r_θ -= Rᵀm, ∂/∂θ = −(Rᵀm)~ (rows 3, 4 only at a 5-DoF node: the drilling
// row is not an unknown, its column is kept for T_SE3 (G9)); follower components are constant
// in the node frame (D19); pressures are dead nodal forces on the translations (D20).
template <class AddPositionBlock>
void MultibodyModel::add_external_loads(double t, Eigen::VectorXd& r, const IterationWeights* w,
                                        AddPositionBlock&& add_position_block) {
  auto subtract = [&](int I, int slot0, const Vec3& x) {
    for (int j = 0; j < 3; ++j) {
      const int a = dofs_.equation(I, slot0 + j);
      if (a >= 0) r[a] -= x[j];
    }
  };
  if (!spec_.loads.empty()) {
    const auto t0 = Clock::now();
    for (const TimedNodalLoad& tl : spec_.loads) {
      const double s = tl.history.factor(t);  // (D16)
      if (s == 0.0) continue;
      const NodalLoad& l = tl.load;
      const int I = l.node;
      const Mat3& R = state_.poses[I].R;
      const Vec3 f = s * (l.follower ? l.force : Vec3(R.transpose() * l.force));
      const Vec3 m = s * (l.follower ? l.moment : Vec3(R.transpose() * l.moment));
      subtract(I, 0, f);
      subtract(I, 3, m);
      if (!w || l.follower) continue;  // (D19): no position derivative
      add_position_block(I, 0, I, 3, -w->stiffness * hat(f));  // (D18)
      add_position_block(I, 3, I, 3, -w->stiffness * hat(m));
    }
    point_loads_.evaluations += static_cast<long long>(spec_.loads.size());
    point_loads_.seconds += seconds_since(t0);
  }
  if (!spec_.pressures.empty()) {
    const auto t0 = Clock::now();
    for (std::size_t k = 0; k < spec_.pressures.size(); ++k) {
      const double s = spec_.pressures[k].history.factor(t);
      if (s == 0.0) continue;
      for (int c = 0; c < 4; ++c) {
        const int I = pressure_nodes_[k][c];
        const Vec3 f = s * (state_.poses[I].R.transpose() * dead_pressure_[k][c]);  // (D20), (D17)
        subtract(I, 0, f);
        if (w) add_position_block(I, 0, I, 3, -w->stiffness * hat(f));  // (D18)
      }
    }
    dead_pressure_stat_.evaluations += static_cast<long long>(spec_.pressures.size());
    dead_pressure_stat_.seconds += seconds_since(t0);
  }
}

void MultibodyModel::build_pattern() {
  for (const ShellElement& e : elements_.all()) pattern_.add_element(e.nodes);
  for (int I = 0; I < node_count(); ++I) pattern_.add_block(I, I);  // rigid bodies, constraint-force terms
  for (const PerpendicularConstraint& c : spec_.perpendiculars)
    if (c.b >= 0) pattern_.add_block(c.a, c.b), pattern_.add_block(c.b, c.a);
  for (const PositionConstraint& c : spec_.positions)  // local-frame rows couple the pair (D12')
    if (c.b >= 0) pattern_.add_block(c.a, c.b), pattern_.add_block(c.b, c.a);
  pattern_.build(dofs_);
  scatter_.resize(elements_.size());
  for (int k = 0; k < elements_.size(); ++k) scatter_[k] = pattern_.element_scatter(dofs_, elements_[k].nodes);
  results_.resize(elements_.size());
  timed_seconds_.assign((elements_.size() + 7) / 8, {0.0, 0.0});
  // B: 3 rows per position constraint on the translations, 1 row per perpendicularity on rotations
  std::vector<Eigen::Triplet<double>> t;
  int row = 0;
  for (const PositionConstraint& c : spec_.positions) {
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 6; ++j) {
        if (dofs_.equation(c.a, j) >= 0) t.emplace_back(row + k, dofs_.equation(c.a, j), 1.0);
        if (c.b >= 0 && dofs_.equation(c.b, j) >= 0) t.emplace_back(row + k, dofs_.equation(c.b, j), 1.0);
      }
    row += 3;
  }
  for (const PerpendicularConstraint& c : spec_.perpendiculars) {
    for (int j = 3; j < 6; ++j) {
      t.emplace_back(row, dofs_.equation(c.a, j), 1.0);
      if (c.b >= 0) t.emplace_back(row, dofs_.equation(c.b, j), 1.0);
    }
    ++row;
  }
  b_pattern_.resize(constraint_rows_, dofs_.size());
  b_pattern_.setFromTriplets(t.begin(), t.end());
  b_pattern_.makeCompressed();
}

Vec6 MultibodyModel::node_vector(const Eigen::VectorXd& x, int node) const {
  Vec6 out = Vec6::Zero();
  for (int s = 0; s < 6; ++s)
    if (dofs_.equation(node, s) >= 0) out[s] = x[dofs_.equation(node, s)];
  return out;
}

void MultibodyModel::configure(const Eigen::VectorXd& step) {
  state_.node_step.resize(state_.poses.size());
  const int nn = node_count();
  std::atomic<bool> nonzero{false};
  // nodes are independent; an exponential per node is ~5 % of a correction on one thread
  assembly::for_each_chunk(threads_, nn, [&](int begin, int end) {
    bool nz = false;
    for (int I = begin; I < end; ++I) {  // X_WN = X_WN,n exp(step_I) on SE(3) (generalized_alpha.md (G3))
      const Vec6 h = node_vector(step, I);
      const ff::lie::Pose X_WN = ff::lie::Pose{committed_.poses[I].R, committed_.poses[I].p} * ff::lie::exp_se3(h);
      state_.poses[I] = {X_WN.R, X_WN.p};
      state_.node_step[I] = h;
      nz = nz || !h.isZero();
    }
    if (nz) nonzero = true;
  });
  state_.step_is_zero = !nonzero;
}

// into the iteration matrix at (I, si), (J, sj) when both are unknowns
void MultibodyModel::add(Assembly& as, int I, int si, int J, int sj, double x) const {
  // in parts (distributed.md (D2)): a node's own block by its owner, a coupling of two nodes by rank 0
  if (in_parts_ && !(I == J ? matrix_parts_.adds_node(I) : linear_solver_rank() == 0)) return;
  const int a = dofs_.equation(I, si), b = dofs_.equation(J, sj);
  if (a >= 0 && b >= 0) as.values[pattern_.value_index(a, b)] += x;
}
// a rate term (mass, damping) of node I's rows oi.. and node J's columns oj..
void MultibodyModel::add_block(Assembly& as, int I, int oi, int J, int oj, const Mat3& blk) const {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) add(as, I, oi + i, J, oj + j, blk(i, j));
}
// a position derivative blk = ∂r(I, oi..)/∂θ(J, oj..) in local increments: times the rows oj..oj+2
// of T_SE3(step_J) it is the derivative with respect to the step (G9)
void MultibodyModel::add_position_block(Assembly& as, int I, int oi, int J, int oj, const Mat3& blk) const {
  if (!as.with_T) return add_block(as, I, oi, J, oj, blk);
  const Eigen::Matrix<double, 3, 6> blk_T = blk * step_tangent_[J].middleRows<3>(oj);
  for (int i = 0; i < 3; ++i)
    for (int s = 0; s < 6; ++s) add(as, I, oi + i, J, s, blk_T(i, s));
}

// One assembly: every effect is a term of its own with its own counter (effect_stats()), in a
// fixed order so that sums never depend on which effects a scene has.
void MultibodyModel::evaluate(double t, const Eigen::VectorXd& v, const Eigen::VectorXd& vdot,
                              const Eigen::VectorXd& lambda, Eigen::VectorXd& r, Eigen::VectorXd& phi,
                              const IterationWeights* w, SparseMatrixD* S, SparseMatrixD* B) {
  const bool tangent = w && S;
  // (G8)-(G9): position derivatives taken in local increments at the current poses are turned
  // into derivatives with respect to the step by T_SE3(step) on the column side
  const bool with_T = (tangent || B) && exact_matrix_ && !state_.step_is_zero;
  if (with_T) {  // (G8), only when a matrix is asked for: most iterations of a kept matrix are not
    step_tangent_.resize(state_.poses.size());
    for (int I = 0; I < node_count(); ++I) step_tangent_[I] = ff::lie::tangent_se3(state_.node_step[I]);
  }
  r.setZero(dofs_.size());
  phi.setZero(constraint_rows_);
  if (tangent) pattern_.zeroed(*S);
  Assembly as{t, v, vdot, lambda, r, phi, w, S, B, tangent ? S->valuePtr() : nullptr, tangent, with_T};
  shell_element_term(as);
  rigid_body_term(as);
  // external loads at t = t_{n+1} (D16)-(D20)
  add_external_loads(t, r, tangent ? w : nullptr, [&](int I, int oi, int J, int oj, const Mat3& blk) {
    add_position_block(as, I, oi, J, oj, blk);
  });
  joint_term(as);
  if (tangent && in_parts_) matrix_parts_.sum_shared(as.values);  // distributed.md (D4)
}

// (D1): the elements this rank evaluates, METIS's part of the mesh over the ranks sharing the solvers
// (alone: every element); made when first needed, again when the ranks or the elements change
const ElementShare& MultibodyModel::element_share() {
  if (!element_share_.made_for(elements_.size(), linear_solver_ranks()))
    element_share_ = ElementShare(elements_.connectivity(), node_count(), linear_solver_rank(), linear_solver_ranks());
  return element_share_;
}

const std::vector<int>* MultibodyModel::assemble_matrix_in_parts(bool on) {
  in_parts_ = on && linear_solver_ranks() > 1;
  if (!in_parts_) return nullptr;
  if (!matrix_parts_.built()) {
    const int nn = node_count();
    matrix_parts_ = TangentParts(static_cast<int>(pattern_.pattern().nonZeros()), nn, element_share());
    for (int k = 0; k < elements_.size(); ++k)
      matrix_parts_.add_element(k, scatter_[k].data(), 576, elements_[k].nodes.data(), 4);
    for (int I = 0; I < nn; ++I) matrix_parts_.add_node(I, pattern_.node_scatter(dofs_, I).data(), 36);
    // the blocks coupling two nodes of a joint (build_pattern), both ways
    auto pair = [&](int a, int b) {
      std::vector<int> positions;
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j) {
          const int ra = dofs_.equation(a, i), cb = dofs_.equation(b, j), rb = dofs_.equation(b, i), ca = dofs_.equation(a, j);
          if (ra >= 0 && cb >= 0) positions.push_back(pattern_.value_index(ra, cb));
          if (rb >= 0 && ca >= 0) positions.push_back(pattern_.value_index(rb, ca));
        }
      matrix_parts_.add_first_rank(positions.data(), static_cast<int>(positions.size()));
    };
    for (const PerpendicularConstraint& c : spec_.perpendiculars)
      if (c.b >= 0) pair(c.a, c.b);
    for (const PositionConstraint& c : spec_.positions)
      if (c.b >= 0) pair(c.a, c.b);
    matrix_parts_.finish();
  }
  return &matrix_parts_.held();
}

// Shell elements: elastic (S15-S17), inertia (D4-D7) and gravity (D8) in one kernel pass per
// element through the shared element loop, each effect counted on its own.
void MultibodyModel::shell_element_term(Assembly& as) {
  const Eigen::VectorXd& v = as.v;
  const Eigen::VectorXd& vdot = as.vdot;
  Eigen::VectorXd& r = as.r;
  const IterationWeights* w = as.w;
  double* values = as.values;
  const bool tangent = as.tangent, with_T = as.with_T;
  const int ne = elements_.size();
  constexpr int timing_stride = 8;
  double t_el = 0, t_in = 0;
  const bool gravity = spec_.gravity;
  // over MPI ranks each evaluates its share of the elements and the sums are added up below
  // (core/solve/distributed.md §2); alone, the share is every element
  const ElementShare& share = element_share();
  const std::vector<int>& mine = share.mine();
  elements_.for_each_of(threads_, mine, state_.poses, [&](int k, const ShellElement& e, const ElementPoses& cur) {
    {
      ElementRates vel, acc;
      for (int c = 0; c < 4; ++c) {
        const int I = e.nodes[c];
        vel[c] = node_vector(v, I);
        acc[c] = node_vector(vdot, I);
        if (!e.plain) {  // corner-local rates: blockdiag(Cᵀ, Cᵀ) of the node's
          vel[c].head<3>() = e.corner[c].transpose() * vel[c].head<3>();
          vel[c].tail<3>() = e.corner[c].transpose() * vel[c].tail<3>();
          acc[c].head<3>() = e.corner[c].transpose() * acc[c].head<3>();
          acc[c].tail<3>() = e.corner[c].transpose() * acc[c].tail<3>();
        }
      }
      ElementResult& out = results_[k];
      Vec24 f;
      Mat24 K, M, C, Kin;
      // effect_stats: every timing_stride-th element is timed (a clock read costs about as much as
      // a tenth of an element's force), the totals are scaled to all elements below
      const bool timed = k % timing_stride == 0;
      Clock::time_point t0, t1;
      if (timed) t0 = Clock::now();
      e.elastic->evaluate(cur, out.r, tangent ? &K : nullptr);
      if (timed) t1 = Clock::now();
      // inertia and gravity in one pass (gravity's time is counted in inertia's)
      e.inertia->evaluate(cur, vel, acc, f, tangent ? InertiaJacobians{&M, &C, &Kin} : InertiaJacobians{},
                          gravity ? &spec_.g : nullptr);
      out.r += f;
      if (tangent) K += Kin;  // position derivatives: elastic, inertia and gravity
      if (timed) {
        // the timed element's own slot (summed below): no lock in the loop
        timed_seconds_[k / timing_stride] = {std::chrono::duration<double>(t1 - t0).count(),
                                             std::chrono::duration<double>(Clock::now() - t1).count()};
      }
      if (!tangent) return;
      if (with_T)  // (G9) per corner, in the corner frame: blockdiag(Cᵀ, Cᵀ) T_SE3(step_I) blockdiag(C, C)
        for (int c = 0; c < 4; ++c) {
          Mat6 T = step_tangent_[e.nodes[c]];
          if (!e.plain)
            for (int i = 0; i < 2; ++i)
              for (int j = 0; j < 2; ++j)
                T.block<3, 3>(3 * i, 3 * j) = e.corner[c].transpose() * T.block<3, 3>(3 * i, 3 * j) * e.corner[c];
          K.middleCols<6>(6 * c) = (K.middleCols<6>(6 * c) * T).eval();
        }
      out.S = w->stiffness * K + w->mass * M + w->damping * C;
    }
  });
  // this rank's timed elements, scaled to all elements (its own share's time, on more than one rank)
  int timed_count = 0;
  for (const int k : mine)
    if (k % timing_stride == 0)
      t_el += timed_seconds_[k / timing_stride][0], t_in += timed_seconds_[k / timing_stride][1], ++timed_count;
  const double scale = timed_count > 0 ? static_cast<double>(mine.size()) / timed_count : 0.0;
  elastic_.evaluations += ne, elastic_.seconds += scale * t_el;
  ++assemblies_;
  inertia_.evaluations += ne, inertia_.seconds += scale * t_in;
  if (gravity) gravity_.evaluations += ne;
  for (const int k : mine) {
    const ShellElement& e = elements_[k];
    Vec24 F = results_[k].r;
    if (!e.plain)
      for (int c = 0; c < 4; ++c) {
        F.segment<3>(6 * c) = e.corner[c] * F.segment<3>(6 * c);
        F.segment<3>(6 * c + 3) = e.corner[c] * F.segment<3>(6 * c + 3);
      }
    for (int c = 0; c < 4; ++c)
      for (int s = 0; s < 6; ++s) {
        const int a = dofs_.equation(e.nodes[c], s);
        if (a >= 0) r[a] += F[6 * c + s];
      }
    if (!tangent) continue;
    Mat24 Ke = results_[k].S;
    if (!e.plain) {
      Mat24 T = Mat24::Zero();
      for (int c = 0; c < 4; ++c) {
        T.block<3, 3>(6 * c, 6 * c) = e.corner[c];
        T.block<3, 3>(6 * c + 3, 6 * c + 3) = e.corner[c];
      }
      Ke = T * Ke * T.transpose();
    }
    const std::array<int, 576>& idx = scatter_[k];
    for (int i = 0; i < 24; ++i)
      for (int j = 0; j < 24; ++j) {
        const int p = idx[i * 24 + j];
        if (p >= 0) values[p] += Ke(i, j);
      }
  }
  if (share.shared()) {  // the other ranks' elements: every rank gets the sums
    sum_over_ranks(r.data(), static_cast<std::size_t>(r.size()));
    // in parts, only the interface entries, once every term is in (evaluate)
    if (tangent && !in_parts_) sum_over_ranks(values, static_cast<std::size_t>(as.S->nonZeros()));
  }
}

// Rigid bodies (D9), (D10).
void MultibodyModel::rigid_body_term(Assembly& as) {
  const Eigen::VectorXd& v = as.v;
  const Eigen::VectorXd& vdot = as.vdot;
  Eigen::VectorXd& r = as.r;
  const IterationWeights* w = as.w;
  const bool tangent = as.tangent;
  auto t_rigid = Clock::now();
  for (int rb = 0; rb < static_cast<int>(spec_.rigid.size()); ++rb) {
    const RigidBodySpec& body = spec_.rigid[rb];
    const int I = rigid_node(rb);
    const Vec6 V = node_vector(v, I), A = node_vector(vdot, I);
    const Vec3 vel = V.head<3>(), om = V.tail<3>();
    const Mat3& J = body.inertia;
    Vec6 F;
    F.head<3>() = body.mass * (A.head<3>() + om.cross(vel));
    F.tail<3>() = J * A.tail<3>() + om.cross(J * om);
    const Vec3 Fg = body.mass * (state_.poses[I].R.transpose() * spec_.g);
    if (spec_.gravity) F.head<3>() -= Fg;
    for (int s = 0; s < 6; ++s) r[dofs_.equation(I, s)] += F[s];
    if (!tangent) continue;
    add_block(as, I, 0, I, 0, w->mass * body.mass * Mat3::Identity() + w->damping * body.mass * hat(om));
    add_block(as, I, 0, I, 3, -w->damping * body.mass * hat(vel));
    add_block(as, I, 3, I, 3, w->mass * J + w->damping * (hat(om) * J - hat(J * om)));
    if (spec_.gravity) add_position_block(as, I, 0, I, 3, -w->stiffness * hat(Fg));
  }
  if (!spec_.rigid.empty()) rigid_.evaluations += 1, rigid_.seconds += seconds_since(t_rigid);

}

// Joints: Φ, Bᵀλ and its variation (D11')-(D13); pins act through the missing unknowns.
void MultibodyModel::joint_term(Assembly& as) {
  const Eigen::VectorXd& lambda = as.lambda;
  Eigen::VectorXd& r = as.r;
  Eigen::VectorXd& phi = as.phi;
  const IterationWeights* w = as.w;
  SparseMatrixD* B = as.B;
  const bool tangent = as.tangent, with_T = as.with_T;
  if (constraint_rows_ == 0) {
    if (B) *B = b_pattern_, b_has_T_ = false;
    if (!pinned_.empty()) joints_.evaluations += 1;  // the pins act through the missing unknowns
    return;
  }
  auto t_joint = Clock::now();
  if (B) {
    *B = b_pattern_;
    std::fill(B->valuePtr(), B->valuePtr() + B->nonZeros(), 0.0);
    b_has_T_ = with_T;
    if (with_T) force_directions_ = *B;
  }
  // x = ∂Φ_row/∂(I, slot) in local increments: a constraint-force direction (G); with respect to
  // the step it is x times the row `slot` of T_SE3(step_I) (G9)
  auto bset = [&](int row, int I, int slot, double x) {
    if (!B) return;
    if (!with_T) {
      if (dofs_.equation(I, slot) >= 0) B->coeffRef(row, dofs_.equation(I, slot)) += x;
      return;
    }
    if (dofs_.equation(I, slot) >= 0) force_directions_.coeffRef(row, dofs_.equation(I, slot)) += x;
    for (int s = 0; s < 6; ++s)
      if (dofs_.equation(I, s) >= 0 && step_tangent_[I](slot, s) != 0.0)
        B->coeffRef(row, dofs_.equation(I, s)) += x * step_tangent_[I](slot, s);
  };
  int row = 0;
  for (const PositionConstraint& c : spec_.positions) {
    // in node a's frame A (D11'), (D12'): Φ = R_WAᵀ (p_WPa − p_WPb), Pa and Pb the points carried by
    // nodes a and b (frames A, B), p_WP = p_WN + R_WN o. Its Jacobian is constant under rigid motions of the
    // pair ([1, −õ_a + Φ̃ | −R_AB, R_AB õ_b], R_AB = R_WAᵀR_WB), so a frozen iteration matrix does not age
    // as the bodies turn.
    const Vec3 lam = lambda.segment<3>(row);
    const Mat3& R_WA = state_.poses[c.a].R;
    const Vec3 p_WPa = state_.poses[c.a].p + R_WA * c.a_offset;
    const Vec3 p_WPb = c.b >= 0 ? Vec3(state_.poses[c.b].p + state_.poses[c.b].R * c.b_offset) : c.target;
    const Vec3 ph = R_WA.transpose() * (p_WPa - p_WPb);
    phi.segment<3>(row) = ph;
    const Mat3 Ba_rot = -hat(c.a_offset) + hat(ph);
    for (int j = 0; j < 3; ++j)
      if (dofs_.equation(c.a, j) >= 0) r[dofs_.equation(c.a, j)] += lam[j];
    const Vec3 fa = Ba_rot.transpose() * lam;
    for (int j = 0; j < 3; ++j)
      if (dofs_.equation(c.a, 3 + j) >= 0) r[dofs_.equation(c.a, 3 + j)] += fa[j];
    for (int k = 0; k < 3; ++k) {
      bset(row + k, c.a, k, 1.0);
      for (int j = 0; j < 3; ++j) bset(row + k, c.a, 3 + j, Ba_rot(k, j));
    }
    const Mat3 L = hat(lam);
    if (tangent) {  // (−Φ × λ)' = λ̃ δΦ
      add_position_block(as, c.a, 3, c.a, 0, w->stiffness * L);
      add_position_block(as, c.a, 3, c.a, 3, w->stiffness * L * Ba_rot);
    }
    if (c.b >= 0) {
      const Mat3& R_WB = state_.poses[c.b].R;
      const Mat3 R_AB = R_WA.transpose() * R_WB;
      const Mat3 Bb_rot = R_AB * hat(c.b_offset);
      const Vec3 mu = R_AB.transpose() * lam;  // λ in b's frame
      for (int j = 0; j < 3; ++j)
        if (dofs_.equation(c.b, j) >= 0) r[dofs_.equation(c.b, j)] -= mu[j];
      const Vec3 fb = Bb_rot.transpose() * lam;
      for (int j = 0; j < 3; ++j)
        if (dofs_.equation(c.b, 3 + j) >= 0) r[dofs_.equation(c.b, 3 + j)] += fb[j];
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) {
          bset(row + k, c.b, j, -R_AB(k, j));
          bset(row + k, c.b, 3 + j, Bb_rot(k, j));
        }
      if (tangent) {
        const Mat3 R_BA = R_AB.transpose();
        add_position_block(as, c.a, 3, c.b, 0, -w->stiffness * L * R_AB);
        add_position_block(as, c.a, 3, c.b, 3, w->stiffness * L * Bb_rot);
        // δμ = μ̃ δθ_b − R_BA λ̃ δθ_a (δR_WBᵀ = −δθ̃_b R_WBᵀ, δR_WA = R_WA δθ̃_a); forces −μ and −õ_b μ
        add_position_block(as, c.b, 0, c.b, 3, -w->stiffness * hat(mu));
        add_position_block(as, c.b, 0, c.a, 3, w->stiffness * R_BA * L);
        add_position_block(as, c.b, 3, c.b, 3, -w->stiffness * hat(c.b_offset) * hat(mu));
        add_position_block(as, c.b, 3, c.a, 3, w->stiffness * hat(c.b_offset) * R_BA * L);
      }
    }
    row += 3;
  }
  for (const PerpendicularConstraint& c : spec_.perpendiculars) {
    const double lam = lambda[row];
    const Mat3& R_WA = state_.poses[c.a].R;
    const Vec3 a_W = R_WA * c.a_local;
    const Vec3 b_W = c.b >= 0 ? Vec3(state_.poses[c.b].R * c.b_vector) : c.b_vector;
    phi[row] = a_W.dot(b_W);
    const Vec3 b_A = R_WA.transpose() * b_W;
    const Vec3 ga = c.a_local.cross(b_A);  // ∂Φ/∂θ_a (D13)
    for (int j = 0; j < 3; ++j) r[dofs_.equation(c.a, 3 + j)] += lam * ga[j], bset(row, c.a, 3 + j, ga[j]);
    if (tangent) add_position_block(as, c.a, 3, c.a, 3, w->stiffness * lam * hat(c.a_local) * hat(b_A));
    if (c.b >= 0) {
      const Mat3& R_WB = state_.poses[c.b].R;
      const Vec3 a_B = R_WB.transpose() * a_W;
      const Vec3 gb = c.b_vector.cross(a_B);  // ∂Φ/∂θ_b
      for (int j = 0; j < 3; ++j) r[dofs_.equation(c.b, 3 + j)] += lam * gb[j], bset(row, c.b, 3 + j, gb[j]);
      if (tangent) {
        add_position_block(as, c.b, 3, c.b, 3, w->stiffness * lam * hat(c.b_vector) * hat(a_B));
        add_position_block(as, c.a, 3, c.b, 3,
                           -w->stiffness * lam * hat(c.a_local) * R_WA.transpose() * R_WB * hat(c.b_vector));
        add_position_block(as, c.b, 3, c.a, 3,
                           -w->stiffness * lam * hat(c.b_vector) * R_WB.transpose() * R_WA * hat(c.a_local));
      }
    }
    ++row;
  }
  joints_.evaluations += 1, joints_.seconds += seconds_since(t_joint);
}


MotionSummary MultibodyModel::summary(const Eigen::VectorXd& v, double t) const {
  MotionSummary s;
  for (const TimedNodalLoad& tl : spec_.loads)  // (D21)
    if (!tl.load.follower) s.load_potential -= tl.history.factor(t) * tl.load.force.dot(node_displacement(tl.load.node));
  for (std::size_t k = 0; k < spec_.pressures.size(); ++k) {
    const double f = spec_.pressures[k].history.factor(t);
    for (int c = 0; c < 4; ++c) s.load_potential -= f * dead_pressure_[k][c].dot(node_displacement(pressure_nodes_[k][c]));
  }
  for (const ShellElement& e : elements_.all()) {
    ElementPoses cur;
    ElementRates vel;
    for (int c = 0; c < 4; ++c) {
      const int I = e.nodes[c];
      cur[c] = {state_.poses[I].R * e.corner[c], state_.poses[I].p};
      vel[c] = node_vector(v, I);
      vel[c].head<3>() = e.corner[c].transpose() * vel[c].head<3>();
      vel[c].tail<3>() = e.corner[c].transpose() * vel[c].tail<3>();
    }
    s.kinetic += e.inertia->kinetic_energy(cur, vel);
    s.strain += e.elastic->energy(cur);
    if (spec_.gravity) s.gravity_potential += e.inertia->gravity_potential(cur, spec_.g);
    e.inertia->add_momenta(cur, vel, s.linear_momentum, s.angular_momentum);
  }
  for (int rb = 0; rb < static_cast<int>(spec_.rigid.size()); ++rb) {
    const RigidBodySpec& body = spec_.rigid[rb];
    const int I = rigid_node(rb);
    const Vec6 V = node_vector(v, I);
    const Vec3 vel = V.head<3>(), om = V.tail<3>();
    s.kinetic += 0.5 * (body.mass * vel.squaredNorm() + om.dot(body.inertia * om));
    const Vec3 momentum_W = body.mass * (state_.poses[I].R * vel);
    s.linear_momentum += momentum_W;
    s.angular_momentum += state_.poses[I].p.cross(momentum_W) + state_.poses[I].R * (body.inertia * om);
    if (spec_.gravity) s.gravity_potential -= body.mass * spec_.g.dot(state_.poses[I].p);
  }
  return s;
}

std::vector<LoadSwitch> MultibodyModel::load_switches() const {
  std::vector<LoadSwitch> all;
  auto add = [&](const LoadHistory& h) {
    all.push_back({h.start, h.ramp == 0.0});
    if (h.ramp > 0.0) all.push_back({h.start + h.ramp, false});
    if (std::isfinite(h.end)) all.push_back({h.end, true});
  };
  for (const TimedNodalLoad& tl : spec_.loads) add(tl.history);
  for (const TimedPressure& tp : spec_.pressures) add(tp.history);
  std::sort(all.begin(), all.end(), [](const LoadSwitch& a, const LoadSwitch& b) { return a.time < b.time; });
  std::vector<LoadSwitch> out;
  for (const LoadSwitch& x : all)
    if (!out.empty() && out.back().time == x.time) out.back().jump = out.back().jump || x.jump;
    else out.push_back(x);
  return out;
}

double MultibodyModel::constraint_violation() const {
  double worst = 0.0;
  for (const PositionConstraint& c : spec_.positions) {
    const Vec3 p_WPa = state_.poses[c.a].p + state_.poses[c.a].R * c.a_offset;
    const Vec3 p_WPb = c.b >= 0 ? Vec3(state_.poses[c.b].p + state_.poses[c.b].R * c.b_offset) : c.target;
    worst = std::max(worst, (p_WPa - p_WPb).cwiseAbs().maxCoeff());
  }
  for (const PerpendicularConstraint& c : spec_.perpendiculars) {
    const Vec3 b_W = c.b >= 0 ? Vec3(state_.poses[c.b].R * c.b_vector) : c.b_vector;
    worst = std::max(worst, std::abs((state_.poses[c.a].R * c.a_local).dot(b_W)));
  }
  return worst;
}

double MultibodyModel::total_mass() const {
  double m = 0;
  for (const ShellElement& e : elements_.all()) m += e.inertia->mass();
  for (const RigidBodySpec& r : spec_.rigid) m += r.mass;
  return m;
}

std::vector<EffectStat> MultibodyModel::effect_stats() const {
  std::vector<EffectStat> out;
  auto own = [&](const char* name, const assembly::EffectCounter& c) {
    if (c.evaluations) out.push_back({name, c.evaluations, c.seconds, {}});
  };
  // formulation terms fused in the element kernel (cb_shell.cpp): counted, timed inside elastic
  auto fused = [&](const char* name, long long elements) {
    if (elements && assemblies_)
      out.push_back({name, elements * assemblies_, std::numeric_limits<double>::quiet_NaN(), "elastic"});
  };
  own("elastic", elastic_);
  fused("hr", hr_elements_);
  fused("ans", ans_elements_);
  fused("drilling", drilling_elements_);
  own("inertia", inertia_);
  if (gravity_.evaluations)  // one pass with the inertia (cb_shell_inertia.h): its time is inertia's
    out.push_back({"gravity", gravity_.evaluations, std::numeric_limits<double>::quiet_NaN(), "inertia"});
  own("rigid_body", rigid_);
  own("joints", joints_);
  own("point_loads", point_loads_);
  own("pressure_dead", dead_pressure_stat_);
  return out;
}

std::vector<double> MultibodyModel::nodal_surface_strain() const {
  return shell::nodal_surface_strain(elements_.all(), reference_, state_.poses,
                                     [](const ShellElement& e) { return e.thickness; });
}

}  // namespace ff::shell
