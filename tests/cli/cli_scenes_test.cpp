// Every bundled scene passes `flexframe check` and runs (shortened) without diverging, except the
// zero-order model at tau0 = 10 N m, which must diverge past its critical speed at t ~ 1.77 s --
// and whose results.h5 must still be complete and readable up to the stop time.

#include <gtest/gtest.h>

#include <regex>

#include "app/io/results.h"
#include "cli_support.h"

namespace ff::cli::test {
namespace {

constexpr const char* kZeroOrder = "hub_beam_zero_order_tau10";
constexpr double kShortEnd = 2.5;  // s: runs are cut to this end time

/// solver.end of a bundled scene file (NaN if not found).
double scene_t_end(const std::string& name) {
  const std::string text = read_text(scene_path(name));
  std::smatch m;
  static const std::regex re(R"((^|\n)\s*end\s*=\s*([0-9.eE+-]+))");
  return std::regex_search(text, m, re) ? std::stod(m[2].str()) : std::nan("");
}

constexpr double kShortLambda = 0.2;  // static scenes stop at this load factor

bool is_static(const std::string& name) {
  static const std::regex re(R"((^|\n)\s*analysis\s*=\s*"static")");
  return std::regex_search(read_text(scene_path(name)), re);
}

constexpr double kShortShellDynamics = 0.01;  // s: shell dynamics scenes stop here (20 steps at 5e-4)

bool is_shell_dynamic(const std::string& name) {
  static const std::regex re(R"((^|\n)\s*analysis\s*=\s*"dynamic")");
  return std::regex_search(read_text(scene_path(name)), re);
}

bool is_eigen(const std::string& name) {
  static const std::regex re(R"re((^|\n)\s*analysis\s*=\s*"(modal|buckling)")re");
  return std::regex_search(read_text(scene_path(name)), re);
}

/// `flexframe run NAME --out DIR/out --no-frames --no-plots --quiet`, shortened to kShortEnd
/// (dynamics) or to the load factor kShortLambda (statics, whose "time" is lambda).
ProcResult run_short(const std::string& name, const std::string& dir, double* t_end) {
  std::ostringstream set;
  set.precision(17);
  if (is_eigen(name)) {  // one step, nothing to shorten: it ends at its preload (or the reference)
    const std::string text = read_text(scene_path(name));
    *t_end = text.find("about = \"preload\"") != std::string::npos ? 1.0 : 0.0;
    return run_flexframe({"run", name, "--out", dir + "/out", "--no-frames", "--no-plots", "--quiet"}, dir + "/run");
  }
  if (is_static(name)) {
    *t_end = kShortLambda;
    set << "solver.end=" << *t_end;
  } else if (is_shell_dynamic(name)) {
    *t_end = kShortShellDynamics;
    set << "solver.end=" << *t_end;
  } else {
    const double scene_end = scene_t_end(name);
    *t_end = std::isfinite(scene_end) ? std::min(scene_end, kShortEnd) : kShortEnd;
    set << "solver.end=" << *t_end;
  }
  return run_flexframe({"run", name, "--out", dir + "/out", "--no-frames", "--no-plots", "--quiet", "--set", set.str()},
                       dir + "/run");
}

TEST(CliScenes, BundledScenesAreListed) {
  const std::vector<std::string> names = bundled_scene_names();
  ASSERT_GE(names.size(), 7u);
  EXPECT_NE(std::find(names.begin(), names.end(), kZeroOrder), names.end());
  // `flexframe scenes` lists the same names
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_flexframe({"scenes"}, dir + "/scenes");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  for (const std::string& n : names) { EXPECT_NE(r.out.find("  " + n + "\n"), std::string::npos) << n << "\n" << r.describe(); }
}

class CliBundledScene : public ::testing::TestWithParam<std::string> {};

TEST_P(CliBundledScene, Checks) {
  const std::string dir = fresh_test_dir();
  const std::string cwd = dir + "/cwd";
  fs::create_directories(cwd);
  const ProcResult r = run_flexframe({"check", scene_path(GetParam())}, dir + "/check", cwd);
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.out.find(GetParam() + ": valid"), std::string::npos) << r.describe();
  EXPECT_TRUE(tree(cwd).empty()) << "check wrote " << ::testing::PrintToString(tree(cwd));
}

TEST_P(CliBundledScene, RunsShortened) {
  const std::string& name = GetParam();
  const std::string dir = fresh_test_dir();
  double t_end = 0;
  const ProcResult r = run_short(name, dir, &t_end);
  ASSERT_EQ(r.signal, 0) << r.describe();
  std::string err;
  const std::optional<Json> s = read_summary(dir + "/out", &err);
  ASSERT_TRUE(s) << err << "\n" << r.describe();
  expect_summary_shape(*s);
  EXPECT_EQ(summary_string(*s, "scene"), name);
  EXPECT_TRUE(fs::is_regular_file(dir + "/out/results.h5"));
  const double stop = summary_number(*s, "stop_time");
  const double steps = summary_number(*s, "steps");
  EXPECT_GT(steps, 0);
  EXPECT_GE(summary_number(*s, "newton_iterations"), steps);
  EXPECT_GT(summary_number(*s, "jacobian_updates"), 0);
  const Json* effects = s->get("effects");
  ASSERT_TRUE(effects);
  std::vector<std::string> fx;
  for (const Json& e : effects->array) fx.push_back(e.string);
  const std::vector<const char*> needed_effects =
      is_static(name) || is_eigen(name) ? std::vector<const char*>{"elastic"}
      : is_shell_dynamic(name) ? std::vector<const char*>{"elastic", "inertia"}
                               : std::vector<const char*>{"inertia", "bending"};
  for (const char* needed : needed_effects)
    EXPECT_NE(std::find(fx.begin(), fx.end(), needed), fx.end()) << "effects lack " << needed;
  // effect_stats: every listed effect ran; anything else that ran is a load or a rigid body
  const Json* stats = s->get("effect_stats");
  ASSERT_TRUE(stats && stats->kind == Json::Kind::object);
  for (const std::string& e : fx) { EXPECT_TRUE(stats->get(e)) << "effect '" << e << "' is listed but did not run"; }
  for (const auto& [e, stat] : stats->object) {
    const bool listed = std::find(fx.begin(), fx.end(), e) != fx.end();
    // a modal analysis's mass is the element inertia, whether or not the scene lists it
    const bool implied = e == "point_loads" || e == "pressure_dead" || e == "pressure_follower" || e == "rigid_body" ||
                         (e == "inertia" && is_eigen(name));
    EXPECT_TRUE(listed || implied) << "'" << e << "' ran but the scene does not ask for it";
    const Json* n = stat.get("evaluations");
    EXPECT_TRUE(n && n->is_number() && n->number > 0) << e;
  }
  ASSERT_TRUE(s->get("metrics"));
  EXPECT_FALSE(s->get("metrics")->object.empty());

  if (name == kZeroOrder) {
    // the hub-beam paper's divergence: the hub rate crosses this model's critical speed at t ~ 1.77 s
    EXPECT_EQ(r.exit_code, 3) << r.describe();
    EXPECT_EQ(summary_string(*s, "status"), "diverged");
    EXPECT_NE(summary_string(*s, "reason").find("critical speed"), std::string::npos) << summary_string(*s, "reason");
    EXPECT_GT(stop, 1.6);
    EXPECT_LT(stop, 1.9);
  } else {
    EXPECT_EQ(r.exit_code, 0) << r.describe();
    EXPECT_EQ(summary_string(*s, "status"), "completed") << summary_string(*s, "reason");
    // a completed run's reason is empty unless its load path returned to the unloaded state (the
    // h = 6.35 roof's snap-back dips below zero load): then it says so (static_solvers.md §4.4)
    bool unloaded = false;
    if (const Json* events = s->get("events"))
      for (const Json& e : events->array) unloaded = unloaded || (e.get("kind") && e.get("kind")->string == "unloaded");
    if (unloaded)
      EXPECT_NE(summary_string(*s, "reason").find("returned to the unloaded state"), std::string::npos)
          << summary_string(*s, "reason");
    else
      EXPECT_EQ(summary_string(*s, "reason"), "");
    EXPECT_NEAR(stop, t_end, 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(Bundled, CliBundledScene, ::testing::ValuesIn(bundled_scene_names()),
                         [](const ::testing::TestParamInfo<std::string>& i) { return i.param; });

// The diverged run's HDF5: complete up to the stop time, outcome "diverged", finite probes.
TEST(CliScenes, DivergedRunResultsAreReadable) {
  const std::string dir = fresh_test_dir();
  double t_end = 0;
  const ProcResult r = run_short(kZeroOrder, dir, &t_end);
  ASSERT_EQ(r.exit_code, 3) << r.describe();
  std::string err;
  const std::optional<Json> s = read_summary(dir + "/out", &err);
  ASSERT_TRUE(s) << err;
  const double stop = summary_number(*s, "stop_time");

  const std::unique_ptr<io::ResultReader> h5 = io::ResultReader::open(dir + "/out/results.h5", &err);
  ASSERT_TRUE(h5) << err;
  const RunOutcome o = h5->outcome();
  EXPECT_EQ(o.status, RunStatus::diverged) << to_string(o.status) << ": " << o.reason;
  EXPECT_EQ(o.reason, summary_string(*s, "reason"));
  EXPECT_NEAR(o.stop_time, stop, 1e-9);
  EXPECT_EQ(static_cast<double>(o.steps), summary_number(*s, "steps"));

  const std::vector<double> t = h5->times();
  ASSERT_EQ(t.size(), h5->frame_count());
  ASSERT_GT(t.size(), 10u);
  EXPECT_EQ(t.front(), 0.0);
  for (std::size_t i = 1; i < t.size(); ++i) { ASSERT_GT(t[i], t[i - 1]) << "frame " << i; }
  EXPECT_NEAR(t.back(), stop, 1e-9) << "the last stored frame is not the last converged step";
  // every step is stored: dt = 0.01 s up to the stop time
  EXPECT_EQ(static_cast<double>(t.size() - 1), summary_number(*s, "steps"));

  ASSERT_FALSE(h5->info().probes.empty());
  for (const Quantity& q : h5->info().probes) {
    const std::vector<double> v = h5->probe_series(q.name);
    ASSERT_EQ(v.size(), t.size()) << q.name;
    for (std::size_t i = 0; i < v.size(); ++i) { ASSERT_TRUE(std::isfinite(v[i])) << q.name << " at frame " << i; }
  }
  const Frame last = h5->frame(t.size() - 1);
  for (double x : last.points) { ASSERT_TRUE(std::isfinite(x)); }
  EXPECT_EQ(last.points.size(), 3 * h5->info().mesh.point_count());
}

}  // namespace
}  // namespace ff::cli::test
