#pragma once
/// A semi-discrete system r(x, v, a, t) = 0 with v = dx/dt, a = d2x/dt2, as integrated by Newmark.

#include <Eigen/Dense>
#include <string>

namespace ff {

class SecondOrderSystem {
 public:
  virtual ~SecondOrderSystem() = default;
  virtual int size() const = 0;
  /// Residual of the equations of motion at (x, v, a, t).
  virtual void residual(const Eigen::VectorXd& x, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                        double t, Eigen::VectorXd& r) const = 0;
  /// Iteration matrix J = ca * dr/da + cv * dr/dv + cx * dr/dx.
  virtual void iteration_matrix(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                                const Eigen::VectorXd& a, double t, double ca, double cv, double cx,
                                Eigen::MatrixXd& jacobian) const = 0;
  /// After a converged step: empty when the state is within the model's validity, otherwise why not.
  virtual std::string check_state(const Eigen::VectorXd& x, const Eigen::VectorXd& v) const { return {}; }
};

}  // namespace ff
