#include "core/shell/shell_model.h"

#include "core/assembly/element_threads.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/assembly/node_frames.h"
#include "core/lie/so3.h"
#include "core/shell/surface_strain.h"
#include "core/solve/solver_ranks.h"

namespace ff::shell {

// Peak resident size of `flexframe run clamped_plate_pressure --set mesh.n1=N --set mesh.n2=N`
// (hr + ans, 5 DoFs, full Newton, Release, /usr/bin/time %M), 2026-11-25:
//   N      nodes    peak [MB]   per node above 50 MB [KB]
//   64      4225       276        53
//   96      9409       552        55
//   128    16641       948        55
//   160    25921      1491        57
// Element storage (elements, scatter maps, element tangents: ~11 KB per quad) is linear; the
// factor's fill grows like log n (nested dissection on a 2-D mesh), hence c0 + c1 log2 n per
// node. With the drilling DoF at every node the N = 128 peak is 1159 MB: 1.235 times the
// variable part.
double estimated_peak_bytes(int nodes, double six_dof_fraction) {
  if (nodes <= 0) return 0.0;
  const double base = 50e6, c0 = 19e3, c1 = 2.5e3, six_dof_extra = 0.235;
  const double n = nodes;
  return base + n * (c0 + c1 * std::log2(n)) * (1.0 + six_dof_extra * std::clamp(six_dof_fraction, 0.0, 1.0));
}

namespace {
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using assembly::Clock;
using assembly::seconds_since;
using lie::hat;

// The 2x2 Gauss points of the bilinear quad x[0..3] (weights 1): visit(N, N_xi, N_eta, g_xi, g_eta)
// with the four shape functions, their derivatives and the tangent vectors at each point
template <class Visit>
void for_each_gauss_point(const std::array<Vec3, 4>& x, Visit&& visit) {
  static const double xa[4] = {-1, 1, 1, -1}, ya[4] = {-1, -1, 1, 1};
  const double g = 1.0 / std::sqrt(3.0);
  for (int gi = 0; gi < 4; ++gi) {
    const double xi = xa[gi] * g, eta = ya[gi] * g;
    double N[4], Nx[4], Ne[4];
    Vec3 gx = Vec3::Zero(), ge = Vec3::Zero();
    for (int a = 0; a < 4; ++a) {
      N[a] = 0.25 * (1 + xa[a] * xi) * (1 + ya[a] * eta);
      Nx[a] = 0.25 * xa[a] * (1 + ya[a] * eta);
      Ne[a] = 0.25 * ya[a] * (1 + xa[a] * xi);
      gx += Nx[a] * x[a];
      ge += Ne[a] * x[a];
    }
    visit(N, Nx, Ne, gx, ge);
  }
}

// p (g_xi x g_eta) over the bilinear quad x[0..3] by 2x2 Gauss (exact: the integrand is
// biquadratic), eq. P2 of shell_model.md: f_a = p sum_g N_a (g_xi x g_eta). With dfdx, also
// df_a/dx_b = p sum_g N_a (N_b,eta [g_xi]x - N_b,xi [g_eta]x) (eq. P3), 3x3 block (a, b) at dfdx[4a + b].
void pressure_forces(const std::array<Vec3, 4>& x, double p, std::array<Vec3, 4>& f, std::array<Mat3, 16>* dfdx) {
  for (Vec3& v : f) v.setZero();
  if (dfdx)
    for (Mat3& m : *dfdx) m.setZero();
  for_each_gauss_point(x, [&](const double* N, const double* Nx, const double* Ne, const Vec3& gx, const Vec3& ge) {
    const Vec3 n = gx.cross(ge);
    for (int a = 0; a < 4; ++a) f[a] += p * N[a] * n;
    if (!dfdx) return;
    const Mat3 Sx = hat(gx), Se = hat(ge);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) (*dfdx)[4 * a + b] += p * N[a] * (Ne[b] * Sx - Nx[b] * Se);
  });
}
}  // namespace

std::array<Vec3, 4> surface_traction_forces(const std::array<Vec3, 4>& x, const Vec3& t) {
  std::array<Vec3, 4> f;
  for (Vec3& v : f) v.setZero();
  for_each_gauss_point(x, [&](const double* N, const double*, const double*, const Vec3& gx, const Vec3& ge) {
    const double area = gx.cross(ge).norm();  // eq. P5: |g_xi x g_eta|
    for (int a = 0; a < 4; ++a) f[a] += N[a] * area * t;
  });
  return f;
}

std::array<Vec3, 4> dead_pressure_forces(const std::array<Vec3, 4>& x, double p) {
  std::array<Vec3, 4> f;
  pressure_forces(x, p, f, nullptr);
  return f;
}

namespace {
// a global axis (index) when d is +-e_k to round-off, else -1
int global_axis(const Vec3& d) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(std::abs(d[k]) - 1.0) < 1e-14 && std::abs(d[(k + 1) % 3]) < 1e-14 && std::abs(d[(k + 2) % 3]) < 1e-14)
      return k;
  return -1;
}

// The slots of one node for restrained directions dirs (unit) with prescribed values (eq. R2):
// basis T (columns = slot directions, world components), restrained slot mask and, per restrained
// slot, its value. All directions global axes: T = I and the axes themselves are the slots, so a
// model with only global restraints assembles exactly as without bases.
struct SlotBasis {
  Mat3 T = Mat3::Identity();
  unsigned restrained = 0;
  Vec3 value = Vec3::Zero();
  bool identity = true;
  std::string error;  // non-empty: the directions or values contradict each other
};

SlotBasis slot_basis(const std::vector<Vec3>& dirs, const std::vector<double>& values) {
  SlotBasis b;
  if (dirs.empty()) return b;
  const double scale = 1.0 + Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size())).cwiseAbs().maxCoeff();
  bool all_axes = true;
  for (const Vec3& d : dirs) all_axes = all_axes && global_axis(d) >= 0;
  if (all_axes) {
    bool set[3] = {false, false, false};
    for (std::size_t j = 0; j < dirs.size(); ++j) {
      const int k = global_axis(dirs[j]);
      const double v = dirs[j][k] > 0 ? values[j] : -values[j];
      if (set[k] && std::abs(b.value[k] - v) > 1e-12 * scale) {
        b.error = "two prescribed displacements along the same direction differ (" + std::to_string(b.value[k]) +
                  " and " + std::to_string(v) + ")";
        return b;
      }
      set[k] = true;
      b.value[k] = v;
      b.restrained |= 1u << k;
    }
    return b;
  }
  // general directions: the leading right singular vectors of D (rows = dirs) span them
  Eigen::MatrixXd D(dirs.size(), 3);
  Eigen::VectorXd v(dirs.size());
  for (std::size_t j = 0; j < dirs.size(); ++j) D.row(j) = dirs[j].transpose(), v[j] = values[j];
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(D, Eigen::ComputeThinU | Eigen::ComputeFullV);
  svd.setThreshold(1e-9);
  const int rank = static_cast<int>(svd.rank());
  b.T = svd.matrixV();
  if (b.T.determinant() < 0) b.T.col(2) *= -1.0;
  const Vec3 u = svd.solve(v);  // least-squares prescribed displacement
  if ((D * u - v).norm() > 1e-9 * scale) {
    b.error = "the prescribed displacements along its restrained directions contradict each other";
    return b;
  }
  for (int s = 0; s < rank; ++s) b.restrained |= 1u << s, b.value[s] = b.T.col(s).dot(u);
  b.identity = false;
  return b;
}

// two unit vectors spanning the plane of normal n (the other global axes when n is one)
std::array<Vec3, 2> in_plane_axes(const Vec3& n) {
  const int k = global_axis(n);
  if (k >= 0) return {Vec3::Unit((k + 1) % 3), Vec3::Unit((k + 2) % 3)};
  Vec3 t1 = n.unitOrthogonal();
  return {t1, n.cross(t1)};
}
}  // namespace

// eqs. R1-R4 of shell_model.md: per node, the slot bases and restrained slots; 5-DoF nodes turn
// their e1 onto the one free rotation axis
void ShellModel::build_node_bases(std::vector<unsigned>& fixed) {
  mesh::ShellMesh& m = spec_.mesh;
  const int nn = m.node_count();
  struct NodeRestraints {
    std::vector<Vec3> u_dirs, r_dirs, planes;
    std::vector<double> u_values;
    int u_source = -1, r_source = -1, plane_source = -1;
  };
  std::vector<NodeRestraints> at(nn);
  auto check_node = [&](int node, ShellSpecError::Part part, int source) {
    if (node < 0 || node >= nn)
      throw ShellSpecError(part, source, "node " + std::to_string(node) + " is not a node of the mesh (" +
                                             std::to_string(nn) + " nodes)");
  };
  for (const auto& [node, mask] : spec_.restraints) {
    check_node(node, ShellSpecError::Part::restraint, -1);
    for (int k = 0; k < 6; ++k)
      if (mask & (1u << k)) {
        if (k < 3) at[node].u_dirs.push_back(Vec3::Unit(k)), at[node].u_values.push_back(0.0);
        else at[node].r_dirs.push_back(Vec3::Unit(k - 3));
      }
  }
  for (std::size_t j = 0; j < spec_.directions.size(); ++j) {
    const DirectionRestraint& r = spec_.directions[j];
    check_node(r.node, ShellSpecError::Part::restraint, r.source);
    const double len = r.direction.norm();
    if (!(len > 1e-12) || !std::isfinite(len))
      throw ShellSpecError(ShellSpecError::Part::restraint, r.source, "a restraint direction at node " +
                                                                          std::to_string(r.node) + " is zero or not finite");
    if (!std::isfinite(r.value))
      throw ShellSpecError(ShellSpecError::Part::restraint, r.source, "a prescribed displacement is not finite");
    if (r.rotation && r.value != 0.0)
      throw ShellSpecError(ShellSpecError::Part::restraint, r.source,
                           "prescribed rotations are not supported; prescribe translations or hold the rotation at zero");
    NodeRestraints& n = at[r.node];
    if (r.rotation) n.r_dirs.push_back(r.direction / len), n.r_source = r.source;
    else n.u_dirs.push_back(r.direction / len), n.u_values.push_back(r.value), n.u_source = r.source;
  }
  for (const auto& [node, axis] : spec_.symmetry) {
    check_node(node, ShellSpecError::Part::symmetry, -1);
    at[node].planes.push_back(Vec3::Unit(axis));
  }
  for (const SymmetryPlane& p : spec_.symmetry_planes) {
    check_node(p.node, ShellSpecError::Part::symmetry, p.source);
    const double len = p.normal.norm();
    if (!(len > 1e-12) || !std::isfinite(len))
      throw ShellSpecError(ShellSpecError::Part::symmetry, p.source, "a symmetry plane normal is zero or not finite");
    at[p.node].planes.push_back(p.normal / len);
    at[p.node].plane_source = p.source;
  }

  basis_u_.assign(nn, Mat3::Identity());
  basis_r_.assign(nn, Mat3::Identity());
  has_basis_.assign(nn, 0);
  prescribed_of_.assign(3 * nn, -1);
  auto node_name = [](int i) { return "node " + std::to_string(i); };
  for (int I = 0; I < nn; ++I) {
    NodeRestraints& n = at[I];
    if (n.u_dirs.empty() && n.r_dirs.empty() && n.planes.empty()) continue;
    // eq. R3: a symmetry plane holds the normal translation and every rotation but the one about
    // the normal
    for (const Vec3& p : n.planes) {
      n.u_dirs.push_back(p), n.u_values.push_back(0.0);
      if (six_dof_[I])
        for (const Vec3& t : in_plane_axes(p)) n.r_dirs.push_back(t);
    }
    if (!six_dof_[I] && !n.planes.empty()) {
      // 5 DoFs: every plane must contain the director; one that misses by a hair is moved into
      // all of them at once (eq. R3')
      Mat3& R_WN0 = m.frames[I];
      const Vec3 d = R_WN0.col(2);
      Eigen::MatrixXd P(n.planes.size(), 3);
      for (std::size_t j = 0; j < n.planes.size(); ++j) P.row(j) = n.planes[j].transpose();
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(P, Eigen::ComputeFullV);
      svd.setThreshold(1e-9);
      const Eigen::MatrixXd Q = svd.matrixV().leftCols(svd.rank());
      const Vec3 along = Q * (Q.transpose() * d);  // the part of d the planes do not contain
      double cross = 0.0;
      for (const Vec3& p : n.planes) cross = std::abs(p.dot(d)) > std::abs(cross) ? p.dot(d) : cross;
      if (along.norm() > kSymmetryDirectorSnap || svd.rank() >= 3)
        throw ShellSpecError(ShellSpecError::Part::symmetry, n.plane_source,
                             node_name(I) + " lies on a symmetry plane its director crosses (normal . director = " +
                                 std::to_string(cross) + "); a symmetry plane must contain the director of a 5-DoF "
                                 "node (give the mesh exact normals, or enable the drilling effect for 6 DoFs)");
      if (along.norm() > 1e-12) {  // round-off of an exact generator normal stays as it is
        const Vec3 snapped = (d - along).normalized();
        largest_snap_ = std::max(largest_snap_, std::asin(std::min(1.0, along.norm())));
        ++snapped_directors_;
        for (std::size_t q = 0; q < m.corner_normals.size(); ++q)
          for (int c = 0; c < 4; ++c)
            if (m.quads[q][c] == I && (m.corner_normals[q][c] - m.normals[I]).norm() < 1e-12) m.corner_normals[q][c] = snapped;
        m.normals[I] = snapped;
        R_WN0 = mesh::frame_from_normal(snapped, m.frame_reference);
      }
      for (const Vec3& p : n.planes) n.r_dirs.push_back(p.cross(R_WN0.col(2)).normalized());  // in-plane tangent axis
    }
    // translations (and their prescribed values)
    const SlotBasis tu = slot_basis(n.u_dirs, n.u_values);
    if (!tu.error.empty()) throw ShellSpecError(ShellSpecError::Part::restraint, n.u_source, node_name(I) + ": " + tu.error);
    basis_u_[I] = tu.T;
    fixed[I] |= tu.restrained;
    for (int s = 0; s < 3; ++s)
      if ((tu.restrained & (1u << s)) && tu.value[s] != 0.0) {
        prescribed_of_[3 * I + s] = static_cast<int>(prescribed_.size());
        prescribed_.push_back({I, s, tu.value[s]});
      }
    // rotations
    if (six_dof_[I]) {
      const SlotBasis tr = slot_basis(n.r_dirs, std::vector<double>(n.r_dirs.size(), 0.0));
      basis_r_[I] = tr.T;
      fixed[I] |= tr.restrained << 3;
      has_basis_[I] = !(tu.identity && tr.identity);
      continue;
    }
    has_basis_[I] = !tu.identity;
    // 5 DoFs (eq. R5): only rotations about tangent axes exist; project the restrained directions
    Mat3& R_WN0 = m.frames[I];
    const Vec3 d = R_WN0.col(2);
    std::vector<Vec3> tangent;
    for (const Vec3& r : n.r_dirs)
      if (const Vec3 t = r - r.dot(d) * d; t.norm() > 1e-9) tangent.push_back(t.normalized());
    if (tangent.empty()) continue;
    Eigen::MatrixXd T(tangent.size(), 3);
    for (std::size_t j = 0; j < tangent.size(); ++j) T.row(j) = tangent[j].transpose();
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(T, Eigen::ComputeFullV);
    svd.setThreshold(1e-9);
    if (svd.rank() >= 2) {
      fixed[I] |= (1u << 3) | (1u << 4);
      continue;
    }
    // one restrained tangent direction b: the node may rotate about a = d x b only; e1 = a
    const Vec3 b = svd.matrixV().col(0);
    Vec3 a = d.cross(b).normalized();
    for (const Vec3& p : n.planes)
      if (std::abs(a.dot(p)) > 1.0 - 1e-9) a = p;  // a symmetry plane: exactly its normal
    R_WN0 << a, d.cross(a), d;
    fixed[I] |= 1u << 4;
  }
}

ShellModel::ShellModel(ShellModelSpec spec) : spec_(std::move(spec)) {
  mesh::ShellMesh& m = spec_.mesh;
  const int nn = m.node_count();
  six_dof_.assign(nn, spec_.options.drilling ? 1 : 0);
  for (int i = 0; i < nn && i < static_cast<int>(m.fold.size()); ++i)
    if (m.fold[i]) six_dof_[i] = 1;
  std::vector<unsigned> fixed(nn, 0u);  // slot mask, bits 0-5
  build_node_bases(fixed);
  dofs_ =
      assembly::DofMap(nn, [&](int i, int slot) { return slot < (six_dof_[i] ? 6 : 5) && !(fixed[i] & (1u << slot)); });

  state_.poses.resize(nn);
  for (int i = 0; i < nn; ++i) state_.poses[i] = {m.frames[i], m.points[i]};
  saved_ = state_;
  reference_ = state_.poses;
  // the elements, of each quad's own part when the parts differ in material
  std::vector<ShellSection> sections{spec_.section};
  std::vector<ShellOptions> options{spec_.options};
  if (!spec_.quad_section.empty()) {
    sections.clear(), options.clear();
    for (int q = 0; q < m.quad_count(); ++q) {
      const int k = spec_.quad_section.at(q);
      sections.push_back(spec_.sections.at(k));
      options.push_back(spec_.options);
      options.back().drilling_factor = spec_.drilling_factors.at(k);
    }
  }
  try {
    elements_.add_mesh(m, 0, sections, options, {0.0}, 0, spec_.quad_reference_direction);
  } catch (const ShellElementError& e) {
    throw ShellSpecError(e.thickness_at_fault() ? ShellSpecError::Part::element : ShellSpecError::Part::mid_surface,
                         e.quad(), e.what());
  }
  Vec3 lo = m.points.front(), hi = lo;
  for (const Vec3& p : m.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  rotation_scale_ = 0.1 * (hi - lo).norm();
  dead_pressure_.resize(spec_.pressures.size());
  for (std::size_t k = 0; k < spec_.pressures.size(); ++k) {
    const PressureLoad& pl = spec_.pressures[k];
    if (pl.quad < 0 || pl.quad >= m.quad_count())
      throw ShellSpecError(ShellSpecError::Part::pressure, static_cast<int>(k),
                           "pressure on quad " + std::to_string(pl.quad) + ", but the mesh has " +
                               std::to_string(m.quad_count()) + " quads");
    ++(pl.follower ? follower_pressures_ : dead_pressures_);
    if (pl.follower) continue;  // evaluated in the current configuration instead
    std::array<Vec3, 4> x;
    for (int c = 0; c < 4; ++c) x[c] = m.points[m.quads[pl.quad][c]];
    pressure_forces(x, pl.pressure, dead_pressure_[k], nullptr);
  }
  build_pattern();
  element_prescribed_.assign(elements_.size(), 0);
  for (int k = 0; k < elements_.size(); ++k)
    for (int I : elements_[k].nodes)
      for (int sl = 0; sl < 3; ++sl)
        if (prescribed_of_[3 * I + sl] >= 0) element_prescribed_[k] = 1;
  work_.reaction.assign(nn, Vec3::Zero());
}

void ShellModel::build_pattern() {
  for (const ShellElement& e : elements_.all()) pattern_.add_element(e.nodes);
  for (int I = 0; I < static_cast<int>(state_.poses.size()); ++I) pattern_.add_block(I, I);  // rotating-basis and load terms
  pattern_.build(dofs_);
  scatter_.resize(elements_.size());
  for (int k = 0; k < elements_.size(); ++k) scatter_[k] = pattern_.element_scatter(dofs_, elements_[k].nodes);
  node_scatter_.resize(state_.poses.size());
  for (std::size_t I = 0; I < state_.poses.size(); ++I) node_scatter_[I] = pattern_.node_scatter(dofs_, static_cast<int>(I));
  work_.element_force.resize(elements_.size());
  work_.element_tangent.resize(elements_.size());
  work_.node_force.resize(state_.poses.size());
}

void ShellModel::apply_prescribed(double lambda) {
  // eq. R4: the prescribed slot component of x_I is its reference value plus lambda * value
  for (const Prescribed& p : prescribed_) {
    const Vec3 t = basis_u_[p.node].col(p.slot);
    Vec3& p_WN = state_.poses[p.node].p;
    p_WN += (t.dot(spec_.mesh.points[p.node]) + lambda * p.value - t.dot(p_WN)) * t;
  }
}

void ShellModel::set_state(const ShellState& state) {
  if (state.poses.size() != state_.poses.size())
    throw std::invalid_argument("set_state: a state of " + std::to_string(state.poses.size()) + " nodes for a model of " +
                                std::to_string(state_.poses.size()));
  state_ = state;
}

double ShellModel::state_magnitude(int i) const {
  return dofs_.unknown(i).slot < 3 ? state_.poses[dofs_.unknown(i).node].p.cwiseAbs().maxCoeff() : 1.0;
}

// slot rows of a world vector at node I (eq. R2): T_u^T v for translations, T_r^T v for 6-DoF rotations
Vec3 ShellModel::rows_u(int I, const Vec3& v) const { return has_basis_[I] ? Vec3(basis_u_[I].transpose() * v) : v; }
Vec3 ShellModel::rows_r(int I, const Vec3& v) const { return has_basis_[I] ? Vec3(basis_r_[I].transpose() * v) : v; }
// a world-by-world 3x3 block between nodes I and J in slot rows and columns
Mat3 ShellModel::block_uu(int I, const Mat3& b, int J) const {
  Mat3 out = b;
  if (has_basis_[I]) out = basis_u_[I].transpose() * out;
  if (has_basis_[J]) out = out * basis_u_[J];
  return out;
}
// into node I's own block (the only node-level terms), through its precomputed value indices
void ShellModel::add_to_node(Assembly& a, int I, int si, int sj, double v) const {
  const int p = node_scatter_[I][6 * si + sj];
  if (p >= 0 && v != 0.0) a.values[p] += v;
}
// -d r / d lambda through the prescribed columns (eq. R4): f_ref gains -K_ap value_p
void ShellModel::add_prescribed_load(Assembly& a, int I, int si, int J, int sj, double k) const {
  const int row = dofs_.equation(I, si);
  if (!a.load || row < 0 || sj >= 3) return;
  const int p = prescribed_of_[3 * J + sj];
  if (p >= 0) (*a.load)[row] -= k * prescribed_[p].value;
}

// One assembly: every effect is a term of its own with its own counter (effect_stats()), in a
// fixed order so that sums never depend on which effects a scene has.
void ShellModel::evaluate(double lambda, Eigen::VectorXd& r, Eigen::SparseMatrix<double>* K, Eigen::VectorXd* load) {
  if (!prescribed_.empty()) apply_prescribed(lambda);
  r.setZero(size());
  if (load) load->setZero(size());
  if (K) pattern_.zeroed(*K);
  Assembly a{lambda, r, K, load, K ? K->valuePtr() : nullptr, load && !prescribed_.empty()};
  elastic_term(a);
  point_load_term(a);
  pressure_term(a, false);
  pressure_term(a, true);
  if (K && in_parts_) tangent_parts_.sum_shared(a.values);  // distributed.md (D4)
}

// (D1): the elements this rank evaluates, METIS's part of the mesh over the ranks sharing the solvers
// (alone: every element); made when first needed, again when the ranks or the elements change
const ElementShare& ShellModel::element_share() {
  if (!element_share_.made_for(elements_.size(), linear_solver_ranks()))
    element_share_ = ElementShare(elements_.connectivity(), static_cast<int>(state_.poses.size()), linear_solver_rank(),
                                  linear_solver_ranks());
  return element_share_;
}

const std::vector<int>* ShellModel::assemble_tangent_in_parts(bool on) {
  in_parts_ = on && linear_solver_ranks() > 1;
  if (!in_parts_) return nullptr;
  if (!tangent_parts_.built()) {
    const int nn = static_cast<int>(state_.poses.size());
    tangent_parts_ = TangentParts(static_cast<int>(pattern_.pattern().nonZeros()), nn, element_share());
    for (int k = 0; k < elements_.size(); ++k)
      tangent_parts_.add_element(k, scatter_[k].data(), 576, elements_[k].nodes.data(), 4);
    for (int I = 0; I < nn; ++I) tangent_parts_.add_node(I, node_scatter_[I].data(), 36);
    tangent_parts_.finish();
  }
  return &tangent_parts_.held();
}

// Elastic term (cb_shell.md (S15)-(S17); shell_model.md for the node bases): the element loop
// in parallel (each element writes only its own buffers), then a serial scatter in element order.
void ShellModel::elastic_term(Assembly& a) {
  const Clock::time_point t_elastic = Clock::now();
  const int nn = static_cast<int>(state_.poses.size());
  Eigen::VectorXd& r = a.r;
  Eigen::SparseMatrix<double>* K = a.K;
  double* values = a.values;
  const bool prescribed_load = a.prescribed_load;
  std::vector<Vec6>& node_force = work_.node_force;  // node-local internal force
  std::fill(node_force.begin(), node_force.end(), Vec6::Zero());
  // over MPI ranks each evaluates its share of the elements and the sums are added up below
  // (core/solve/distributed.md §2); alone, the share is every element
  const ElementShare& share = element_share();
  const std::vector<int>& mine = share.mine();
  elements_.for_each_of(threads_, mine, state_.poses, [&](int k, const ShellElement& e, const ElementPoses& cur) {
    {
      const bool tangent = K || (prescribed_load && element_prescribed_[k]);
      e.elastic->evaluate(cur, work_.element_force[k], tangent ? &work_.element_tangent[k] : nullptr);
      if (!tangent) return;
      // to solver rows here, in parallel
      to_solver_rows(e, work_.element_tangent[k]);
    }
  });
  for (const int k : mine) {
    const ShellElement& e = elements_[k];
    const Vec24& F = work_.element_force[k];
    for (int c = 0; c < 4; ++c) {  // node-local from corner-local: blockdiag(C, C)
      node_force[e.nodes[c]].head<3>() += e.corner[c] * F.segment<3>(6 * c);
      node_force[e.nodes[c]].tail<3>() += e.corner[c] * F.segment<3>(6 * c + 3);
    }
    const Mat24& Ke = work_.element_tangent[k];  // already in solver rows
    if (prescribed_load && element_prescribed_[k])
      for (int c = 0; c < 4; ++c)
        for (int i = 0; i < 6; ++i)
          for (int d = 0; d < 4; ++d)
            for (int j = 0; j < 3; ++j) add_prescribed_load(a, e.nodes[c], i, e.nodes[d], j, Ke(6 * c + i, 6 * d + j));
    if (!K) continue;
    const std::array<int, 576>& idx = scatter_[k];
    for (int r = 0; r < 24; ++r)
      for (int s = 0; s < 24; ++s) {
        const int v = idx[r * 24 + s];
        if (v >= 0) values[v] += Ke(r, s);
      }
  }
  if (share.shared()) {  // the other ranks' elements: every rank gets the sums
    sum_over_ranks(node_force.data()->data(), 6 * node_force.size());
    // in parts, only the interface entries, once every term is in (evaluate)
    if (K && !in_parts_) sum_over_ranks(values, static_cast<std::size_t>(K->nonZeros()));
    if (a.load) sum_over_ranks(a.load->data(), static_cast<std::size_t>(a.load->size()));
  }
  for (int I = 0; I < nn; ++I) {
    const Mat3& R_WN = state_.poses[I].R;
    const Vec3 fu = R_WN * node_force[I].head<3>();  // world components
    work_.reaction[I] = fu;
    Vec6 g;
    g.head<3>() = rows_u(I, fu);
    g.tail<3>() = six_dof_[I] ? rows_r(I, R_WN * node_force[I].tail<3>()) : Vec3(node_force[I].tail<3>());
    for (int s = 0; s < 6; ++s)
      if (dofs_.equation(I, s) >= 0) r[dofs_.equation(I, s)] += g[s];
    if (!K || !adds_node_tangent(I)) continue;
    // the rotating basis of A_I along the node's own rotation increment
    if (six_dof_[I]) {
      Mat3 tu = -hat(fu), tt = -hat(R_WN * node_force[I].tail<3>());
      if (has_basis_[I]) {
        tu = basis_u_[I].transpose() * tu * basis_r_[I];
        tt = basis_r_[I].transpose() * tt * basis_r_[I];
      }
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) add_to_node(a, I, i, 3 + j, tu(i, j)), add_to_node(a, I, 3 + i, 3 + j, tt(i, j));
    } else {
      Mat3 tu = -R_WN * hat(node_force[I].head<3>());
      if (has_basis_[I]) tu = basis_u_[I].transpose() * tu;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 2; ++j) add_to_node(a, I, i, 3 + j, tu(i, j));
    }
  }
  elastic_.evaluations += elements_.size();  // the model's, over all ranks
  ++assemblies_;
  elastic_.seconds += seconds_since(t_elastic);
}

// An element matrix in corner-local components turned into solver rows and columns: per 3 x 3
// block L_row m L_colᵀ, with L the corner's node rotation times its corner frame (translations;
// rotations of a 6-DoF node alike, of a 5-DoF node the corner frame alone), then the node's basis
// (shell_model.md): A_I blockdiag(C, C) is block diagonal in 3 x 3
void ShellModel::to_solver_rows(const ShellElement& e, Mat24& m) const {
  std::array<Mat3, 8> L;  // per corner: translations, rotations
  for (int c = 0; c < 4; ++c) {
    const int I = e.nodes[c];
    L[2 * c] = state_.poses[I].R * e.corner[c];
    L[2 * c + 1] = six_dof_[I] ? L[2 * c] : e.corner[c];
    if (has_basis_[I]) {
      L[2 * c + 1] = six_dof_[I] ? Mat3(basis_r_[I].transpose() * L[2 * c + 1]) : L[2 * c + 1];
      L[2 * c] = basis_u_[I].transpose() * L[2 * c];
    }
  }
  for (int row = 0; row < 8; ++row)
    for (int col = 0; col < 8; ++col) {
      const Mat3 blk = L[row] * m.block<3, 3>(3 * row, 3 * col);
      m.block<3, 3>(3 * row, 3 * col).noalias() = blk * L[col].transpose();
    }
}

void ShellModel::assemble_element_matrices(const std::function<void(int, const ElementPoses&, Mat24&)>& element_matrix,
                                           Eigen::SparseMatrix<double>& out) const {
  pattern_.zeroed(out);
  double* values = out.valuePtr();
  ElementPoses cur;
  Mat24 m;
  for (int k = 0; k < elements_.size(); ++k) {
    const ShellElement& e = elements_[k];
    ShellElements::corner_poses(e, state_.poses, cur);
    element_matrix(k, cur, m);
    to_solver_rows(e, m);  // the turns of elastic_term
    const std::array<int, 576>& idx = scatter_[k];
    for (int r = 0; r < 24; ++r)
      for (int s = 0; s < 24; ++s)
        if (idx[r * 24 + s] >= 0) values[idx[r * 24 + s]] += m(r, s);
  }
}

// Point loads: r -= lambda f (world or, follower, node-frame components) and their load stiffness.
void ShellModel::point_load_term(Assembly& a) {
  if (spec_.loads.empty()) return;
  const Clock::time_point t_loads = Clock::now();
  const double lambda = a.lambda;
  Eigen::VectorXd& r = a.r;
  Eigen::SparseMatrix<double>* K = a.K;
  Eigen::VectorXd* load = a.load;
  for (const NodalLoad& l : spec_.loads) {
    const int I = l.node;
    const Mat3& R_WN = state_.poses[I].R;
    const Vec3 f_W = l.follower ? Vec3(R_WN * l.force) : l.force;  // world components
    work_.reaction[I] -= lambda * f_W;
    Vec6 f = Vec6::Zero();
    f.head<3>() = rows_u(I, f_W);
    if (six_dof_[I]) {
      f.tail<3>() = rows_r(I, l.follower ? Vec3(R_WN * l.moment) : l.moment);
    } else {
      f.tail<3>() = l.follower ? l.moment : Vec3(R_WN.transpose() * l.moment);
      f[5] = 0.0;
    }
    for (int s = 0; s < 6; ++s) {
      const int a = dofs_.equation(I, s);
      if (a < 0) continue;
      r[a] -= lambda * f[s];
      if (load) (*load)[a] += f[s];
    }
    if (!K || !adds_node_tangent(I)) continue;
    if (l.follower) {
      Mat3 tf = six_dof_[I] ? Mat3(lambda * hat(R_WN * l.force)) : Mat3(lambda * R_WN * hat(l.force));
      if (has_basis_[I])
        tf = six_dof_[I] ? Mat3(basis_u_[I].transpose() * tf * basis_r_[I]) : Mat3(basis_u_[I].transpose() * tf);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < (six_dof_[I] ? 3 : 2); ++j) add_to_node(a, I, i, 3 + j, tf(i, j));
      if (six_dof_[I]) {
        Mat3 tm = lambda * hat(R_WN * l.moment);
        if (has_basis_[I]) tm = basis_r_[I].transpose() * tm * basis_r_[I];
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) add_to_node(a, I, 3 + i, 3 + j, tm(i, j));
      }
    } else if (!six_dof_[I]) {
      // local components of a fixed global moment turn with the node
      const Mat3 tm = -lambda * hat(R_WN.transpose() * l.moment);
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) add_to_node(a, I, 3 + i, 3 + j, tm(i, j));
    }
  }
  point_loads_.evaluations += static_cast<long long>(spec_.loads.size());
  point_loads_.seconds += seconds_since(t_loads);
}

// Pressures of one kind, dead or follower (shell_model.md (P1)-(P5)), each kind its own effect.
void ShellModel::pressure_term(Assembly& a, bool follower) {
  const long long count = follower ? follower_pressures_ : dead_pressures_;
  if (count == 0) return;
  const double lambda = a.lambda;
  Eigen::VectorXd& r = a.r;
  Eigen::SparseMatrix<double>* K = a.K;
  Eigen::VectorXd* load = a.load;
  double* values = a.values;
  const bool prescribed_load = a.prescribed_load;
  // pressure: nodal forces on translations only (world components along the node bases), so the
  // follower load stiffness -lambda df/dx needs no rotating-basis term (shell_model.md eq. P3).
  // Dead pressures first, then follower ones (each timed as its own effect).
  auto apply_pressure = [&](std::size_t k) {
    const PressureLoad& pl = spec_.pressures[k];
    const std::array<int, 4>& q = elements_[pl.quad].nodes;
    std::array<Vec3, 4> f;
    std::array<Mat3, 16> dfdx;
    const bool with_stiffness = pl.follower && (K || prescribed_load);
    if (pl.follower) {
      std::array<Vec3, 4> p_WN;
      for (int c = 0; c < 4; ++c) p_WN[c] = state_.poses[q[c]].p;
      pressure_forces(p_WN, pl.pressure, f, with_stiffness ? &dfdx : nullptr);
    } else {
      f = dead_pressure_[k];
    }
    for (int c = 0; c < 4; ++c) {
      work_.reaction[q[c]] -= lambda * f[c];
      const Vec3 fs = rows_u(q[c], f[c]);
      for (int s = 0; s < 3; ++s) {
        const int a = dofs_.equation(q[c], s);
        if (a < 0) continue;
        r[a] -= lambda * fs[s];
        if (load) (*load)[a] += fs[s];
      }
    }
    if (!with_stiffness) return;
    const std::array<int, 576>& idx = scatter_[pl.quad];
    const bool adds_stiffness = adds_element_tangent(pl.quad);  // in parts: its rank's
    for (int c = 0; c < 4; ++c)
      for (int d = 0; d < 4; ++d) {
        const Mat3 b = block_uu(q[c], dfdx[4 * c + d], q[d]);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            if (prescribed_load) add_prescribed_load(a, q[c], i, q[d], j, -lambda * b(i, j));
            const int v = K && adds_stiffness ? idx[(6 * c + i) * 24 + 6 * d + j] : -1;
            if (v >= 0) values[v] -= lambda * b(i, j);
          }
      }
  };
  const Clock::time_point t_pressure = Clock::now();
  for (std::size_t k = 0; k < spec_.pressures.size(); ++k)
    if (spec_.pressures[k].follower == follower) apply_pressure(k);
  assembly::EffectCounter& counter = follower ? follower_pressure_stat_ : dead_pressure_stat_;
  counter.evaluations += count;
  counter.seconds += seconds_since(t_pressure);
}

std::vector<EffectStat> ShellModel::effect_stats() const {
  std::vector<EffectStat> out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const long long element_evaluations = assemblies_ * static_cast<long long>(elements_.size());
  if (elastic_.evaluations) out.push_back({"elastic", elastic_.evaluations, elastic_.seconds, {}});
  // formulation terms of the element, fused in its kernel (cb_shell.cpp): counted, timed in elastic
  if (spec_.options.hr && element_evaluations) out.push_back({"hr", element_evaluations, nan, "elastic"});
  if (spec_.options.ans && element_evaluations) out.push_back({"ans", element_evaluations, nan, "elastic"});
  if (spec_.options.drilling && element_evaluations) out.push_back({"drilling", element_evaluations, nan, "elastic"});
  if (point_loads_.evaluations) out.push_back({"point_loads", point_loads_.evaluations, point_loads_.seconds, {}});
  if (dead_pressure_stat_.evaluations)
    out.push_back({"pressure_dead", dead_pressure_stat_.evaluations, dead_pressure_stat_.seconds, {}});
  if (follower_pressure_stat_.evaluations)
    out.push_back({"pressure_follower", follower_pressure_stat_.evaluations, follower_pressure_stat_.seconds, {}});
  return out;
}

bool ShellModel::tangent_symmetric_at_equilibrium() const {
  for (const NodalLoad& l : spec_.loads)
    if (l.follower || l.moment.squaredNorm() > 0.0) return false;
  for (const PressureLoad& p : spec_.pressures)
    if (p.follower) return false;
  return true;
}

void ShellModel::update(const Eigen::VectorXd& delta) {
  const int nn = static_cast<int>(state_.poses.size());
  std::vector<Vec6> d(nn, Vec6::Zero());
  for (int k = 0; k < size(); ++k) d[dofs_.unknown(k).node][dofs_.unknown(k).slot] += delta[k];
  for (int I = 0; I < nn; ++I) {
    // eq. R2: slot increments along the node bases
    if (has_basis_[I]) {
      d[I].head<3>() = basis_u_[I] * d[I].head<3>();
      if (six_dof_[I]) d[I].tail<3>() = basis_r_[I] * d[I].tail<3>();
    }
    state_.poses[I].p += d[I].head<3>();
    if (six_dof_[I]) state_.poses[I].R = lie::exp_so3(d[I].tail<3>()) * state_.poses[I].R;
    else state_.poses[I].R = state_.poses[I].R * lie::exp_so3(Vec3(d[I][3], d[I][4], 0.0));
  }
}

std::vector<double> ShellModel::nodal_surface_strain() const {
  return shell::nodal_surface_strain(elements_.all(), reference_, state_.poses,
                                     [](const ShellElement& e) { return e.thickness; });
}

}  // namespace ff::shell
