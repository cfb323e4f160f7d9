// Every run's answer metrics with their discretization error (issue 49; core/model/error_bars.md,
// docs/guide/how-accurate.md): the estimate from the coarser twin must bracket the true error
// against a published solution, the bars are on by default and can be turned off, and a source
// that cannot be estimated is said, not dropped silently.

#include <hdf5.h>
#include <nlohmann/json.hpp>

#include "app/io/results.h"
#include "cli_support.h"

namespace ff::cli::test {
namespace {

nlohmann::json summary_of(const std::string& out) {
  return nlohmann::json::parse(read_text(out + "/summary.json"));
}

ProcResult run_scene(const std::string& dir, const std::string& name, const std::string& out,
                     const std::vector<std::string>& extra = {}, double timeout_s = 300) {
  std::vector<std::string> args = {"run", scene_path(name), "--out", dir + "/" + out,
                                   "--no-frames", "--no-plots", "--quiet"};
  args.insert(args.end(), extra.begin(), extra.end());
  return run_flexframe(args, dir + "/" + out, "", timeout_s);
}

// The effectivity (estimated over true error) the issue asks where the true error exceeds 0.5 %:
// between 1/3 and 3; and the bar (GCI) at least the true error.
void expect_brackets(const nlohmann::json& metric, double reference, const std::string& what,
                     double least_error = 0.005) {
  ASSERT_TRUE(metric["flags"].empty()) << what << ": " << metric.dump(1);
  const double value = metric["value"], estimate = metric["estimate"], bar = metric["bar"];
  const double true_error = value - reference;
  ASSERT_GT(std::abs(true_error), least_error * std::abs(reference)) << what << ": the case must have an error to bracket";
  const double effectivity = estimate / true_error;
  EXPECT_GE(effectivity, 1.0 / 3.0) << what << ": estimate " << estimate << " for a true error " << true_error;
  EXPECT_LE(effectivity, 3.0) << what << ": estimate " << estimate << " for a true error " << true_error;
  EXPECT_GE(bar, std::abs(true_error)) << what;
}

TEST(ErrorBars, ClampedPlateFrequenciesAgainstLeissa) {
  // Leissa, Vibration of Plates, NASA SP-160 (1969), Table 4.23: clamped square plate,
  // lambda = omega a^2 sqrt(rho h / D) = 35.985, 73.394, 73.394, 108.22, 131.58, 132.21; with the
  // scene's plate f = 2.49903 lambda Hz (its header). At 16 x 16 every frequency is 0.8-5.4 % high.
  const std::string dir = fresh_test_dir();
  // two levels (the formal order): the estimate the issue judges; three are tested below
  const ProcResult r = run_scene(dir, "modal_clamped_plate", "out",
                                 {"--error-bar", "two", "--set", "part[0].n1=16", "part[0].n2=16"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json bars = summary_of(dir + "/out")["error_bars"];
  const double lambda[] = {35.985, 73.394, 73.394, 108.22, 131.58, 132.21};
  for (int k = 0; k < 6; ++k) {
    const std::string name = "frequency_" + std::to_string(k + 1);
    ASSERT_TRUE(bars["metrics"].contains(name)) << bars.dump(1);
    expect_brackets(bars["metrics"][name], 2.49903 * lambda[k], name);
  }
  EXPECT_EQ(bars["twins"][0]["elements"], 64) << "the mesh twin halves 16 x 16";
  // results.h5 keeps the same bars beside the frames (results_layout.md /attributes error_bars)
  std::string err;
  const auto reader = io::ResultReader::open(dir + "/out/results.h5", &err);
  ASSERT_TRUE(reader) << err;
  std::string stored;
  for (const auto& [key, value] : reader->attributes())
    if (key == "error_bars") stored = value;
  ASSERT_FALSE(stored.empty()) << "results.h5 has no error_bars attribute";
  EXPECT_EQ(nlohmann::json::parse(stored)["metrics"], bars["metrics"]);
  EXPECT_NE(r.out.find("frequency_1"), std::string::npos);
  EXPECT_NE(r.out.find(" ± "), std::string::npos) << "the console prints the bar beside the value:\n" << r.out;
  EXPECT_NE(r.out.find("% of the run"), std::string::npos) << "and what it cost:\n" << r.out;
}

TEST(ErrorBars, ClampedPlateDeflectionAgainstTheSeriesSolution) {
  // Timoshenko & Woinowsky-Krieger (1959), §44, Table 35: w_max = 0.00126 q a^4 / D for the
  // clamped square plate; the series to more digits gives the coefficient 0.0012653 (Taylor &
  // Govindjee, Commun. Numer. Meth. Engng 20 (2004) 757-765, Table I). At the scene's 8 x 8 the
  // centre deflection is 0.42 % low (the Reissner-Mindlin shear adds ~0.1 % to the limit), and the
  // 4 x 4 twin must see it: judged here below the 0.5 % threshold, since it is the
  // scene's own mesh. (At 6 x 6 the 3 x 3 twin has no node at the centre and the metric is flagged;
  // at 4 x 4 the 2 x 2 twin is far outside the asymptotic range: see the guide's limits.)
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_scene(dir, "clamped_plate_pressure", "out", {"--error-bar", "two"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json s = summary_of(dir + "/out");
  const double D = 210e9 * std::pow(0.01, 3) / (12 * (1 - 0.3 * 0.3));
  expect_brackets(s["error_bars"]["metrics"]["w_centre"], 0.0012653 * 1000.0 / D, "w_centre", 0.003);
  EXPECT_EQ(s["error_bars"]["metrics"]["w_centre"]["sources"][0]["source"], "mesh");
  EXPECT_DOUBLE_EQ(s["error_bars"]["metrics"]["w_centre"]["sources"][0]["ratio"], 2.0);
}

TEST(ErrorBars, TimeStepEstimateAgainstATenTimesFinerStep) {
  // The double pendulum (the main job) shortened to 0.5 s at dt = 1e-3: its time bar, the
  // integrator's accumulated local error (core/model/error_bars.md (R9)), must cover the
  // difference to the same mesh at dt = 1e-4, a step ten times finer whose own error is 1 % of the
  // run's (second order), and be within 1/3-3 of it wherever that exceeds 0.5 %.
  const std::string dir = fresh_test_dir();
  const ProcResult run = run_scene(dir, "double_pendulum_shells", "run", {"--set", "solver.dt=1e-3", "solver.end=0.5"}, 600);
  ASSERT_EQ(run.exit_code, 0) << run.describe();
  const ProcResult fine = run_scene(dir, "double_pendulum_shells", "fine",
                                    {"--error-bar", "off", "--set", "solver.dt=1e-4", "solver.end=0.5"}, 600);
  ASSERT_EQ(fine.exit_code, 0) << fine.describe();
  const nlohmann::json bars = summary_of(dir + "/run")["error_bars"];
  const nlohmann::json reference = summary_of(dir + "/fine");
  EXPECT_FALSE(reference.contains("error_bars")) << "--error-bar off runs no twin";
  EXPECT_EQ(bars["levels"], 2) << "auto: two levels in time";
  EXPECT_EQ(bars["time_source"], "local error estimate");
  // no time twin: the one twin is the coarser mesh at the run's own step
  ASSERT_EQ(bars["twins"].size(), 1u) << bars.dump(1);
  EXPECT_EQ(bars["twins"][0]["name"], "mesh");
  EXPECT_EQ(bars["twins"][0]["description"].get<std::string>().find("solver.dt"), std::string::npos);
  int judged = 0;
  for (const auto& [name, m] : bars["metrics"].items()) {
    if (name.rfind("arc_", 0) == 0) {  // the arcs' largest changes: said to have no bar, and why
      ASSERT_EQ(m["flags"].size(), 1u) << name << ": " << m.dump(1);
      EXPECT_EQ(m["flags"][0].get<std::string>().rfind("not estimated: the largest change of an arc", 0), 0u) << name;
      EXPECT_TRUE(m["bar"].is_null()) << name;
      continue;
    }
    ASSERT_TRUE(m["flags"].empty()) << name << ": " << m.dump(1);
    const nlohmann::json* time = nullptr;
    for (const auto& source : m["sources"])
      if (source["source"] == "time") time = &source;
    ASSERT_NE(time, nullptr) << name;
    EXPECT_EQ((*time)["estimate"].get<double>(), 0.0) << "a magnitude moves no value";
    EXPECT_EQ((*time)["bar"].get<double>(), m["time_local_estimate"].get<double>()) << name;
    const double true_error = m["value"].get<double>() - reference["metrics"][name].get<double>();
    // the bar covers the difference to the finer step wherever it is above the solver's
    // tolerance (1e-6 of the metric), and is within 1/3-3 of it above 0.5 %
    if (std::abs(true_error) > 1e-6 * std::abs(m["value"].get<double>())) {
      EXPECT_GE((*time)["bar"].get<double>(), std::abs(true_error)) << name;
    }
    if (std::abs(true_error) <= 0.005 * std::abs(m["value"].get<double>())) continue;
    ++judged;
    const double effectivity = (*time)["bar"].get<double>() / std::abs(true_error);
    EXPECT_GE(effectivity, 1.0 / 3.0) << name;
    EXPECT_LE(effectivity, 3.0) << name;
  }
  EXPECT_TRUE(bars["metrics"].contains("pointF_z_min")) << bars.dump(1);
  EXPECT_TRUE(bars["metrics"].contains("arc_strain_max_I")) << "an answer without a bar is said: " << bars.dump(1);
  EXPECT_NE(run.out.find("arc_strain_max_I"), std::string::npos);
  EXPECT_FALSE(bars["metrics"].contains("NOI")) << "the solver's counts get no bar";
  EXPECT_NE(run.out.find("time from the integrator's local error"), std::string::npos) << run.out;
  (void)judged;
}

TEST(ErrorBars, ThreeLevelsGiveTheObservedOrderOrAFlag) {
  // --error-bar three: twins at 8 x 8 and 4 x 4 beside the 16 x 16 run; each frequency either gets
  // the observed order (R6) with F_s = 1.25, or a flag saying the levels are not in the asymptotic
  // range, or that a twin has no mode of the run's shape: never a number from an order the levels
  // contradict, nor from another mode
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_scene(dir, "modal_clamped_plate", "out",
                                 {"--error-bar", "three", "--set", "part[0].n1=16", "part[0].n2=16"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json bars = summary_of(dir + "/out")["error_bars"];
  ASSERT_EQ(bars["twins"].size(), 2u) << bars.dump(1);
  EXPECT_EQ(bars["twins"][1]["elements"], 16);
  int observed = 0;
  for (const auto& [name, m] : bars["metrics"].items()) {
    if (!m["flags"].empty()) {
      // out of the asymptotic range, or (frequencies 5 and 6) a 4 x 4 twin whose first six modes
      // have no mode of that shape at all (MAC 0): comparing its 5th would compare another mode
      const std::string flag = m["flags"][0].get<std::string>();
      EXPECT_TRUE(flag.find("asymptotic range") != std::string::npos || flag.find("has no mode like") != std::string::npos)
          << name << m.dump(1);
      EXPECT_TRUE(m["bar"].is_null());
      continue;
    }
    ++observed;
    ASSERT_EQ(m["sources"].size(), 1u);
    EXPECT_EQ(m["sources"][0]["safety_factor"], 1.25) << name;
    const double observed_order = m["sources"][0]["observed_order"], p = m["sources"][0]["order"];
    EXPECT_GE(observed_order, 1.0) << name;
    EXPECT_LE(observed_order, 4.0) << name;
    // (R6a): the observed order where it is at most the formal 2, else the formal order
    EXPECT_EQ(m["sources"][0]["order_kind"], observed_order <= 2.0 ? "observed" : "formal (the observed order is above it)")
        << name;
    EXPECT_DOUBLE_EQ(p, std::min(observed_order, 2.0)) << name;
  }
  EXPECT_GT(observed, 0) << "the first frequency converges cleanly from 4 x 4: " << bars.dump(1);
  EXPECT_NE(r.out.find("three levels"), std::string::npos) << r.out;
}

// modes are paired with the twin's by their shape (MAC over the nodes both meshes share), not by
// their number: the bundled cantilever strip at 30 x 6 elements has a torsion and a bending mode
// (its 7th and 8th) that its twin (15 x 3) orders the other way round (a third level, 8 x 2, would
// have fewer than 4 elements across: two levels)
TEST(ErrorBars, ModesArePairedWithTheTwinsByShape) {
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_scene(dir, "modal_cantilever_strip", "out", {"--set", "part[0].n1=30", "part[0].n2=6"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json bars = summary_of(dir + "/out")["error_bars"];
  for (const auto& [metric, other] : {std::pair{"frequency_7", 8}, std::pair{"frequency_8", 7}}) {
    const nlohmann::json& f = bars["metrics"][metric];
    ASSERT_EQ(f["notes"].size(), 1u) << f.dump(1);
    EXPECT_NE(f["notes"][0].get<std::string>().find("paired with the mesh twin's mode " + std::to_string(other) +
                                                    " by its shape"),
              std::string::npos)
        << f.dump(1);
    EXPECT_FALSE(f["bar"].is_null()) << f.dump(1);
  }
  // the modes that keep their order are paired by number, without a note
  EXPECT_TRUE(bars["metrics"]["frequency_1"]["notes"].empty()) << bars["metrics"]["frequency_1"].dump(1);
  EXPECT_NE(r.out.find("paired with the mesh twin's mode 8"), std::string::npos) << r.out;
}

// error_bars.md §6: the bundled pulled cylinder (Sze 3.5) passes two limit points; its mesh twin at
// half the counts passes none. Its metrics get a flag, not a bar; the run warns on the console and
// records the difference among its path's events in summary.json
TEST(ErrorBars, ATwinWhosePathDiffersInKindIsAnEventAndAWarning) {
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_scene(dir, "pulled_cylinder", "out", {"--error-bar", "two"}, 600);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json s = summary_of(dir + "/out");
  int limit_points = 0, differs = 0;
  for (const auto& e : s["events"]) {
    limit_points += e["kind"] == "limit_point";
    differs += e["kind"] == "twin_path_differs";
  }
  ASSERT_EQ(limit_points, 2) << s["events"].dump(1);
  ASSERT_EQ(s["error_bars"]["twins"][0]["events"].size(), 0u) << s["error_bars"]["twins"].dump(1);
  EXPECT_EQ(differs, 1) << s["events"].dump(1);
  for (const auto& [name, m] : s["error_bars"]["metrics"].items()) {
    ASSERT_FALSE(m["flags"].empty()) << name;
    EXPECT_NE(m["flags"][0].get<std::string>().find("path differs in kind"), std::string::npos) << name;
    EXPECT_TRUE(m["bar"].is_null()) << name;
  }
  EXPECT_NE(r.err.find("warning: error bars: the mesh twin's path differs in kind"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("twin_path_differs"), std::string::npos) << r.out;
}

// the cantilever roll-up against its closed form (u/L = sin t / t - 1, w/L = (1 - cos t) / t at
// t = M L / EI; the scene's header): its coarsest twin (5 x 2) diverges before the full roll-up,
// and the estimate falls back to the two levels that completed (20 x 2 and 10 x 2, formal order,
// F_s = 3) instead of flagging every metric; the estimates are within 1/3-3 of the true errors
TEST(ErrorBars, AFailedThirdLevelLeavesTwoAgainstTheClosedForm) {
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_scene(dir, "cantilever_rollup", "out", {"--error-bar", "three"}, 600);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json bars = summary_of(dir + "/out")["error_bars"];
  ASSERT_EQ(bars["levels"], 3) << "--error-bar three";
  const double L = 12.0, pi = std::acos(-1.0);
  const std::map<std::string, double> exact = {
      {"tip_u_half", -L}, {"tip_w_half", 2.0 * L / pi}, {"tip_u_full", -L}};
  for (const auto& [name, reference] : exact) {
    const nlohmann::json& m = bars["metrics"][name];
    ASSERT_TRUE(m["flags"].empty()) << name << m.dump(1);
    ASSERT_EQ(m["notes"].size(), 1u) << name << m.dump(1);
    EXPECT_EQ(m["notes"][0].get<std::string>(), "mesh: two levels, the formal order (the mesh_coarser twin ended diverged)");
    EXPECT_EQ(m["sources"][0]["safety_factor"], 3.0) << name;
    const double true_error = m["value"].get<double>() - reference;
    const double effectivity = m["estimate"].get<double>() / true_error;
    EXPECT_GT(effectivity, 1.0 / 3.0) << name << ": true " << true_error << m.dump(1);
    EXPECT_LT(effectivity, 3.0) << name << ": true " << true_error << m.dump(1);
  }
}

TEST(ErrorBars, ACoarseRoofIsFlaggedNotGivenASmallBar) {
  // MacNeal & Harder (1985), problem 3: the Scordelis-Lo roof's midside deflection 0.3024. From the
  // STEP part meshed free (part.mesh_pattern = "free") at mesh_size = 3 the run is 2.7 % high,
  // while its twin at 6 lands within 0.2 % of it: two levels would print a bar of 0.3 %, a ninth of
  // the error. By default a static run has three levels, and 3, 6, 12 do not converge
  // monotonically: the metric must be flagged, or carry a bar of at least a third of the true error
  // (the rule)
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_scene(dir, "scordelis_lo_roof_cad", "out",
                                 {"--set", "part[0].mesh_size=3", "part[0].mesh_pattern=free"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json bars = summary_of(dir + "/out")["error_bars"];
  EXPECT_EQ(bars["levels"], 3) << "auto: three levels in statics of a Gmsh-meshed part";
  const nlohmann::json m = bars["metrics"]["w_midside"];
  const double true_error = std::abs(m["value"].get<double>() - 0.3024);
  ASSERT_GT(true_error, 0.02 * 0.3024) << "the case must keep its error above 2 %";
  if (m["flags"].empty()) { EXPECT_GE(m["bar"].get<double>(), true_error / 3) << m.dump(1); }
  else EXPECT_NE(r.out.find("w_midside"), std::string::npos) << r.out;
  EXPECT_FALSE(m["flags"].empty()) << "3, 6, 12 are not in the asymptotic range: " << m.dump(1);
}

// The same roof as mapped grids (the default part.mesh_pattern): sizes 12, 6, 3 converge
// monotonically, and the estimate at size 3 lies within 1/3-3 of the true error against MacNeal &
// Harder's 0.3024 (measured 3.9 % for 1.84 %, (R6a)); at size 1.5 the true error (0.04 %) is
// below the 0.5 %, and the bar must still hold it
TEST(ErrorBars, TheMappedRoofsEstimateBracketsMacNealAndHarder) {
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_scene(dir, "scordelis_lo_roof_cad", "out", {"--set", "part[0].mesh_size=3"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json s = summary_of(dir + "/out");
  EXPECT_NE(s["mesh_import"].dump().find("meshed as mapped"), std::string::npos) << s["mesh_import"].dump();
  EXPECT_EQ(s["error_bars"]["levels"], 3);
  expect_brackets(s["error_bars"]["metrics"]["w_midside"], 0.3024, "w_midside at size 3");
  const ProcResult fine = run_scene(dir, "scordelis_lo_roof_cad", "fine", {});
  ASSERT_EQ(fine.exit_code, 0) << fine.describe();
  const nlohmann::json m = summary_of(dir + "/fine")["error_bars"]["metrics"]["w_midside"];
  ASSERT_TRUE(m["flags"].empty()) << m.dump(1);
  EXPECT_GE(m["bar"].get<double>(), std::abs(m["value"].get<double>() - 0.3024)) << m.dump(1);
}

// Sze, Liu & Lo (2004), §3.4: the hemisphere with an 18 degree hole under alternating radial
// forces, ABAQUS S4R reference at F = 200 and 400 (assets/reference/sze2004_34_hemisphere_18deg_hole.csv).
// At 8 x 8 the run is 6-11 % short, and its 4 x 4 twin's two-level estimate (the default on a
// generated mesh) brackets each error. Asked for three levels, the third (2 x 2, fewer than 4
// elements across) is not made, and the same two-level estimate is given with the reason
// (error_bars.md §5: 8, 4, 2 observed orders of 0.2-0.56 and flagged every metric)
TEST(ErrorBars, TheCoarseHemisphereAgainstSze) {
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_scene(dir, "hemisphere_18deg_h004", "out", {"--set", "part[0].n1=8", "part[0].n2=8"});
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json bars = summary_of(dir + "/out")["error_bars"];
  EXPECT_EQ(bars["levels"], 2) << bars.dump(1);
  const ProcResult three = run_scene(dir, "hemisphere_18deg_h004", "three",
                                     {"--error-bar", "three", "--set", "part[0].n1=8", "part[0].n2=8"});
  ASSERT_EQ(three.exit_code, 0) << three.describe();
  const nlohmann::json asked = summary_of(dir + "/three")["error_bars"];
  EXPECT_EQ(asked["levels"], 2) << asked.dump(1);
  EXPECT_NE(asked["missing"].dump().find("fewer than 4 across"), std::string::npos) << asked["missing"].dump();
  for (const auto& [name, m] : bars["metrics"].items()) {  // the same two levels
    EXPECT_EQ(asked["metrics"][name]["estimate"], m["estimate"]) << name;
    EXPECT_EQ(asked["metrics"][name]["bar"], m["bar"]) << name;
  }
  const std::map<std::string, double> sze = {{"disp_outward_point_F200", 3.406}, {"disp_inward_point_F200", 5.902},
                                             {"disp_outward_point_F400", 4.067}, {"disp_inward_point_F400", 8.178}};
  for (const auto& [name, reference] : sze) {
    SCOPED_TRACE(name);
    expect_brackets(bars["metrics"][name], reference, name);
  }
}

TEST(ErrorBars, AFixedMeshFileSaysWhyItHasNoMeshEstimate) {
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_scene(dir, "clamped_plate_pressure_obj", "out");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json m = summary_of(dir + "/out")["error_bars"]["metrics"]["w_centre"];
  EXPECT_TRUE(m["bar"].is_null()) << m.dump(1);
  ASSERT_EQ(m["missing"].size(), 1u) << m.dump(1);
  EXPECT_NE(m["missing"][0].get<std::string>().find("is a fixed mesh"), std::string::npos) << m.dump(1);
  EXPECT_NE(r.out.find("no mesh estimate"), std::string::npos) << "said where the user looks:\n" << r.out;
  // the one mesh measure a fixed mesh has, said as such: the field indicator's global error
  EXPECT_NE(m["missing"][0].get<std::string>().find("the field indicator alone puts the solution's energy-norm error"),
            std::string::npos)
      << m.dump(1);
  EXPECT_GT(summary_of(dir + "/out")["field_error"]["relative_energy_error"].get<double>(), 0.0);
}

TEST(ErrorBars, CtrlCWhileTheTwinsAreSolvedEndsTheRunInterrupted) {
  // the solve completed, its twins did not: the run must not call itself completed (the brief's
  // stopped-run rule), and both records say so, with every frame of the run kept
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  Child child({"run", scene_path("double_pendulum_shells"), "--out", out, "--no-frames", "--no-plots", "--set",
               "solver.end=0.2"},
              dir + "/run");
  ASSERT_TRUE(child.started());
  const std::string err_log = dir + "/run.stderr.txt";
  const auto t0 = std::chrono::steady_clock::now();
  while (read_text(err_log).find("error bars: solving the coarser twins") == std::string::npos && child.running() &&
         std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() < 120 * slowdown())
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_NE(read_text(err_log).find("error bars: solving the coarser twins"), std::string::npos)
      << child.wait(1).describe();
  ASSERT_TRUE(child.send(SIGINT));
  const ProcResult r = child.wait(60);
  EXPECT_EQ(r.exit_code, 130) << r.describe();
  const nlohmann::json s = summary_of(out);
  EXPECT_EQ(s["status"], "interrupted") << s.dump(1);
  EXPECT_NE(s["reason"].get<std::string>().find("error-bar twins"), std::string::npos) << s["reason"];
  std::string err;
  const auto reader = io::ResultReader::open(out + "/results.h5", &err);
  ASSERT_TRUE(reader) << err;
  EXPECT_EQ(reader->outcome().status, RunStatus::interrupted) << "one outcome in both records";
  EXPECT_GT(reader->frame_count(), 1);
}

TEST(ErrorBars, OffByFlagOrSceneKey) {
  const std::string dir = fresh_test_dir();
  const ProcResult flag = run_scene(dir, "clamped_plate_pressure", "flag", {"--error-bar", "off"});
  ASSERT_EQ(flag.exit_code, 0) << flag.describe();
  EXPECT_FALSE(summary_of(dir + "/flag").contains("error_bars"));
  EXPECT_EQ(flag.out.find(" ± "), std::string::npos) << flag.out;
  const ProcResult key = run_scene(dir, "clamped_plate_pressure", "key", {"--set", "output.error_bar=false"});
  ASSERT_EQ(key.exit_code, 0) << key.describe();
  EXPECT_FALSE(summary_of(dir + "/key").contains("error_bars"));
  // the flag wins over the key
  const ProcResult both = run_scene(dir, "clamped_plate_pressure", "both", {"--error-bar", "on", "--set", "output.error_bar=false"});
  ASSERT_EQ(both.exit_code, 0) << both.describe();
  EXPECT_TRUE(summary_of(dir + "/both").contains("error_bars"));
  const ProcResult bad = run_scene(dir, "clamped_plate_pressure", "bad", {"--error-bar", "maybe"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.err.find("--error-bar"), std::string::npos) << bad.describe();
}

TEST(ErrorBars, TheFieldIndicatorIsLargestAtTheHole) {
  // The plate with a hole (Kirsch; the scene's header) on an even mesh (mesh_size 1.5 everywhere,
  // the hole's own refinement undone): the stress concentration at the hole is what the mesh
  // misses. A refinement study of this scene (docs/validation/error-bars.md, "Field indicator"):
  // sigma_xx at the hole reads 2.71, 2.75, 2.96 MPa at mesh_size 1.5, 0.75, 0.375 against 3.04 on
  // 16 257 quads (-11 % here), while u_x at r = 2a moves 3 %. The indicator must put its largest
  // element within one radius of the hole's edge (measured: r = 1.65) and half of its error in a
  // few elements (measured: 5 %).
  const std::string dir = fresh_test_dir();
  const std::vector<std::string> args = {"run", scene_path("plate_with_hole_geo"), "--out", dir + "/even", "--quiet",
                                         "--error-bar", "two", "--set", "part[0].local_sizes=[1.5]"};
  const ProcResult r = run_flexframe(args, dir + "/even", "", 300);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json f = summary_of(dir + "/even")["field_error"];
  ASSERT_TRUE(f.is_object()) << r.describe();
  const double x = f["largest_at"][0], y = f["largest_at"][1];
  EXPECT_LT(std::hypot(x, y), 2.0) << f.dump(1);  // hole radius a = 1 at the origin
  EXPECT_LT(f["half_error_element_fraction"].get<double>(), 0.15) << f.dump(1);
  EXPECT_GT(f["relative_energy_error"].get<double>(), 0.005);
  EXPECT_LT(f["relative_energy_error"].get<double>(), 0.2);
  EXPECT_EQ(f["picture"], "plots/error_indicator.png");
  EXPECT_TRUE(fs::is_regular_file(dir + "/even/plots/error_indicator.png"));
  EXPECT_NE(r.out.find("field error (recovered stresses)"), std::string::npos) << r.out;
  // the field is stored with the frames: replay draws it
  const ProcResult rp = run_flexframe({"replay", dir + "/even", "--out", dir + "/replay", "--no-plots", "--field",
                                       "error_indicator", "--size", "320x240"},
                                      dir + "/replay");
  EXPECT_EQ(rp.exit_code, 0) << rp.describe();
  // off with the bars: no field, no summary entry
  const ProcResult off = run_flexframe({"run", scene_path("plate_with_hole_geo"), "--out", dir + "/off", "--quiet",
                                        "--no-frames", "--error-bar", "off"},
                                       dir + "/off", "", 300);
  ASSERT_EQ(off.exit_code, 0) << off.describe();
  EXPECT_FALSE(summary_of(dir + "/off").contains("field_error"));
  EXPECT_FALSE(fs::exists(dir + "/off/plots/error_indicator.png"));
}

TEST(ErrorBars, ATwinThatReadsItsProbeAtAnotherNodeIsFlagged) {
  // 9 x 9 elements and a probe at (0.45, 0.45): the run reads node (4/9, 4/9); its twin of 5 x 5
  // has no node there and reads (0.4, 0.4), 0.063 away. The difference of the two readings is the
  // deflection's change over that distance, not a discretization error: no number, a flag naming
  // both points (error_bars.md §6). At 8 x 8 with the probe on a node of both, there is a bar.
  const std::string dir = fresh_test_dir();
  const ProcResult odd = run_scene(dir, "clamped_plate_pressure", "odd",
                                   {"--error-bar", "two", "--set", "part[0].n1=9", "part[0].n2=9",
                                    "probe[0].point=[0.45,0.45,0.0]"});
  ASSERT_EQ(odd.exit_code, 0) << odd.describe();
  const nlohmann::json m = summary_of(dir + "/odd")["error_bars"]["metrics"]["w_centre"];
  ASSERT_EQ(m["flags"].size(), 1u) << m.dump(1);
  const std::string flag = m["flags"][0];
  EXPECT_NE(flag.find("has no node at the probe's point"), std::string::npos) << flag;
  EXPECT_NE(flag.find("(0.4, 0.4, 0)"), std::string::npos) << flag;
  EXPECT_NE(flag.find("(0.4444, 0.4444, 0)"), std::string::npos) << flag;
  EXPECT_FALSE(m.contains("bar") && m["bar"].is_number()) << m.dump(1);
  const ProcResult even = run_scene(dir, "clamped_plate_pressure", "even",
                                    {"--error-bar", "two", "--set", "part[0].n1=8", "part[0].n2=8"});
  ASSERT_EQ(even.exit_code, 0) << even.describe();
  EXPECT_TRUE(summary_of(dir + "/even")["error_bars"]["metrics"]["w_centre"]["flags"].empty());
}

// a 1-D f64 dataset of results.h5, empty when it is not there
std::vector<double> read_series(hid_t file, const std::string& name) {
  const hid_t d = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
  if (d < 0) return {};
  const hid_t sp = H5Dget_space(d);
  hsize_t n = 0;
  if (H5Sget_simple_extent_ndims(sp) == 1) H5Sget_simple_extent_dims(sp, &n, nullptr);
  std::vector<double> v(n);
  if (n > 0 && H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) < 0) v.clear();
  H5Sclose(sp);
  H5Dclose(d);
  return v;
}

TEST(ErrorBars, TheTwinsCurvesAreStoredAndPlottedBesideTheRuns) {
  // results.h5 keeps each twin's probe history (results_layout.md /error_bar_twins), whose last
  // value is the twin's metric in summary.json, and the probe's plot draws the twins' curves
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/run";
  const ProcResult r = run_flexframe({"run", scene_path("clamped_plate_pressure"), "--out", out, "--quiet",
                                      "--no-frames", "--error-bar", "two"},
                                     out, "", 300);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json twins = summary_of(out)["error_bars"]["twins"];
  ASSERT_EQ(twins.size(), 1u);
  ASSERT_EQ(twins[0]["name"], "mesh");
  const hid_t f = H5Fopen((out + "/results.h5").c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  const std::vector<double> t = read_series(f, "/error_bar_twins/mesh/time");
  const std::vector<double> w = read_series(f, "/error_bar_twins/mesh/probes/w_centre");
  H5Fclose(f);
  ASSERT_GE(t.size(), 2u);  // the reference state and the loaded one
  ASSERT_EQ(w.size(), t.size());
  EXPECT_EQ(t.back(), 1.0);  // the load factor at the end of the path
  EXPECT_EQ(w.back(), twins[0]["metrics"]["w_centre"].get<double>());
  // the run's own curve lies above its 4 x 4 twin's (the coarser plate is stiffer)
  EXPECT_GT(summary_of(out)["metrics"]["w_centre"].get<double>(), w.back());
  EXPECT_TRUE(fs::is_regular_file(out + "/plots/w_centre.png"));
}

}  // namespace
}  // namespace ff::cli::test
