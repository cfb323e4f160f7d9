// solver.linear_solver: every compiled LU backend solves the same Newton corrections, so a static
// scene's answer does not depend on the choice beyond round-off. The clamped plate under pressure
// (assets/scenes/clamped_plate_pressure.toml: Kirchhoff w = 0.00126 q a^4 / D, Timoshenko &
// Woinowsky-Krieger §44, Table 35) through each backend; their centre deflections agree to 1e-9.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <string>

#include "core/model/simulation.h"
#include "core/scene/scene.h"
#include "core/solve/sparse_solver.h"

namespace {

double w_centre(const std::string& backend) {
  const std::string path = std::string(FF_SOURCE_DIR) + "/assets/scenes/clamped_plate_pressure.toml";
  ff::scene::LoadedScene s = ff::scene::load_scene(path, {"solver.linear_solver=\"" + backend + "\""});
  std::atomic<bool> stop{false};
  const ff::RunOutcome o = s.simulation->run([](ff::Frame&&) {}, stop);
  EXPECT_EQ(o.status, ff::RunStatus::completed) << backend << ": " << o.reason;
  for (const auto& [k, v] : s.simulation->metrics())
    if (k == "w_centre") return v;
  ADD_FAILURE() << "metric w_centre missing";
  return NAN;
}

}  // namespace

TEST(LinearSolverChoice, EveryLuBackendGivesTheSameAnswer) {
  const double reference = w_centre("default");
  EXPECT_GT(reference, 1e-6);
  for (const char* b : {"umfpack", "mumps", "sparse_lu"}) {
    if (!ff::linear_backend_available(*ff::parse_linear_backend(b))) continue;
    const double w = w_centre(b);
    std::printf("%-9s w_centre = %.15e\n", b, w);
    EXPECT_LT(std::abs(w / reference - 1.0), 1e-9) << b;
  }
}
