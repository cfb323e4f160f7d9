// Scripted scenes ([[timeline]], core/scene/timeline.h): the camera path's interpolation, the
// parameter changes the simulations apply exactly at their time, and bad timelines refused at
// the offending key.

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/scene/scene.h"
#include "core/scene/timeline.h"

namespace ff::scene {
namespace {

namespace fs = std::filesystem;

std::string bundled(const std::string& name) { return std::string(FF_SOURCE_DIR) + "/assets/scenes/" + name + ".toml"; }

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// a scene file in the test's own folder: `text` as given
std::string write_scene(const std::string& name, const std::string& text) {
  const fs::path dir = fs::path(FF_BINARY_DIR) / "test_out" / "unit" / "timeline";
  fs::create_directories(dir);
  const std::string path = (dir / (name + ".toml")).string();
  std::ofstream(path) << text;
  return path;
}

std::vector<Frame> run(Simulation& sim) {
  std::vector<Frame> frames;
  std::atomic<bool> stop{false};
  const RunOutcome o = sim.run([&](Frame&& f) { frames.push_back(std::move(f)); }, stop);
  EXPECT_EQ(o.status, RunStatus::completed) << o.reason;
  return frames;
}

int probe(const RunInfo& info, const std::string& name) {
  for (std::size_t k = 0; k < info.probes.size(); ++k)
    if (info.probes[k].name == name) return static_cast<int>(k);
  ADD_FAILURE() << "no probe " << name;
  return 0;
}

double mean_z(const Frame& f) {
  double z = 0.0;
  for (std::size_t i = 2; i < f.points.size(); i += 3) z += f.points[i];
  return z / static_cast<double>(f.points.size() / 3);
}

// ---- camera path ---------------------------------------------------------------------------

TEST(Timeline, ViewStringsAsCameraAccepts) {
  auto v = parse_view_angles("iso,1.5");
  ASSERT_TRUE(v);
  EXPECT_NEAR(v->azimuth_deg, -45.0, 1e-12);
  EXPECT_NEAR(v->elevation_deg, 35.2643896827547, 1e-9);
  EXPECT_EQ(v->zoom, 1.5);
  v = parse_view_angles("-60, 25, 2");
  ASSERT_TRUE(v);
  EXPECT_EQ(v->azimuth_deg, -60.0);
  EXPECT_EQ(v->elevation_deg, 25.0);
  EXPECT_EQ(v->zoom, 2.0);
  EXPECT_TRUE(parse_view_angles("auto")->automatic);
  EXPECT_EQ(parse_view_angles("top")->elevation_deg, 90.0);
  for (const char* bad : {"", "sideways", "10", "10,95", "iso,0", "iso,2,3", "1,2,3,4", "nan,0"})
    EXPECT_FALSE(parse_view_angles(bad)) << bad;
}

TEST(Timeline, CameraPathInterpolatesLinearlyInTime) {
  std::vector<CameraKey> path = {{1.0, "0,0", *parse_view_angles("0,0")},
                                 {3.0, "180,60,3", *parse_view_angles("180,60,3")},
                                 {4.0, "auto", *parse_view_angles("auto")},
                                 {5.0, "10,10", *parse_view_angles("10,10")}};
  EXPECT_FALSE(camera_at({}, 1.0));
  // before the first key: the first key; after the last: the last
  EXPECT_EQ(camera_at(path, 0.0)->azimuth_deg, 0.0);
  EXPECT_EQ(camera_at(path, 9.0)->azimuth_deg, 10.0);
  // half way between keys 0 and 1
  const ViewAngles mid = *camera_at(path, 2.0);
  EXPECT_NEAR(mid.azimuth_deg, 90.0, 1e-12);
  EXPECT_NEAR(mid.elevation_deg, 30.0, 1e-12);
  EXPECT_NEAR(mid.zoom, 2.0, 1e-12);
  EXPECT_NEAR(camera_at(path, 2.5)->azimuth_deg, 135.0, 1e-12);
  // `auto` cannot be interpolated: the earlier key holds until the next
  EXPECT_NEAR(camera_at(path, 3.5)->azimuth_deg, 180.0, 1e-12);
  EXPECT_TRUE(camera_at(path, 4.5)->automatic);
}

TEST(Timeline, BundledSceneCarriesItsCameraPath) {
  const LoadedScene s = load_scene(bundled("hub_beam_timeline"));
  ASSERT_EQ(s.output.camera_path.size(), 2u);
  EXPECT_EQ(s.output.camera_path[1].at, 2.5);
  // the same path read back from the scene text (as replay does from results.h5)
  const auto again = camera_path_from_text(s.simulation->info().scene_text, "stored");
  ASSERT_EQ(again.size(), 2u);
  EXPECT_EQ(again[1].view.zoom, 1.3);
  // and the events are in the run's settings
  int events = 0;
  for (const auto& [k, v] : s.simulation->info().settings)
    if (k.rfind("timeline[", 0) == 0) ++events;
  EXPECT_EQ(events, 6);  // at + camera, at + torque_scale, at + camera
}

// ---- parameter changes -----------------------------------------------------------------------

// hub_beam_timeline switches the torque off at t = 1.23 s, inside the step 1.20 -> 1.25: the step
// is split there, and from then on the hub's angular momentum (eq. 14) is conserved.
TEST(Timeline, HubTorqueSwitchedOffAtItsTime) {
  LoadedScene s = load_scene(bundled("hub_beam_timeline"));
  const std::vector<Frame> frames = run(*s.simulation);
  const RunInfo& info = s.simulation->info();
  const int torque = probe(info, "torque"), momentum = probe(info, "angular_momentum");
  const Frame* at = nullptr;
  for (const Frame& f : frames)
    if (std::abs(f.time - 1.23) < 1e-12) at = &f;
  ASSERT_TRUE(at) << "no frame at the change: the step was not split";
  EXPECT_NEAR(at->stats.dt, 0.03, 1e-12);
  const double p_off = at->probes[momentum];
  EXPECT_GT(std::abs(p_off), 0.1);  // the drive put momentum in
  double peak = 0.0;
  for (const Frame& f : frames) {
    peak = std::max(peak, std::abs(f.probes[momentum]));
    if (f.time > 1.23 + 1e-12) {
      EXPECT_EQ(f.probes[torque], 0.0) << "t = " << f.time;
      // trapezoidal Newmark (beta = 1/4) conserves the momentum of the nonlinear hub-beam only to
      // O(dt^2): at dt = 0.05 s it wanders by ~5e-5 relative (measured), against the ~0.67 kg m^2/s
      // (~80 %) the drive would have added from 1.23 s to 2.5 s
      EXPECT_NEAR(f.probes[momentum], p_off, 2e-4 * std::abs(p_off)) << "t = " << f.time;
    } else if (f.time > 0.0) {
      EXPECT_GT(f.probes[torque], 0.0) << "t = " << f.time;
    }
  }
  // later steps stay on the 0.05 s grid
  EXPECT_NEAR(frames.back().time, 2.5, 1e-12);
  EXPECT_NEAR(frames[frames.size() - 2].time, 2.45, 1e-12);
}

// shell dynamics: gravity switched off at t = 0 leaves the pendulum at rest; a change mid-run
// leaves every frame before it as without the change and alters every frame after it
TEST(Timeline, GravityChangeShowsFromItsTime) {
  const std::string base = read_text(bundled("double_pendulum_shells"));
  const std::vector<std::string> short_run = {"solver.end=0.003", "solver.output_every=1"};
  auto frames_of = [&](const std::string& name, const std::string& timeline) {
    LoadedScene s = load_scene(write_scene(name, base + timeline), short_run);
    return run(*s.simulation);
  };
  const std::vector<Frame> plain = frames_of("plain", "");
  const std::vector<Frame> off = frames_of("off", "\n[[timeline]]\nat = 0.0\ngravity = [0.0, 0.0, 0.0]\n");
  ASSERT_EQ(off.size(), plain.size());
  for (const Frame& f : off)
    for (std::size_t i = 0; i < f.points.size(); ++i) { ASSERT_NEAR(f.points[i], f.base_points[i], 1e-12); }
  EXPECT_NE(plain.back().points, plain.front().points);  // with gravity it falls

  // reversed gravity from t = 0.00175 s (inside the 4th step of 5e-4 s)
  const std::vector<Frame> up = frames_of("up", "\n[[timeline]]\nat = 0.00175\ngravity = [0.0, 0.0, 9.81]\n");
  ASSERT_EQ(up.size(), plain.size() + 1);  // the split step
  // frames 0..3 (t <= 0.0015) as without the change; frame 4 is the change itself (t = 0.00175);
  // from frame 5 on, up[k] and plain[k - 1] are at the same time but under different gravity
  for (std::size_t k = 0; k < 4; ++k) { EXPECT_EQ(up[k].points, plain[k].points) << "t = " << up[k].time; }
  for (std::size_t k = 5; k < up.size(); ++k) {
    EXPECT_NEAR(up[k].time, plain[k - 1].time, 1e-15);
    // reversed gravity decelerates the fall: the mean height of the nodes stays higher
    EXPECT_NE(up[k].points, plain[k - 1].points) << "t = " << up[k].time;
    EXPECT_GT(mean_z(up[k]), mean_z(plain[k - 1])) << "t = " << up[k].time;
  }
  EXPECT_NEAR(up[4].time, 0.00175, 1e-15);
  EXPECT_NEAR(up[5].time, 0.002, 1e-15);  // the rest of the split step: back on the grid
}

// ---- bad input -------------------------------------------------------------------------------

std::string error_of(const std::string& name, const std::string& text) {
  try {
    load_scene(write_scene(name, text));
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(Timeline, BadEntriesAreRefusedAtTheirKey) {
  const std::string base = read_text(bundled("hub_beam_efg_tau1"));
  // unknown key (gravity is not a hub-beam parameter)
  std::string e = error_of("unknown", base + "\n[[timeline]]\nat = 1.0\ngravity = [0, 0, 1]\n");
  EXPECT_NE(e.find("unknown.toml:45"), std::string::npos) << e;
  EXPECT_NE(e.find("timeline[0].gravity"), std::string::npos) << e;
  // beyond the end, out of order, nothing changed, bad camera
  e = error_of("late", base + "\n[[timeline]]\nat = 11.0\ntorque_scale = 0\n");
  EXPECT_NE(e.find("late.toml:44"), std::string::npos) << e;
  EXPECT_NE(e.find("timeline[0].at"), std::string::npos) << e;
  e = error_of("order", base + "\n[[timeline]]\nat = 2.0\ntorque_scale = 0\n[[timeline]]\nat = 1.0\ntorque_scale = 1\n");
  EXPECT_NE(e.find("order.toml:47"), std::string::npos) << e;
  EXPECT_NE(e.find("ascending"), std::string::npos) << e;
  e = error_of("empty", base + "\n[[timeline]]\nat = 2.0\n");
  EXPECT_NE(e.find("changes nothing"), std::string::npos) << e;
  e = error_of("camera", base + "\n[[timeline]]\nat = 2.0\ncamera = \"sideways\"\n");
  EXPECT_NE(e.find("camera.toml:45"), std::string::npos) << e;
  EXPECT_NE(e.find("timeline[0].camera"), std::string::npos) << e;
  e = error_of("negative", base + "\n[[timeline]]\nat = -1.0\ntorque_scale = 0\n");
  EXPECT_NE(e.find("timeline[0].at"), std::string::npos) << e;
  // a gravity change needs the gravity effect
  std::string shells = read_text(bundled("double_pendulum_shells"));
  const std::size_t g = shells.find("\"gravity\", ");
  ASSERT_NE(g, std::string::npos);
  shells.erase(g, 11);
  e = error_of("no_gravity", shells + "\n[[timeline]]\nat = 0.1\ngravity = [0, 0, 0]\n");
  EXPECT_NE(e.find("timeline[0].gravity"), std::string::npos) << e;
  EXPECT_NE(e.find("lacks gravity"), std::string::npos) << e;
}

// Live edits (scene::change_live, the GUI's `set` of a live key): a change made from the
// publish callback at a frame takes effect from the next step and gives bitwise the same run as
// the same change written as a [[timeline]] entry at that frame's time (a step boundary).
TEST(LiveChange, TorqueChangedLiveEqualsTheSameTimelineChange) {
  const std::string text = read_text(bundled("hub_beam_timeline"));
  // the bundled scene without its timeline (its entries come last in the file), then one entry at 1.0 s
  const std::string base = text.substr(0, text.find("[[timeline]]"));
  LoadedScene planned = load_scene(write_scene("live_planned", base + "\n[[timeline]]\nat = 1.0\ntorque_scale = 0.25\n"));
  const std::vector<Frame> want = run(*planned.simulation);
  LoadedScene live = load_scene(write_scene("live_base", base));
  Simulation& sim = *live.simulation;
  const double tau0 = 1.0;  // hub_beam_timeline's torque amplitude
  EXPECT_NE(change_live(live, "torque.period", "3"), "");  // not a live key: the caller rebuilds
  std::vector<Frame> got;
  std::atomic<bool> stop{false};
  sim.run(
      [&](Frame&& f) {
        if (std::abs(f.time - 1.0) < 1e-12) {
          EXPECT_NE(change_live(live, "torque.amplitude", "x"), "");
          EXPECT_NE(change_live(live, "torque.amplitude", "-1"), "");
          EXPECT_EQ(change_live(live, "torque.amplitude", std::to_string(0.25 * tau0)), "");
        }
        got.push_back(std::move(f));
      },
      stop);
  ASSERT_EQ(got.size(), want.size());
  const int torque = probe(sim.info(), "torque");
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(got[i].time, want[i].time) << i;
    EXPECT_EQ(got[i].probes, want[i].probes) << "t = " << want[i].time;
  }
  EXPECT_NE(got.back().probes[torque], 0.0);  // a quarter of the drive, not none
}

TEST(LiveChange, GravityChangedLiveEqualsTheSameTimelineChange) {
  const std::string text = read_text(bundled("double_pendulum_shells"));
  const std::string coarse = text + "\n";  // shortened and coarsened through overrides
  const std::vector<std::string> o = {"solver.end=0.004", "solver.output_every=1", "part[0].n1=4", "part[0].n2=4",
                                      "part[1].n1=4", "part[1].n2=4"};
  LoadedScene planned = load_scene(write_scene("live_g_planned", coarse + "[[timeline]]\nat = 0.002\ngravity = [0.0, 0.0, 9.81]\n"), o);
  const std::vector<Frame> want = run(*planned.simulation);
  LoadedScene live = load_scene(write_scene("live_g_base", coarse), o);
  Simulation& sim = *live.simulation;
  std::vector<Frame> got;
  std::atomic<bool> stop{false};
  sim.run(
      [&](Frame&& f) {
        if (std::abs(f.time - 0.002) < 1e-12) { EXPECT_EQ(change_live(live, "gravity.g", "[0.0, 0.0, 9.81]"), ""); }
        got.push_back(std::move(f));
      },
      stop);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) { EXPECT_EQ(got[i].points, want[i].points) << "t = " << want[i].time; }
  EXPECT_NE(change_live(live, "gravity.g", "[1, 2]"), "");
}

// What the schema refuses never reaches the model, and the message says which key and why, as
// a scene file's value would; a key that is not live says which ones are.
TEST(LiveChange, RefusedValuesNameTheKey) {
  LoadedScene hub = load_scene(bundled("hub_beam_timeline"));
  std::string e = change_live(hub, "torque.amplitude", "x");
  EXPECT_NE(e.find("key 'torque.amplitude': expected a number in [0, 1e+100], got a string (\"x\")"), std::string::npos)
      << e;
  e = change_live(hub, "torque.amplitude", "-1");
  EXPECT_NE(e.find("key 'torque.amplitude': expected a number in [0, 1e+100], got -1"), std::string::npos) << e;
  e = change_live(hub, "torque.period", "3");
  EXPECT_NE(e.find("'torque.period' cannot change while the model runs (live keys: torque.amplitude)"), std::string::npos)
      << e;
  e = change_live(hub, "gravity.g", "[0, 0, 1]");  // another model's live key
  EXPECT_NE(e.find("(live keys: torque.amplitude)"), std::string::npos) << e;
  EXPECT_EQ(change_live(hub, "torque.amplitude", "2"), "");

  LoadedScene shells = load_scene(bundled("double_pendulum_shells"), {"part[0].n1=4", "part[0].n2=4", "part[1].n1=4",
                                                                      "part[1].n2=4"});
  e = change_live(shells, "gravity.g", "[1, 2]");
  EXPECT_NE(e.find("key 'gravity.g': expected a list of numbers (length 3), each [-1e+100, 1e+100], got 2 elements"),
            std::string::npos)
      << e;
  e = change_live(shells, "gravity.g", "9.81");
  EXPECT_NE(e.find("key 'gravity.g': expected a list of numbers (length 3), each [-1e+100, 1e+100], got a "
                   "floating-point number (9.81)"),
            std::string::npos)
      << e;
  // a gravity beyond what the element's products hold is refused live as in a scene file
  e = change_live(shells, "gravity.g", "[0, 0, -1e300]");
  EXPECT_NE(e.find("expected a number in [-1e+100, 1e+100], got -1e+300"), std::string::npos) << e;
  e = change_live(shells, "solver.dt", "0.1");
  EXPECT_NE(e.find("'solver.dt' cannot change while the model runs (live keys: gravity.g)"), std::string::npos) << e;
  EXPECT_EQ(change_live(shells, "gravity.g", "[0, 0, -1]"), "");
  // the model itself guards its type, should a caller skip the schema
  EXPECT_NE(shells.simulation->change_live("gravity.g", LiveValue{1.0}), "");
  EXPECT_EQ(shells.simulation->change_live("gravity.g", LiveValue{std::vector<double>{0, 0, -1}}), "");
}

}  // namespace
}  // namespace ff::scene
