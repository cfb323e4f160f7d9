// summary.json "effect_stats" (effects only as asked, DESIGN.md "Effects"): a short static shell
// run and a short hub-beam run list every effect that ran with its evaluations and seconds, and
// none that the scene left out. Effects fused into another's kernel (hr, ans inside the elastic
// element; the hub-beam terms inside its equations of motion) have "time_s": null and say
// "included_in".

#include <gtest/gtest.h>

#include <set>

#include "cli_support.h"

namespace ff::cli::test {
namespace {

/// The names in effect_stats, after checking each entry's shape.
std::set<std::string> effect_names(const Json& summary) {
  std::set<std::string> names;
  const Json* stats = summary.get("effect_stats");
  EXPECT_TRUE(stats && stats->kind == Json::Kind::object) << "summary.json: no \"effect_stats\" object";
  if (!stats) return names;
  for (const auto& [name, e] : stats->object) {
    names.insert(name);
    const Json* n = e.get("evaluations");
    EXPECT_TRUE(n && n->is_number() && n->number > 0) << name << ": evaluations missing or not > 0";
    const Json* t = e.get("time_s");
    EXPECT_TRUE(t) << name << ": no time_s";
    if (!t) continue;
    const Json* in = e.get("included_in");
    if (in) {
      EXPECT_TRUE(in->is_string());
      EXPECT_EQ(t->kind, Json::Kind::null) << name << " is timed inside " << in->string;
      EXPECT_TRUE(stats->get(in->string)) << name << " is included in " << in->string << ", which is not listed";
    } else {
      EXPECT_TRUE(t->is_number() && t->number > 0) << name << ": time_s missing or not > 0";
    }
  }
  return names;
}

std::set<std::string> run_and_read(const std::vector<std::string>& sets, const std::string& scene,
                                   const std::string& tag, const std::string& dir) {
  std::vector<std::string> args{"run", scene, "--out", dir + "/" + tag, "--no-frames", "--no-plots", "--quiet"};
  for (const std::string& s : sets) args.insert(args.end(), {"--set", s});
  const ProcResult r = run_flexframe(args, dir + "/" + tag);
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  std::string err;
  const std::optional<Json> s = read_summary(dir + "/" + tag, &err);
  EXPECT_TRUE(s) << err << "\n" << r.describe();
  return s ? effect_names(*s) : std::set<std::string>{};
}

}  // namespace

TEST(CliEffectStats, StaticShellListsOnlyTheEffectsThatRan) {
  const std::string dir = fresh_test_dir();
  const std::vector<std::string> small{"part[0].n1=4", "part[0].n2=4"};
  // the bundled plate: elastic with hr and ans, a dead pressure; no mass matrix, no drilling
  std::set<std::string> on = run_and_read(small, "clamped_plate_pressure", "hr_ans", dir);
  EXPECT_EQ(on, (std::set<std::string>{"elastic", "hr", "ans", "pressure_dead"}));
  // the same plate with only the elastic effect, a follower pressure and 6 DoF per node
  std::vector<std::string> sets = small;
  sets.insert(sets.end(), {"scene.effects=[\"elastic\",\"drilling\"]", "load[0].follower=true"});
  std::set<std::string> off = run_and_read(sets, "clamped_plate_pressure", "plain", dir);
  EXPECT_EQ(off, (std::set<std::string>{"elastic", "drilling", "pressure_follower"}));
}

TEST(CliEffectStats, HubBeamListsTheCouplingOrderThatRan) {
  const std::string dir = fresh_test_dir();
  std::set<std::string> first = run_and_read({"solver.end=0.5"}, "hub_beam_fem_tau1", "first", dir);
  EXPECT_EQ(first, (std::set<std::string>{"inertia", "bending", "axial", "first_order_coupling", "hub_torque"}));
  std::set<std::string> zero = run_and_read(
      {"solver.end=0.5", "scene.effects=[\"inertia\",\"bending\"]"}, "hub_beam_fem_tau1", "zero", dir);
  EXPECT_EQ(zero, (std::set<std::string>{"inertia", "bending"}));
}

}  // namespace ff::cli::test
