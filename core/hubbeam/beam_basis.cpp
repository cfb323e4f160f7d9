#include "core/hubbeam/beam_basis.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/solve/gauss.h"

namespace ff::hubbeam {

ShapeRows BeamBasis::make_rows() const {
  const int n = node_count();
  ShapeRows rows;
  rows.n1 = Eigen::RowVectorXd::Zero(n);
  rows.dn1 = Eigen::RowVectorXd::Zero(n);
  rows.n2 = Eigen::RowVectorXd::Zero(2 * n);
  rows.dn2 = Eigen::RowVectorXd::Zero(2 * n);
  rows.ddn2 = Eigen::RowVectorXd::Zero(2 * n);
  return rows;
}

// hub_beam.md eq. (18): the cubic spline of the hub-beam paper (Xie & Jian 2017), C2 at r = 1/2
// and r = 1
void cubic_spline_weight(double r, double& w, double& dw, double& ddw) {
  if (r <= 0.5) {
    w = 2.0 / 3.0 - 4.0 * r * r + 4.0 * r * r * r;
    dw = -8.0 * r + 12.0 * r * r;
    ddw = -8.0 + 24.0 * r;
  } else if (r <= 1.0) {
    w = 4.0 / 3.0 - 4.0 * r + 4.0 * r * r - 4.0 / 3.0 * r * r * r;
    dw = -4.0 + 8.0 * r - 4.0 * r * r;
    ddw = 8.0 - 8.0 * r;
  } else {
    w = dw = ddw = 0.0;
  }
}

namespace {

std::vector<double> uniform_nodes(double length, int count) {
  std::vector<double> x(count);
  for (int i = 0; i < count; ++i) x[i] = length * i / (count - 1);
  return x;
}

// ---------------------------------------------------------------- EFG (IGMLS + IMLS)
class EfgBasis final : public BeamBasis {
 public:
  EfgBasis(double length, const EfgOptions& o) : length_(length), opt_(o) {
    if (o.nodes < 3) throw std::invalid_argument("EFG needs at least 3 nodes");
    x_ = uniform_nodes(length, o.nodes);
    const int n = o.nodes;
    support_.resize(n);
    for (int i = 0; i < n; ++i) {
      double c = 1e300;  // c_I: distance to the nearest other node
      for (int j = 0; j < n; ++j)
        if (j != i) c = std::min(c, std::abs(x_[i] - x_[j]));
      support_[i] = o.scale * c;
    }
    // eq. (22): Lambda from the raw GMLS rows at the nodes, then invert once
    Eigen::MatrixXd lambda(2 * n, 2 * n), lambda1(n, n);
    Eigen::RowVectorXd phi(2 * n), dphi(2 * n), ddphi(2 * n), phi1(n), dphi1(n);
    for (int j = 0; j < n; ++j) {
      raw_transverse(x_[j], phi, dphi, ddphi);
      lambda.row(j) = phi;
      lambda.row(n + j) = dphi;
      raw_axial(x_[j], phi1, dphi1);
      lambda1.row(j) = phi1;
    }
    Eigen::FullPivLU<Eigen::MatrixXd> lu(lambda), lu1(lambda1);
    if (!lu.isInvertible() || !lu1.isInvertible())
      throw std::invalid_argument(
          "EFG: the interpolating transform Lambda is singular; increase efg.scale or the node count");
    lambda_inv_ = lu.inverse();
    lambda1_inv_ = lu1.inverse();
  }

  int node_count() const override { return opt_.nodes; }
  double length() const override { return length_; }
  const std::vector<double>& nodes() const override { return x_; }
  std::string name() const override { return "efg"; }

  void evaluate(double x, ShapeRows& rows) const override {
    const int n = opt_.nodes;
    Eigen::RowVectorXd phi(2 * n), dphi(2 * n), ddphi(2 * n), phi1(n), dphi1(n);
    raw_transverse(x, phi, dphi, ddphi);
    rows.n2.noalias() = phi * lambda_inv_;  // eq. (22)
    rows.dn2.noalias() = dphi * lambda_inv_;
    rows.ddn2.noalias() = ddphi * lambda_inv_;
    raw_axial(x, phi1, dphi1);
    rows.n1.noalias() = phi1 * lambda1_inv_;  // eq. (23)
    rows.dn1.noalias() = dphi1 * lambda1_inv_;
  }

  void check_points(const std::vector<double>& xs) const override {
    const int n = opt_.nodes;
    Eigen::RowVectorXd phi(2 * n), dphi(2 * n), ddphi(2 * n), phi1(n), dphi1(n);
    for (double x : xs) {
      raw_transverse(x, phi, dphi, ddphi);
      raw_axial(x, phi1, dphi1);
    }
  }

  std::vector<QuadraturePoint> quadrature() const override {
    const int cells = opt_.cells > 0 ? opt_.cells : opt_.nodes - 1;
    const GaussRule rule = gauss_legendre(opt_.gauss_points);
    std::vector<QuadraturePoint> q;
    const double h = length_ / cells;
    for (int c = 0; c < cells; ++c)
      for (std::size_t g = 0; g < rule.points.size(); ++g)
        q.push_back({h * (c + 0.5 * (rule.points[g] + 1.0)), 0.5 * h * rule.weights[g]});
    return q;
  }

 private:
  // monomials in xi = y / L and their y-derivatives
  void basis(double y, int order, Eigen::VectorXd& p, Eigen::VectorXd& dp, Eigen::VectorXd& ddp) const {
    const int m = order + 1;
    p.setZero(m);
    dp.setZero(m);
    ddp.setZero(m);
    const double xi = y / length_;
    for (int k = 0; k < m; ++k) {
      p[k] = std::pow(xi, k);
      if (k >= 1) dp[k] = k * std::pow(xi, k - 1) / length_;
      if (k >= 2) ddp[k] = k * (k - 1) * std::pow(xi, k - 2) / (length_ * length_);
    }
  }

  void weight(int node, double x, double& w, double& wx, double& wxx) const {
    const double d = support_[node];
    const double s = x - x_[node];
    double dw, ddw;
    cubic_spline_weight(std::abs(s) / d, w, dw, ddw);
    wx = dw * (s >= 0 ? 1.0 : -1.0) / d;
    wxx = ddw / (d * d);
  }

  [[noreturn]] void singular(double x, const char* field, int order) const {
    std::ostringstream msg;
    msg << "EFG: the " << field << " moment matrix is singular at x = " << x
        << " m: too few nodes in the support for a basis of degree " << order
        << " (efg.scale = " << opt_.scale << "); increase efg.scale or lower the basis order";
    throw std::invalid_argument(msg.str());
  }

  // eqs. (19)-(21): generalized MLS on values and slopes
  void raw_transverse(double x, Eigen::RowVectorXd& phi, Eigen::RowVectorXd& dphi,
                      Eigen::RowVectorXd& ddphi) const {
    const int n = opt_.nodes, m = opt_.basis_order + 1;
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m, m), da = a, dda = a;
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(m, 2 * n), db = b, ddb = b;
    Eigen::VectorXd pi, dpi, ddpi;
    for (int i = 0; i < n; ++i) {
      double w, wx, wxx;
      weight(i, x, w, wx, wxx);
      if (w == 0.0 && wx == 0.0 && wxx == 0.0) continue;
      basis(x_[i], opt_.basis_order, pi, dpi, ddpi);
      const Eigen::MatrixXd outer = pi * pi.transpose() + dpi * dpi.transpose();
      a += w * outer;
      da += wx * outer;
      dda += wxx * outer;
      b.col(i) = w * pi;
      b.col(n + i) = w * dpi;
      db.col(i) = wx * pi;
      db.col(n + i) = wx * dpi;
      ddb.col(i) = wxx * pi;
      ddb.col(n + i) = wxx * dpi;
    }
    Eigen::VectorXd p, dp, ddp;
    basis(x, opt_.basis_order, p, dp, ddp);
    Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
    if (lu.rank() < m || lu.rcond() < 1e-13) singular(x, "transverse", opt_.basis_order);
    const Eigen::VectorXd g = lu.solve(p);
    const Eigen::VectorXd dg = lu.solve(dp - da * g);
    const Eigen::VectorXd ddg = lu.solve(ddp - 2.0 * da * dg - dda * g);
    phi = g.transpose() * b;
    dphi = dg.transpose() * b + g.transpose() * db;
    ddphi = ddg.transpose() * b + 2.0 * dg.transpose() * db + g.transpose() * ddb;
  }

  // eq. (23): MLS on values only (then made interpolating through Lambda1)
  void raw_axial(double x, Eigen::RowVectorXd& phi, Eigen::RowVectorXd& dphi) const {
    const int n = opt_.nodes, m = opt_.axial_basis_order + 1;
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m, m), da = a;
    Eigen::MatrixXd b = Eigen::MatrixXd::Zero(m, n), db = b;
    Eigen::VectorXd pi, dpi, ddpi;
    for (int i = 0; i < n; ++i) {
      double w, wx, wxx;
      weight(i, x, w, wx, wxx);
      if (w == 0.0 && wx == 0.0) continue;
      basis(x_[i], opt_.axial_basis_order, pi, dpi, ddpi);
      a += w * pi * pi.transpose();
      da += wx * pi * pi.transpose();
      b.col(i) = w * pi;
      db.col(i) = wx * pi;
    }
    Eigen::VectorXd p, dp, ddp;
    basis(x, opt_.axial_basis_order, p, dp, ddp);
    Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
    if (lu.rank() < m || lu.rcond() < 1e-13) singular(x, "axial", opt_.axial_basis_order);
    const Eigen::VectorXd g = lu.solve(p);
    const Eigen::VectorXd dg = lu.solve(dp - da * g);
    phi = g.transpose() * b;
    dphi = dg.transpose() * b + g.transpose() * db;
  }

  double length_;
  EfgOptions opt_;
  std::vector<double> x_, support_;
  Eigen::MatrixXd lambda_inv_, lambda1_inv_;
};

// ---------------------------------------------------------------- FEM (Hermite + linear)
class FemBasis final : public BeamBasis {
 public:
  FemBasis(double length, const FemOptions& o) : length_(length), opt_(o) {
    if (o.elements < 1) throw std::invalid_argument("FEM needs at least one element");
    x_ = uniform_nodes(length, o.elements + 1);
  }
  int node_count() const override { return opt_.elements + 1; }
  double length() const override { return length_; }
  const std::vector<double>& nodes() const override { return x_; }
  std::string name() const override { return "fem"; }

  void evaluate(double x, ShapeRows& rows) const override {
    const int n = node_count(), ne = opt_.elements;
    const double h = length_ / ne;
    int e = static_cast<int>(std::floor(x / h));
    e = std::clamp(e, 0, ne - 1);
    const double s = (x - e * h) / h;
    rows.n1.setZero();
    rows.dn1.setZero();
    rows.n2.setZero();
    rows.dn2.setZero();
    rows.ddn2.setZero();
    // eq. (24)
    rows.n1[e] = 1.0 - s;
    rows.n1[e + 1] = s;
    rows.dn1[e] = -1.0 / h;
    rows.dn1[e + 1] = 1.0 / h;
    const int v0 = e, v1 = e + 1, t0 = n + e, t1 = n + e + 1;
    rows.n2[v0] = 1.0 - 3.0 * s * s + 2.0 * s * s * s;
    rows.n2[t0] = h * (s - 2.0 * s * s + s * s * s);
    rows.n2[v1] = 3.0 * s * s - 2.0 * s * s * s;
    rows.n2[t1] = h * (s * s * s - s * s);
    rows.dn2[v0] = (-6.0 * s + 6.0 * s * s) / h;
    rows.dn2[t0] = 1.0 - 4.0 * s + 3.0 * s * s;
    rows.dn2[v1] = (6.0 * s - 6.0 * s * s) / h;
    rows.dn2[t1] = 3.0 * s * s - 2.0 * s;
    rows.ddn2[v0] = (-6.0 + 12.0 * s) / (h * h);
    rows.ddn2[t0] = (-4.0 + 6.0 * s) / h;
    rows.ddn2[v1] = (6.0 - 12.0 * s) / (h * h);
    rows.ddn2[t1] = (6.0 * s - 2.0) / h;
  }

  std::vector<QuadraturePoint> quadrature() const override {
    const GaussRule rule = gauss_legendre(opt_.gauss_points);
    const double h = length_ / opt_.elements;
    std::vector<QuadraturePoint> q;
    for (int e = 0; e < opt_.elements; ++e)
      for (std::size_t g = 0; g < rule.points.size(); ++g)
        q.push_back({h * (e + 0.5 * (rule.points[g] + 1.0)), 0.5 * h * rule.weights[g]});
    return q;
  }

 private:
  double length_;
  FemOptions opt_;
  std::vector<double> x_;
};

}  // namespace

std::unique_ptr<BeamBasis> make_efg_basis(double length, const EfgOptions& options) {
  return std::make_unique<EfgBasis>(length, options);
}
std::unique_ptr<BeamBasis> make_fem_basis(double length, const FemOptions& options) {
  return std::make_unique<FemBasis>(length, options);
}

}  // namespace ff::hubbeam
