// Shell benchmark scenes run as bundled (assets/scenes), against their references:
// - cantilever_rollup: analytic pure bending (the shell paper, Zhang, Liu, Zhang & Liu 2022, ex. 1; Sze et al. 2004 §3.2)
// - hemisphere_18deg_h004: ABAQUS S4R path of Sze et al. 2004 §3.4 (assets/reference/
//   sze2004_34_hemisphere_18deg_hole.csv rows P/Pmax = 0.5 and 1.0) and the shell paper's 3.41 / 5.88 at F = 200.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "core/scene/scene.h"

namespace {
ff::Metrics run(const std::string& scene, ff::RunOutcome* outcome = nullptr) {
  ff::scene::LoadedScene s = ff::scene::load_scene(std::string(FF_SOURCE_DIR) + "/assets/scenes/" + scene + ".toml");
  std::atomic<bool> stop{false};
  const ff::RunOutcome o = s.simulation->run([](ff::Frame&&) {}, stop);
  if (outcome) *outcome = o;
  EXPECT_EQ(o.status, ff::RunStatus::completed) << o.reason;
  return s.simulation->metrics();
}
double get(const ff::Metrics& m, const std::string& k) {
  for (const auto& [n, v] : m)
    if (n == k) return v;
  ADD_FAILURE() << "metric " << k << " missing";
  return NAN;
}
double rel(double v, double ref) { return std::abs(v - ref) / std::abs(ref); }
}  // namespace

TEST(ShellScenes, CantileverRollupMatchesPureBending) {
  const ff::Metrics m = run("cantilever_rollup");
  // t = pi at M_max / 2: u = -12, w = 24 / pi; t = 2 pi: closed circle. Measured: 0.44 %, 0.35 %, 1.8 % of L.
  EXPECT_LT(rel(get(m, "tip_u_half"), -12.0), 0.006);
  EXPECT_LT(rel(get(m, "tip_w_half"), 24.0 / M_PI), 0.006);
  EXPECT_LT(std::abs(get(m, "tip_u_full") + 12.0), 0.025 * 12.0);
  EXPECT_LT(std::abs(get(m, "tip_w_full")), 0.005 * 12.0);
}

TEST(ShellScenes, HemisphereH004MatchesSzeAndThePaper) {
  const ff::Metrics m = run("hemisphere_18deg_h004");
  // Sze et al. (S4R): 3.406 / 5.902 at F = 200 and 4.067 / 8.178 at F = 400. Measured -0.3 %, -0.8 %, -0.4 %, -0.7 %.
  EXPECT_LT(rel(get(m, "disp_outward_point_F200"), 3.406), 0.02);
  EXPECT_LT(rel(get(m, "disp_inward_point_F200"), 5.902), 0.02);
  EXPECT_LT(rel(get(m, "disp_outward_point_F400"), 4.067), 0.02);
  EXPECT_LT(rel(get(m, "disp_inward_point_F400"), 8.178), 0.02);
  // the shell paper's ABAQUS S4R 24x24 values at F = 200
  EXPECT_LT(rel(get(m, "disp_outward_point_F200"), 3.41), 0.02);
  EXPECT_LT(rel(get(m, "disp_inward_point_F200"), 5.88), 0.02);
}

// Pull-out of an open cylinder (Sze et al. 2004 §3.5, last row of assets/reference/
// sze2004_35_pullout_open_cylinder.csv: 2.768, 4.551, 3.269 at P = 40000). The shell paper's 24x16 mesh
// against the reference's 24x36 S4R; measured +1.2 %, +2.1 %, -1.5 % after passing the snap at P ~ 20500.
TEST(ShellScenes, PulledCylinderMatchesSze) {
  const ff::Metrics m = run("pulled_cylinder");
  EXPECT_LT(rel(get(m, "w_A"), 2.768), 0.03);
  EXPECT_LT(rel(get(m, "minus_u_B"), 4.551), 0.03);
  EXPECT_LT(rel(get(m, "minus_u_C"), 3.269), 0.03);
}

#include "core/scene/reference_csv.h"

namespace {
// the reference path's limit point, minimum after it and value at P/Pmax = 1 on its last branch,
// computed exactly like the scene metrics (parabola through the samples around the first maximum)
struct RoofReference {
  double limit_load, w_at_limit, min_after, w_final;
};
RoofReference roof_reference(const std::string& file) {
  const ff::scene::ReferenceTable t = ff::scene::read_reference_csv(std::string(FF_SOURCE_DIR) + "/assets/reference/" + file);
  std::vector<double> P = t.column("P_over_Pmax"), w = t.column("minus_w_centre");
  for (double& p : P) p *= 3000.0;
  std::size_t i = 1;
  while (!(P[i] > P[i - 1] && P[i] >= P[i + 1])) ++i;
  const double a = 0.5 * (P[i - 1] + P[i + 1]) - P[i], b = 0.5 * (P[i + 1] - P[i - 1]), s = -b / (2 * a);
  RoofReference r;
  r.limit_load = P[i] + b * s + a * s * s;
  r.w_at_limit = w[i] + 0.5 * (w[i + 1] - w[i - 1]) * s + (0.5 * (w[i - 1] + w[i + 1]) - w[i]) * s * s;
  r.min_after = *std::min_element(P.begin() + i, P.end());
  const std::size_t n = P.size();  // last branch: interpolate between the rows bracketing P = 3000
  std::size_t k = n - 1;
  while (k > i && !(P[k - 1] <= 3000.0 && P[k] >= 3000.0)) --k;
  r.w_final = w[k - 1] + (w[k] - w[k - 1]) * (3000.0 - P[k - 1]) / (P[k] - P[k - 1]);
  return r;
}
}  // namespace

// Hinged roofs (Sze et al. 2004 §3.8, cases a and d, P_max = 3000 as inferred in the reference files).
// Measured against the reference computed the same way: h = 12.7: limit load -1.0 %, w at limit -0.3 %,
// w at P = 3000 +1.2 %; h = 6.35: limit load -0.03 %, w at limit +3.1 % (a very flat top), snap-back
// minimum and w at P = 3000 within a few percent.
TEST(ShellScenes, HingedRoofsMatchSzeThroughSnapThroughAndSnapBack) {
  const struct {
    const char* scene;
    const char* file;
  } cases[] = {{"hinged_roof_h127", "sze2004_38a_hinged_roof_h12p7_iso.csv"},
               {"hinged_roof_h635", "sze2004_38d_hinged_roof_h6p35_iso.csv"}};
  for (const auto& c : cases) {
    const ff::Metrics m = run(c.scene);
    const RoofReference r = roof_reference(c.file);
    EXPECT_LT(rel(get(m, "limit_load"), r.limit_load), 0.02) << c.scene;
    EXPECT_LT(rel(get(m, "w_at_limit"), r.w_at_limit), 0.05) << c.scene;
    EXPECT_LT(std::abs(get(m, "min_load_after_limit") - r.min_after), 0.03 * r.limit_load) << c.scene;
    EXPECT_LT(rel(get(m, "w_final"), r.w_final), 0.03) << c.scene;
  }
  // the thin roof really snaps back: its load goes negative before it rises again
  EXPECT_LT(roof_reference("sze2004_38d_hinged_roof_h6p35_iso.csv").min_after, 0.0);
}

namespace {
// the load-deflection path of a static scene, every arc-length step (output.frame_every = 1); the
// scene's steps must be fine enough for linear interpolation between them (a chord of a curved
// path lies on one side of it: the roofs' default steps read 3-6 % softer than the path itself)
struct LoadPath {
  std::vector<double> load, w;
  ff::Metrics metrics;
};
LoadPath load_path(const std::string& scene, const std::string& probe) {
  ff::scene::LoadedScene s = ff::scene::load_scene(std::string(FF_SOURCE_DIR) + "/assets/scenes/" + scene + ".toml",
                                                   {"output.frame_every=1"});
  std::size_t load_index = 0, probe_index = 0;
  const auto& probes = s.simulation->info().probes;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    if (probes[i].name == "load") load_index = i;
    if (probes[i].name == probe) probe_index = i;
  }
  LoadPath p;
  std::atomic<bool> stop{false};
  const ff::RunOutcome o = s.simulation->run(
      [&](ff::Frame&& f) {
        p.load.push_back(f.probes[load_index]);
        p.w.push_back(f.probes[probe_index]);
      },
      stop);
  EXPECT_EQ(o.status, ff::RunStatus::completed) << o.reason;
  p.metrics = s.simulation->metrics();
  return p;
}
// Deflection of `path` at `load` on the branch that contains deflection `w_near` (the path is
// monotonic in w for these roofs): the crossing of `load` whose deflection is closest to w_near.
double deflection_at_load(const LoadPath& path, double load, double w_near) {
  double best = NAN;
  for (std::size_t k = 1; k < path.load.size(); ++k) {
    const double a = path.load[k - 1], b = path.load[k];
    if ((a - load) * (b - load) > 0 || a == b) continue;
    const double w = path.w[k - 1] + (path.w[k] - path.w[k - 1]) * (load - a) / (b - a);
    if (std::isnan(best) || std::abs(w - w_near) < std::abs(best - w_near)) best = w;
  }
  return best;
}
}  // namespace

// Laminated hinged roofs, h = 12.7, [0/90/0] and [90/0/90] (Sze, Liu & Lo 2004 §3.8, Table 9 cases b
// and c as transcribed in assets/reference/sze2004_38{b,c}_*.csv; ABAQUS S4R). 0 degrees along the
// roof's axis (fibre_reference = "v"): around the arc instead swaps the two layups' answers
// (docs/validation/laminates.md). Checked: the first limit load within 2 %, and the deflection at
// every tabulated load within 3 % on its own branch (rising, falling after the limit, rising again),
// except the rows within 5 % of a turning point's load, where a deflection at a given load is
// ill-conditioned (a 1 % load error moves it by tens of percent).
TEST(ShellScenes, LaminatedHingedRoofsFollowSzeThroughTheSnap) {
  const struct {
    const char* scene;
    const char* file;
  } cases[] = {{"hinged_roof_h127_0_90_0", "sze2004_38b_hinged_roof_h12p7_0_90_0.csv"},
               {"hinged_roof_h127_90_0_90", "sze2004_38c_hinged_roof_h12p7_90_0_90.csv"}};
  for (const auto& c : cases) {
    const LoadPath path = load_path(c.scene, "minus_w_centre");
    const RoofReference r = roof_reference(c.file);
    EXPECT_LT(rel(get(path.metrics, "limit_load"), r.limit_load), 0.02) << c.scene;
    EXPECT_LT(rel(get(path.metrics, "w_at_limit"), r.w_at_limit), 0.03) << c.scene;
    const ff::scene::ReferenceTable t =
        ff::scene::read_reference_csv(std::string(FF_SOURCE_DIR) + "/assets/reference/" + c.file);
    const std::vector<double> P = t.column("P_over_Pmax"), W = t.column("minus_w_centre");
    int compared = 0;
    double worst = 0.0;
    for (std::size_t i = 1; i < P.size(); ++i) {
      const double load = 3000.0 * P[i];
      const bool near_turn = std::abs(load - r.limit_load) < 0.05 * r.limit_load ||
                             std::abs(load - r.min_after) < 0.05 * r.limit_load;
      if (near_turn || load > path.load.back()) continue;
      const double w = deflection_at_load(path, load, W[i]);
      ASSERT_FALSE(std::isnan(w)) << c.scene << " never reaches P = " << load;
      worst = std::max(worst, rel(w, W[i]));
      EXPECT_LT(rel(w, W[i]), 0.03) << c.scene << " at P = " << load << ": " << w << " against " << W[i];
      ++compared;
    }
    EXPECT_GE(compared, 20) << c.scene;
    std::printf("%s: limit load %.1f (reference %.1f), w there %.3f (%.3f); %d tabulated loads, worst %.2f %%\n",
                c.scene, get(path.metrics, "limit_load"), r.limit_load, get(path.metrics, "w_at_limit"), r.w_at_limit,
                compared, 100 * worst);
  }
}
