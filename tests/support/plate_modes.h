#pragma once
// A test model whose modes are known in closed form (issue 36): a simply supported rectangular
// steel plate a x b, whose mode (m, n) is w = sin(mπx/a) sin(nπy/b) at
// f = (π/2)(m²/a² + n²/b²) sqrt(D/(ρh)) (Leissa, Vibration of Plates, NASA SP-160, 1969).
// PlateModesSimulation publishes the reference state in one step and then has "found"
// the lowest kModeCount modes: what the mode outputs (app/mode_outputs.h) and the window are
// tested with, through the path a real eigen-analysis takes (Simulation::modes() after the run).

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "core/model/simulation.h"

namespace ff::test {

constexpr double kA = 1.0, kB = 0.6, kH = 0.01;             // plate [m]
constexpr double kE = 210e9, kNu = 0.3, kRho = 7850.0;      // steel
constexpr int kNx = 20, kNy = 12;                           // quads along x and y
constexpr int kModeCount = 6;

inline double plate_frequency(int m, int n) {
  const double d = kE * kH * kH * kH / (12.0 * (1.0 - kNu * kNu));
  const double pi = std::numbers::pi;
  return 0.5 * pi * (m * m / (kA * kA) + n * n / (kB * kB)) * std::sqrt(d / (kRho * kH));
}

inline RunInfo plate_info() {
  RunInfo info;
  info.scene_name = "ss_plate_modes";
  info.scene_path = "(test model)";
  info.time_unit = "s";
  info.fields = {{"displacement", "m", "displacement magnitude"}};  // as a shell model stores it
  for (int j = 0; j <= kNy; ++j)
    for (int i = 0; i <= kNx; ++i)
      info.mesh.reference_points.insert(info.mesh.reference_points.end(), {kA * i / kNx, kB * j / kNy, 0.0});
  for (int j = 0; j < kNy; ++j)
    for (int i = 0; i < kNx; ++i) {
      const int p = j * (kNx + 1) + i;
      info.mesh.quads.insert(info.mesh.quads.end(), {p, p + 1, p + kNx + 2, p + kNx + 1});
    }
  return info;
}

// the lowest kModeCount modes (m, n), displacement along z scaled to a largest nodal value of 1
inline ModeSet plate_modes(const RunInfo& info, std::vector<std::pair<int, int>>* mn = nullptr) {
  std::vector<std::tuple<double, int, int>> all;
  for (int m = 1; m <= 6; ++m)
    for (int n = 1; n <= 6; ++n) all.emplace_back(plate_frequency(m, n), m, n);
  std::sort(all.begin(), all.end());
  ModeSet set{"modal", "frequency", "Hz", "natural frequency", "reference state", {}};
  const std::size_t count = info.mesh.point_count();
  for (int k = 0; k < kModeCount; ++k) {
    const auto [f, m, n] = all[static_cast<std::size_t>(k)];
    if (mn) mn->emplace_back(m, n);
    Mode mode;
    mode.number = k + 1;
    mode.value = f;
    mode.eigenvalue = std::pow(2.0 * std::numbers::pi * f, 2);
    mode.displacement.assign(3 * count, 0.0);
    double largest = 0;
    for (std::size_t i = 0; i < count; ++i) {
      const double x = info.mesh.reference_points[3 * i], y = info.mesh.reference_points[3 * i + 1];
      const double w = std::sin(m * std::numbers::pi * x / kA) * std::sin(n * std::numbers::pi * y / kB);
      mode.displacement[3 * i + 2] = w;
      largest = std::max(largest, std::fabs(w));
    }
    for (double& v : mode.displacement) v /= largest;
    set.modes.push_back(std::move(mode));
  }
  return set;
}

// Publishes the reference state, then has "found" the plate's modes (or none, with_modes = false).
class PlateModesSimulation : public Simulation {
 public:
  explicit PlateModesSimulation(bool with_modes) : info_(plate_info()), modes_(plate_modes(info_)), with_modes_(with_modes) {}
  const RunInfo& info() const override { return info_; }
  double end_time() const override { return 1.0; }
  std::string start() override { return ""; }
  double time() const override { return time_; }
  StepDone step(double) override {
    time_ = 1.0;
    StepDone d;
    d.accepted = true;
    d.finished = true;
    return d;
  }
  Frame frame() const override {
    Frame f;
    f.time = time_;
    f.points = info_.mesh.reference_points;
    f.base_points = f.points;
    f.fields = {std::vector<double>(info_.mesh.point_count(), 0.0)};
    return f;
  }
  Metrics metrics() const override { return {}; }
  const ModeSet* modes() const override { return with_modes_ && time_ >= 1.0 ? &modes_ : nullptr; }
  SolverTotals totals() const override { return {}; }

 private:
  RunInfo info_;
  ModeSet modes_;
  bool with_modes_;
  double time_ = 0.0;
};

}  // namespace ff::test
