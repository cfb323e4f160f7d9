// Model and state apart (issue 31, item 3): ShellModel and MultibodyModel are the constant
// structure; what changes while they are solved is a ShellState / MultibodyState, and saving and
// restoring an attempt is a copy of it. The tests can fail: an attempt that left anything of its
// configuration behind after restore (or rollback) would move the poses compared here.
#include <gtest/gtest.h>

#include "core/mesh/generators.h"
#include "core/shell/multibody_model.h"
#include "core/shell/shell_model.h"

namespace {
using namespace ff;
using namespace ff::shell;

bool same_poses(const std::vector<NodePose>& a, const std::vector<NodePose>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].p != b[i].p || a[i].R != b[i].R) return false;
  return true;
}

TEST(ModelState, ShellAttemptIsUndoneByRestoringTheSavedState) {
  ShellModelSpec spec;
  spec.mesh = mesh::rectangular_plate(1.0, 0.2, 4, 1);
  spec.section = isotropic_section(1e6, 0.3, 0.01);
  for (int i = 0; i < spec.mesh.node_count(); ++i)
    if (spec.mesh.points[i].x() < 1e-12) spec.restraints.push_back({i, kClamped});
  ShellModel model(spec);
  const ShellState before = model.state();
  model.save_state();
  Eigen::VectorXd step = Eigen::VectorXd::Constant(model.size(), 1e-3);
  model.update(step);
  EXPECT_FALSE(same_poses(model.state().poses, before.poses));
  model.restore_state();
  EXPECT_TRUE(same_poses(model.state().poses, before.poses));
  // a state from elsewhere (another analysis of the same structure) is taken whole, or refused
  model.update(step);
  const ShellState moved = model.state();
  model.set_state(before);
  EXPECT_TRUE(same_poses(model.state().poses, before.poses));
  model.set_state(moved);
  EXPECT_TRUE(same_poses(model.state().poses, moved.poses));
  ShellState wrong = before;
  wrong.poses.pop_back();
  EXPECT_THROW(model.set_state(wrong), std::invalid_argument);
}

TEST(ModelState, MultibodyRejectedAttemptRollsBackToTheCommittedState) {
  MultibodySpec spec;
  ShellBodySpec body;
  body.name = "plate";
  body.mesh = mesh::rectangular_plate(1.0, 0.2, 4, 1);
  body.section = isotropic_section(1e6, 0.3, 0.01);
  body.density = 1000.0;
  spec.shells.push_back(body);
  MultibodyModel model(spec);
  const MultibodyState start = model.state();
  EXPECT_TRUE(start.step_is_zero);
  const Eigen::VectorXd step = Eigen::VectorXd::Constant(model.size(), 1e-3);
  model.configure(step);
  EXPECT_FALSE(model.state().step_is_zero);
  EXPECT_FALSE(same_poses(model.state().poses, start.poses));
  model.rollback();
  EXPECT_TRUE(same_poses(model.state().poses, start.poses));
  EXPECT_TRUE(model.state().step_is_zero);
  model.configure(step);
  model.commit();
  const MultibodyState committed = model.state();
  EXPECT_TRUE(committed.step_is_zero);
  model.configure(2.0 * step);
  model.rollback();
  EXPECT_TRUE(same_poses(model.state().poses, committed.poses));
}

}  // namespace
