#include "core/shell/shell_model.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/shell/surface_strain.h"

namespace ff::shell {

namespace {
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Clock = std::chrono::steady_clock;

double seconds_between(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double>(b - a).count(); }

Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}
Mat3 exp_so3(const Vec3& th) {
  const double a = th.norm();
  return a < 1e-300 ? Mat3::Identity() : Eigen::AngleAxisd(a, th / a).toRotationMatrix();
}
// the rotation taking unit a to unit b about their common normal
Mat3 align(const Vec3& a, const Vec3& b) {
  const Vec3 axis = a.cross(b);
  const double s = axis.norm(), c = a.dot(b);
  return s < 1e-14 ? Mat3::Identity() : exp_so3(axis / s * std::atan2(s, c));
}

// p (g_xi x g_eta) over the bilinear quad x[0..3] by 2x2 Gauss (exact: the integrand is
// biquadratic), eq. P2 of shell_model.md: f_a = p sum_g N_a (g_xi x g_eta). With dfdx, also
// df_a/dx_b = p sum_g N_a (N_b,eta [g_xi]x - N_b,xi [g_eta]x) (eq. P3), 3x3 block (a, b) at dfdx[4a + b].
void pressure_forces(const std::array<Vec3, 4>& x, double p, std::array<Vec3, 4>& f, std::array<Mat3, 16>* dfdx) {
  static const double xa[4] = {-1, 1, 1, -1}, ya[4] = {-1, -1, 1, 1};
  const double g = 1.0 / std::sqrt(3.0);
  for (Vec3& v : f) v.setZero();
  if (dfdx)
    for (Mat3& m : *dfdx) m.setZero();
  for (int gi = 0; gi < 4; ++gi) {
    const double xi = xa[gi] * g, eta = ya[gi] * g;  // weights are 1
    double N[4], Nx[4], Ne[4];
    Vec3 gx = Vec3::Zero(), ge = Vec3::Zero();
    for (int a = 0; a < 4; ++a) {
      N[a] = 0.25 * (1 + xa[a] * xi) * (1 + ya[a] * eta);
      Nx[a] = 0.25 * xa[a] * (1 + ya[a] * eta);
      Ne[a] = 0.25 * ya[a] * (1 + xa[a] * xi);
      gx += Nx[a] * x[a];
      ge += Ne[a] * x[a];
    }
    const Vec3 n = gx.cross(ge);
    for (int a = 0; a < 4; ++a) f[a] += p * N[a] * n;
    if (!dfdx) continue;
    const Mat3 Sx = skew(gx), Se = skew(ge);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) (*dfdx)[4 * a + b] += p * N[a] * (Ne[b] * Sx - Nx[b] * Se);
  }
}
}  // namespace

ShellModel::ShellModel(ShellModelSpec spec) : spec_(std::move(spec)) {
  mesh::ShellMesh& m = spec_.mesh;
  const int nn = m.node_count();
  six_.assign(nn, spec_.options.drilling ? 1 : 0);
  for (int i = 0; i < nn && i < static_cast<int>(m.fold.size()); ++i)
    if (m.fold[i]) six_[i] = 1;
  std::vector<unsigned> fixed(nn, 0u);  // slot mask, bits 0-5
  auto node_name = [](int i) { return "node " + std::to_string(i); };

  // symmetry planes: translation along the normal and rotations off the normal are restrained
  for (const auto& [node, axis] : spec_.symmetry) {
    const Vec3 n = Vec3::Unit(axis);
    fixed[node] |= 1u << axis;
    if (six_[node]) {
      for (int k = 0; k < 3; ++k)
        if (k != axis) fixed[node] |= 1u << (3 + k);
    } else {
      Mat3& R0 = m.frames[node];
      const Vec3 e3 = R0.col(2);
      if (std::abs(n.dot(e3)) > 1e-6)
        throw std::invalid_argument(node_name(node) + " lies on a symmetry plane its director crosses (normal . "
                                    "director = " + std::to_string(n.dot(e3)) + "); a symmetry plane must contain the director");
      R0 << n, e3.cross(n), e3;  // e1 = plane normal: the exact restraint is then theta_2 = 0
      fixed[node] |= 1u << 4;
    }
  }
  for (const auto& [node, mask] : spec_.restraints) {
    fixed[node] |= mask & kAllTranslations;
    const unsigned rot = (mask & kAllRotations) >> 3;
    if (!rot) continue;
    if (six_[node]) {
      fixed[node] |= rot << 3;
    } else if (rot == 7) {
      fixed[node] |= (1u << 3) | (1u << 4);
    } else {
      throw std::invalid_argument(node_name(node) + " has 5 DoFs (no drilling effect): a restraint on rotation about "
                                  "a single global axis cannot be exact there; clamp all rotations, use a symmetry "
                                  "plane, or enable the drilling effect (6 DoFs)");
    }
  }
  eq_.assign(6 * nn, -1);
  for (int i = 0; i < nn; ++i)
    for (int s = 0; s < (six_[i] ? 6 : 5); ++s)
      if (!(fixed[i] & (1u << s))) {
        eq_[6 * i + s] = static_cast<int>(free_.size());
        free_.push_back({i, s});
      }

  poses_.resize(nn);
  for (int i = 0; i < nn; ++i) poses_[i] = {m.frames[i], m.points[i]};
  saved_ = poses_;
  reference_ = poses_;
  elements_.reserve(m.quad_count());
  for (int q = 0; q < m.quad_count(); ++q) {
    Element e;
    e.nodes = m.quads[q];
    ElementPoses ref;
    for (int c = 0; c < 4; ++c) {
      const int I = e.nodes[c];
      const Vec3 nc = q < static_cast<int>(m.corner_normals.size()) ? m.corner_normals[q][c] : m.normals[I];
      // a fold corner has its own director; C maps node-local increments to corner-local ones
      const Mat3 Rc = align(m.frames[I].col(2), nc.normalized()) * m.frames[I];
      e.corner[c] = m.frames[I].transpose() * Rc;
      ref[c] = {Rc, m.points[I]};
    }
    e.el = std::make_unique<CbShellElement>(ref, spec_.section, spec_.options);
    elements_.push_back(std::move(e));
  }
  Vec3 lo = m.points.front(), hi = lo;
  for (const Vec3& p : m.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  rotation_scale_ = 0.1 * (hi - lo).norm();
  dead_pressure_.resize(spec_.pressures.size());
  for (std::size_t k = 0; k < spec_.pressures.size(); ++k) {
    const PressureLoad& pl = spec_.pressures[k];
    if (pl.quad < 0 || pl.quad >= m.quad_count())
      throw std::invalid_argument("pressure on quad " + std::to_string(pl.quad) + ", but the mesh has " +
                                  std::to_string(m.quad_count()) + " quads");
    ++(pl.follower ? follower_pressures_ : dead_pressures_);
    if (pl.follower) continue;  // evaluated in the current configuration instead
    std::array<Vec3, 4> x;
    for (int c = 0; c < 4; ++c) x[c] = m.points[m.quads[pl.quad][c]];
    pressure_forces(x, pl.pressure, dead_pressure_[k], nullptr);
  }
  build_pattern();
}

int ShellModel::value_index(int row, int col) const {
  const int* inner = pattern_.innerIndexPtr();
  const int* begin = inner + pattern_.outerIndexPtr()[col];
  const int* end = inner + pattern_.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, row);
  return (it != end && *it == row) ? static_cast<int>(it - inner) : -1;
}

void ShellModel::build_pattern() {
  const int n = size(), nn = static_cast<int>(poses_.size());
  std::vector<Eigen::Triplet<double>> trip;
  for (const Element& e : elements_)
    for (int c = 0; c < 4; ++c)
      for (int d = 0; d < 4; ++d)
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < 6; ++j) {
            const int a = eq_[6 * e.nodes[c] + i], b = eq_[6 * e.nodes[d] + j];
            if (a >= 0 && b >= 0) trip.emplace_back(a, b, 1.0);
          }
  for (int I = 0; I < nn; ++I)  // node blocks (rotating-basis and load terms)
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) {
        const int a = eq_[6 * I + i], b = eq_[6 * I + j];
        if (a >= 0 && b >= 0) trip.emplace_back(a, b, 1.0);
      }
  pattern_.resize(n, n);
  pattern_.setFromTriplets(trip.begin(), trip.end());
  pattern_.makeCompressed();
  scatter_.resize(elements_.size());
  for (std::size_t k = 0; k < elements_.size(); ++k) {
    const Element& e = elements_[k];
    for (int c = 0; c < 4; ++c)
      for (int d = 0; d < 4; ++d)
        for (int i = 0; i < 6; ++i)
          for (int j = 0; j < 6; ++j) {
            const int a = eq_[6 * e.nodes[c] + i], b = eq_[6 * e.nodes[d] + j];
            scatter_[k][(6 * c + i) * 24 + 6 * d + j] = (a >= 0 && b >= 0) ? value_index(a, b) : -1;
          }
  }
  el_force_.resize(elements_.size());
  el_tangent_.resize(elements_.size());
}

void ShellModel::evaluate(double lambda, Eigen::VectorXd& r, Eigen::SparseMatrix<double>* K, Eigen::VectorXd* load) {
  // effect timing: one clock pair per effect and assembly, none inside the element loop
  const Clock::time_point t_elastic = Clock::now();
  const int n = size(), nn = static_cast<int>(poses_.size());
  r.setZero(n);
  if (load) load->setZero(n);
  if (K) {
    *K = pattern_;
    std::fill(K->valuePtr(), K->valuePtr() + K->nonZeros(), 0.0);
  }
  double* values = K ? K->valuePtr() : nullptr;
  std::vector<Vec6> node_force(nn, Vec6::Zero());  // node-local internal force
  // A_I maps node-local 6-vectors to solver rows (global translations; global or local rotations)
  auto A = [&](int I) {
    Mat6 a = Mat6::Zero();
    a.topLeftCorner<3, 3>() = poses_[I].R;
    a.bottomRightCorner<3, 3>() = six_[I] ? poses_[I].R : Mat3::Identity();
    return a;
  };
  auto add = [&](int I, int si, int J, int sj, double v) {
    const int a = eq_[6 * I + si], b = eq_[6 * J + sj];
    if (a >= 0 && b >= 0 && v != 0.0) values[value_index(a, b)] += v;
  };
  // elements in parallel (each writes only its own buffers), then a serial scatter
  const int ne = static_cast<int>(elements_.size());
#pragma omp parallel for schedule(static)
  for (int k = 0; k < ne; ++k) {
    const Element& e = elements_[k];
    ElementPoses cur;
    for (int c = 0; c < 4; ++c) cur[c] = {poses_[e.nodes[c]].R * e.corner[c], poses_[e.nodes[c]].x};
    e.el->evaluate(cur, el_force_[k], K ? &el_tangent_[k] : nullptr);
    if (!K) continue;
    // to solver rows here, in parallel: A_I blockdiag(C, C) is block diagonal in 3 x 3
    std::array<Mat3, 8> L;  // per corner: translations, rotations
    for (int c = 0; c < 4; ++c) {
      const int I = e.nodes[c];
      L[2 * c] = poses_[I].R * e.corner[c];
      L[2 * c + 1] = six_[I] ? L[2 * c] : e.corner[c];
    }
    Mat24& Ke = el_tangent_[k];
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b) {
        const Mat3 blk = L[a] * Ke.block<3, 3>(3 * a, 3 * b);
        Ke.block<3, 3>(3 * a, 3 * b).noalias() = blk * L[b].transpose();
      }
  }
  for (int k = 0; k < ne; ++k) {
    const Element& e = elements_[k];
    const Vec24& F = el_force_[k];
    for (int c = 0; c < 4; ++c) {  // node-local from corner-local: blockdiag(C, C)
      node_force[e.nodes[c]].head<3>() += e.corner[c] * F.segment<3>(6 * c);
      node_force[e.nodes[c]].tail<3>() += e.corner[c] * F.segment<3>(6 * c + 3);
    }
    if (!K) continue;
    const Mat24& Ke = el_tangent_[k];  // already in solver rows
    const std::array<int, 576>& idx = scatter_[k];
    for (int r = 0; r < 24; ++r)
      for (int s = 0; s < 24; ++s) {
        const int v = idx[r * 24 + s];
        if (v >= 0) values[v] += Ke(r, s);
      }
  }
  for (int I = 0; I < nn; ++I) {
    const Vec6 g = A(I) * node_force[I];
    for (int s = 0; s < 6; ++s)
      if (eq_[6 * I + s] >= 0) r[eq_[6 * I + s]] += g[s];
    if (!K) continue;
    // the rotating basis of A_I along the node's own rotation increment
    const Mat3& R = poses_[I].R;
    if (six_[I]) {
      const Mat3 tu = -skew(R * node_force[I].head<3>()), tt = -skew(R * node_force[I].tail<3>());
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) add(I, i, I, 3 + j, tu(i, j)), add(I, 3 + i, I, 3 + j, tt(i, j));
    } else {
      const Mat3 tu = -R * skew(node_force[I].head<3>());
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 2; ++j) add(I, i, I, 3 + j, tu(i, j));
    }
  }
  elastic_.evaluations += ne;
  ++assemblies_;
  const Clock::time_point t_loads = Clock::now();
  elastic_.seconds += seconds_between(t_elastic, t_loads);
  // external loads: r -= lambda f_ext
  for (const NodalLoad& l : spec_.loads) {
    const int I = l.node;
    const Mat3& R = poses_[I].R;
    Vec6 f = Vec6::Zero();
    f.head<3>() = l.follower ? Vec3(R * l.force) : l.force;
    if (six_[I]) {
      f.tail<3>() = l.follower ? Vec3(R * l.moment) : l.moment;
    } else {
      f.tail<3>() = l.follower ? l.moment : Vec3(R.transpose() * l.moment);
      f[5] = 0.0;
    }
    for (int s = 0; s < 6; ++s) {
      const int a = eq_[6 * I + s];
      if (a < 0) continue;
      r[a] -= lambda * f[s];
      if (load) (*load)[a] += f[s];
    }
    if (!K) continue;
    if (l.follower) {
      const Mat3 tf = six_[I] ? Mat3(lambda * skew(R * l.force)) : Mat3(lambda * R * skew(l.force));
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < (six_[I] ? 3 : 2); ++j) add(I, i, I, 3 + j, tf(i, j));
      if (six_[I]) {
        const Mat3 tm = lambda * skew(R * l.moment);
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) add(I, 3 + i, I, 3 + j, tm(i, j));
      }
    } else if (!six_[I]) {
      // local components of a fixed global moment turn with the node
      const Mat3 tm = -lambda * skew(R.transpose() * l.moment);
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j) add(I, 3 + i, I, 3 + j, tm(i, j));
    }
  }
  if (!spec_.loads.empty()) {
    point_loads_.evaluations += static_cast<long long>(spec_.loads.size());
    point_loads_.seconds += seconds_between(t_loads, Clock::now());
  }
  // pressure: nodal forces on translations only (global components, global increments), so the
  // follower load stiffness -lambda df/dx needs no rotating-basis term (shell_model.md eq. P3).
  // Dead pressures first, then follower ones (each timed as its own effect).
  auto apply_pressure = [&](std::size_t k) {
    const PressureLoad& pl = spec_.pressures[k];
    const std::array<int, 4>& q = elements_[pl.quad].nodes;
    std::array<Vec3, 4> f;
    std::array<Mat3, 16> dfdx;
    if (pl.follower) {
      std::array<Vec3, 4> x;
      for (int c = 0; c < 4; ++c) x[c] = poses_[q[c]].x;
      pressure_forces(x, pl.pressure, f, K ? &dfdx : nullptr);
    } else {
      f = dead_pressure_[k];
    }
    for (int c = 0; c < 4; ++c)
      for (int s = 0; s < 3; ++s) {
        const int a = eq_[6 * q[c] + s];
        if (a < 0) continue;
        r[a] -= lambda * f[c][s];
        if (load) (*load)[a] += f[c][s];
      }
    if (!K || !pl.follower) return;
    const std::array<int, 576>& idx = scatter_[pl.quad];
    for (int c = 0; c < 4; ++c)
      for (int d = 0; d < 4; ++d)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) {
            const int v = idx[(6 * c + i) * 24 + 6 * d + j];
            if (v >= 0) values[v] -= lambda * dfdx[4 * c + d](i, j);
          }
  };
  for (const bool follower : {false, true}) {
    const long long count = follower ? follower_pressures_ : dead_pressures_;
    if (count == 0) continue;
    const Clock::time_point t_pressure = Clock::now();
    for (std::size_t k = 0; k < spec_.pressures.size(); ++k)
      if (spec_.pressures[k].follower == follower) apply_pressure(k);
    Counter& counter = follower ? follower_pressure_stat_ : dead_pressure_stat_;
    counter.evaluations += count;
    counter.seconds += seconds_between(t_pressure, Clock::now());
  }
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

void ShellModel::update(const Eigen::VectorXd& delta) {
  const int nn = static_cast<int>(poses_.size());
  std::vector<Vec6> d(nn, Vec6::Zero());
  for (int k = 0; k < size(); ++k) d[free_[k].node][free_[k].slot] += delta[k];
  for (int I = 0; I < nn; ++I) {
    poses_[I].x += d[I].head<3>();
    if (six_[I]) poses_[I].R = exp_so3(d[I].tail<3>()) * poses_[I].R;
    else poses_[I].R = poses_[I].R * exp_so3(Vec3(d[I][3], d[I][4], 0.0));
  }
}

std::vector<double> ShellModel::nodal_surface_strain() const {
  return shell::nodal_surface_strain(elements_, reference_, poses_,
                                     [this](const Element& e) { return spec_.section.thickness; });
}

}  // namespace ff::shell
