// Parts joined at a common edge ([[junction]], core/scene/structure_parts.h) and the linear static
// analysis (solver.method = "linear", core/shell/shell_model.md §L), against published data:
// Raasch's hook, Knight (1997), "The Raasch challenge for shell elements", AIAA J. 35(2):375-381,
// the reference tip deflection 5.02 along the unit in-plane shear at the free end (linear). The
// bundled scene assets/scenes/raasch_hook.toml writes the hook as two cylinder parts (radii 14
// and 46) joined where they meet tangentially; nothing is imported.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "core/scene/scene.h"
#include "core/shell/shell_static_simulation.h"

namespace {

struct HookRun {
  double tip_w = NAN;
  int nodes = 0;
  int six_dof_nodes = 0;
};

HookRun run_hook(const std::vector<std::string>& overrides) {
  ff::scene::LoadedScene s =
      ff::scene::load_scene(std::string(FF_SOURCE_DIR) + "/assets/scenes/raasch_hook.toml", overrides);
  std::atomic<bool> stop{false};
  const ff::RunOutcome o = s.simulation->run([](ff::Frame&&) {}, stop);
  EXPECT_EQ(o.status, ff::RunStatus::completed) << o.reason;
  HookRun r;
  for (const auto& [k, v] : s.simulation->metrics())
    if (k == "tip_w") r.tip_w = v;
  const auto& model = dynamic_cast<const ff::shell::ShellStaticSimulation&>(*s.simulation).model();
  r.nodes = model.spec().mesh.node_count();
  for (int i = 0; i < r.nodes; ++i) r.six_dof_nodes += model.dofs_of_node(i) == 6;
  return r;
}

}  // namespace

// The bundled mesh (12 + 90 elements along the arcs, 12 across the width): measured 4.9625, 1.1 %
// below Knight's 5.02 (the bound: 2 %). The two parts share one line of 13 nodes: 13 x 103
// nodes in all instead of 13 x 104, and since their directors agree there (the large arc flips
// its own) no node needs the drilling DoF.
TEST(ShellJunction, RaaschHookMeetsKnightsReference) {
  const HookRun r = run_hook({});
  EXPECT_NEAR(r.tip_w / 5.02, 1.0, 0.02) << r.tip_w;
  EXPECT_EQ(r.nodes, 13 * 103);
  EXPECT_EQ(r.six_dof_nodes, 0);
}

// Refining across the width, which carries the in-plane shear, moves the deflection up towards
// the reference; the arcs' own refinement hardly matters (12 + 90 against 24 + 180 elements along
// them: 4.9625 against 4.9616 at 12 across). Measured at 12 + 90 along: 4.9192 (8 across),
// 4.9856 (16), 5.0156 (32), and 5.0069 (24), 5.0224 (48): the differences fall 2.2x per halving,
// and the Richardson limit from 8, 16, 32 is 5.041, 0.4 % above Knight's 5.02.
TEST(ShellJunction, RaaschHookConvergesTowardsTheReference) {
  std::vector<double> w;
  for (int n : {8, 16, 32}) {
    const std::string across = std::to_string(n);
    w.push_back(run_hook({"part[0].n2=" + across, "part[1].n2=" + across}).tip_w);
  }
  EXPECT_LT(w[0], w[1]);
  EXPECT_LT(w[1], w[2]);
  const double ratio = (w[1] - w[0]) / (w[2] - w[1]);
  EXPECT_GT(ratio, 1.5) << "w = " << w[0] << ", " << w[1] << ", " << w[2];
  const double limit = w[2] + (w[2] - w[1]) / (ratio - 1.0);
  EXPECT_NEAR(limit / 5.02, 1.0, 0.01) << "w = " << w[0] << ", " << w[1] << ", " << w[2] << ", limit " << limit;
  EXPECT_NEAR(w[2] / 5.02, 1.0, 0.005) << w[2];
}

// Without the junction the two parts are apart: the large arc is held by nothing, and the
// linear analysis says so (a singular stiffness is a mechanism) instead of giving a number.
TEST(ShellJunction, WithoutTheJunctionTheFreeArcIsAMechanism) {
  std::ifstream in(std::string(FF_SOURCE_DIR) + "/assets/scenes/raasch_hook.toml");
  std::stringstream text;
  text << in.rdbuf();
  std::string scene = text.str();
  const auto b = scene.find("[[junction]]"), e = scene.find("[[bc]]");
  ASSERT_NE(b, std::string::npos);
  ASSERT_NE(e, std::string::npos);
  scene.erase(b, e - b);
  const std::string dir = std::string(FF_BINARY_DIR) + "/test_out/shell_junction";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/hook_apart.toml";
  std::ofstream(path) << scene;
  ff::scene::LoadedScene s = ff::scene::load_scene(path, {});
  std::atomic<bool> stop{false};
  const ff::RunOutcome o = s.simulation->run([](ff::Frame&&) {}, stop);
  EXPECT_NE(o.status, ff::RunStatus::completed);
  EXPECT_NE(o.reason.find("mechanism"), std::string::npos) << o.reason;
}

// A junction's mistakes are refused at their keys.
TEST(ShellJunction, JunctionMistakesAreRefusedAtTheirKeys) {
  try {
    ff::scene::load_scene(std::string(FF_SOURCE_DIR) + "/assets/scenes/raasch_hook.toml",
                          {"junction[0].parts=[\"small_arc\", \"nowhere\"]"});
    ADD_FAILURE() << "a junction naming no part was accepted";
  } catch (const ff::scene::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("no part is called 'nowhere'"), std::string::npos) << e.what();
  }
  // the parts' directors facing opposite sides where they meet: the key that fixes it is named
  try {
    ff::scene::load_scene(std::string(FF_SOURCE_DIR) + "/assets/scenes/raasch_hook.toml", {"part[1].flip_director=false"});
    ADD_FAILURE() << "opposite directors at the junction were accepted";
  } catch (const ff::scene::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("flip_director"), std::string::npos) << e.what();
  }
  // parts that do not touch
  try {
    ff::scene::load_scene(std::string(FF_SOURCE_DIR) + "/assets/scenes/raasch_hook.toml",
                          {"part[1].origin=[60.0, -30.0, 0.0]"});
    ADD_FAILURE() << "a junction of parts apart was accepted";
  } catch (const ff::scene::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("share no node"), std::string::npos) << e.what();
  }
}
