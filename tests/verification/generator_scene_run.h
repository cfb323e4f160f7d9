#pragma once
// Runs a scene given as TOML text (written to the build tree), with optional key overrides as on
// the command line, and returns the probes' final values by name: the verification tests of the
// mesh generators build their problems from the [mesh] keys exactly as a user's scene would, and
// the dynamics tests run the guide's example this way (`ctx` brings a mesh file reader, for the io
// tests: the scene's files are relative to FF_BINARY_DIR/test_out).
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "core/model/simulation.h"
#include "core/scene/scene.h"

namespace ff::verification {

inline std::map<std::string, double> run_scene_text(const std::string& name, const std::string& text,
                                                    const std::vector<std::string>& overrides = {},
                                                    const ff::scene::SceneContext& ctx = {}) {
  const std::string dir = std::string(FF_BINARY_DIR) + "/test_out";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/" + name + ".toml";
  std::ofstream(path) << text;
  ff::scene::LoadedScene s = ff::scene::load_scene(path, overrides, ctx);
  std::atomic<bool> stop{false};
  std::vector<double> last;
  const ff::RunOutcome out = s.simulation->run([&](ff::Frame&& f) { last = f.probes; }, stop);
  EXPECT_EQ(out.status, ff::RunStatus::completed) << out.reason;
  std::map<std::string, double> probes;
  const ff::RunInfo& info = s.simulation->info();
  for (std::size_t k = 0; k < info.probes.size() && k < last.size(); ++k) probes[info.probes[k].name] = last[k];
  return probes;
}

// The scene text around a [mesh] table and the supports, loads and probes of one problem.
inline std::string linear_scene(const std::string& name, const std::string& effects, const std::string& mesh,
                                const std::string& material, const std::string& rest) {
  return "[scene]\nname = \"" + name + "\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = " + effects + "\n[[part]]\n" + mesh +
         "\n[[material]]\n" + material + "\n" + rest +
         "\n[solver]\nmethod = \"load_control\"\ninitial_step = 1.0\nmax_step = 1.0\n"
         "[output]\nframes = false\nplots = false\n";
}

}  // namespace ff::verification
