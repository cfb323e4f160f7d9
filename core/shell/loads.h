#pragma once
/// \file loads.h
/// External loads shared by the static shell model (shell_model.h, scaled by the load factor
/// lambda) and the dynamic multibody model (multibody_model.h, scaled by a time history f(t),
/// cb_shell_dynamics.md §8).

#include <cmath>
#include <limits>

#include "core/shell/cb_shell.h"  // Vec3

namespace ff::shell {

struct NodalLoad {
  int node = -1;
  Vec3 force = Vec3::Zero();   ///< global components at lambda = 1 (follower: node-frame components)
  Vec3 moment = Vec3::Zero();  ///< global components at lambda = 1 (follower: node-frame components)
  bool follower = false;
};

/// Uniform pressure on one quad of the mesh, p times the mid-surface area element
/// g_xi x g_eta (shell_model.md eq. P1): positive along the quad's normal, i.e. towards the
/// director's side of a counter-clockwise quad (core/mesh/README.md convention 1).
struct PressureLoad {
  int quad = -1;
  double pressure = 0.0;  ///< force per unit area at lambda = 1
  /// false: dead load, normal and area of the reference configuration; true: normal and area of
  /// the current configuration (load stiffness in the tangent, non-symmetric in general)
  bool follower = false;
};

/// Time history of a load in dynamics (cb_shell_dynamics.md eq. D16): the load at time t is its
/// reference value times factor(t), which is 0 before `start` and from `end` on, rises linearly
/// over `ramp` from `start`, and is 1 in between. The defaults are a load applied suddenly at t = 0
/// and held; a finite `end` makes a rectangular (ramp = 0) or trapezoid-fronted pulse.
struct LoadHistory {
  double start = 0.0;
  double end = std::numeric_limits<double>::infinity();
  double ramp = 0.0;
  double factor(double t) const {
    if (t < start || t >= end) return 0.0;
    if (t < start + ramp) return (t - start) / ramp;  // ramp > 0 here
    return 1.0;
  }
  /// Empty when the history is usable, otherwise what is wrong with it.
  const char* defect() const {
    if (!std::isfinite(start)) return "its start time must be a finite number";
    if (!(end > start)) return "its end time must lie after its start time";
    if (!(ramp >= 0.0) || !std::isfinite(ramp)) return "its ramp duration must be a finite number >= 0";
    return "";
  }
};

}  // namespace ff::shell
