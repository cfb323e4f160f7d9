#include "core/assembly/node_frames.h"

#include <cmath>

namespace ff::assembly {

Eigen::Matrix3d align(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d axis = a.cross(b);
  const double s = axis.norm(), c = a.dot(b);
  return s < 1e-14 ? Eigen::Matrix3d::Identity()
                   : Eigen::Matrix3d(Eigen::AngleAxisd(std::atan2(s, c), axis / s).toRotationMatrix());
}

CornerFrame corner_frame(const Eigen::Matrix3d& R_WN0, const Eigen::Vector3d& corner_director) {
  CornerFrame c;
  c.frame = align(R_WN0.col(2), corner_director.normalized()) * R_WN0;
  c.turn = R_WN0.transpose() * c.frame;
  return c;
}

}  // namespace ff::assembly
