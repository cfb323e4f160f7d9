#pragma once
/// \file beam_basis.h
/// Shape functions of the flexible beam of the hub-beam system (see hub_beam.md §6, §7).
/// Axial row N1 (1 x N, acting on q1 = nodal axial displacements) and transverse row
/// N2 (1 x 2N, acting on q2 = [v_1..v_N, theta_1..theta_N]). x is the undeformed abscissa
/// from the beam root, in metres.

#include <Eigen/Dense>
#include <memory>
#include <string>
#include <vector>

namespace ff::hubbeam {

/// Values and derivatives of the shape rows at one abscissa.
struct ShapeRows {
  Eigen::RowVectorXd n1, dn1;            ///< N1, dN1/dx            (1 x N)
  Eigen::RowVectorXd n2, dn2, ddn2;      ///< N2, dN2/dx, d2N2/dx2  (1 x 2N)
};

/// Integration point of the Galerkin integrals over [0, L].
struct QuadraturePoint {
  double x;       ///< abscissa [m]
  double weight;  ///< weight including the cell Jacobian [m]
};

class BeamBasis {
 public:
  virtual ~BeamBasis() = default;
  virtual int node_count() const = 0;
  virtual double length() const = 0;
  virtual const std::vector<double>& nodes() const = 0;
  /// Fills `rows` at abscissa x (rows must be sized; see make_rows()).
  virtual void evaluate(double x, ShapeRows& rows) const = 0;
  /// Integration points used for the matrices of eqs. (7)-(9).
  virtual std::vector<QuadraturePoint> quadrature() const = 0;
  virtual std::string name() const = 0;
  ShapeRows make_rows() const;
  /// Throws std::invalid_argument (as evaluate() would) where the rows cannot be formed at one of
  /// the abscissae `xs`, without forming them: EFG solves its moment matrices only (the product
  /// with Lambda^-1, evaluate()'s cost, is skipped), so `check` finds a support too small at a
  /// quadrature point in a fraction of the assembly's time. FEM rows exist everywhere.
  virtual void check_points(const std::vector<double>& xs) const { (void)xs; }
};

struct EfgOptions {
  int nodes = 10;               ///< field nodes, uniformly spaced on [0, L]
  double scale = 2.5;           ///< support d_mI = scale * c_I (eq. 18)
  int gauss_points = 4;         ///< per background cell
  int cells = 0;                ///< background cells; 0 = nodes - 1
  int basis_order = 2;          ///< transverse GMLS basis degree (the hub-beam paper,
                                ///< Xie & Jian 2017: 2, p = [1, x, x^2])
  int axial_basis_order = 1;    ///< axial IMLS basis degree
};

struct FemOptions {
  int elements = 9;
  int gauss_points = 4;
};

/// Element-free Galerkin with IGMLS (transverse) and interpolating MLS (axial), eqs. (18)-(23).
/// Throws std::invalid_argument with a plain explanation when the support is too small for
/// the basis (moment matrix singular) or Lambda cannot be inverted.
std::unique_ptr<BeamBasis> make_efg_basis(double length, const EfgOptions& options);

/// Hermite cubic bending + linear axial finite elements, eq. (24).
std::unique_ptr<BeamBasis> make_fem_basis(double length, const FemOptions& options);

/// The cubic-spline weight of eq. (18) and its first two derivatives with respect to r.
void cubic_spline_weight(double r, double& w, double& dw, double& ddw);

}  // namespace ff::hubbeam
