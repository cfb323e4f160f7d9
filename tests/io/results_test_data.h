#pragma once
/// \file results_test_data.h
/// Deterministic RunInfo and frames for the result-store tests, and bitwise comparison.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "core/frame/frame.h"

namespace ff::io::test {

/// A fresh path under FF_BINARY_DIR/test_out/ (the file is removed if it exists).
inline std::string out_path(const std::string& name) {
  std::filesystem::path dir = std::filesystem::path(FF_BINARY_DIR) / "test_out";
  std::filesystem::create_directories(dir);
  std::filesystem::path p = dir / name;
  std::filesystem::remove(p);
  return p.string();
}

/// n points on a strip (n even), with lines, triangles and quads over them.
inline RunInfo make_info(std::size_t n = 60, std::size_t probes = 3, std::size_t fields = 2) {
  RunInfo info;
  info.scene_name = "strip_test";
  info.scene_path = "assets/scenes/strip_test.toml";
  info.scene_text =
      "# strip test scene\n[scene]\nname = \"strip_test\"\n\n[solver]\ndt = 1e-3  # \xce\x94t\n";
  info.effects = {"elastic", "inertia", "gravity", "drilling"};
  info.settings = {{"integrator", "lie_generalized_alpha"}, {"rho_inf", "0.9"},
                   {"dt", "0.001"}, {"jacobian.policy", "every_iteration"},
                   {"note", "\xce\xb1-method, UTF-8"}};
  info.time_unit = "s";
  const std::size_t half = n / 2;
  for (std::size_t i = 0; i < n; ++i) {
    double x = 0.1 * static_cast<double>(i % std::max<std::size_t>(half, 1));
    double y = i < half ? 0.0 : 0.05;
    info.mesh.reference_points.insert(info.mesh.reference_points.end(), {x, y, 1.0 / 3.0});
  }
  for (std::size_t i = 0; i + 1 < half; ++i) {
    auto a = static_cast<std::int32_t>(i), b = a + 1, c = static_cast<std::int32_t>(half + i),
         d = c + 1;
    info.mesh.lines.insert(info.mesh.lines.end(), {a, b});
    info.mesh.quads.insert(info.mesh.quads.end(), {a, b, d, c});
    info.mesh.triangles.insert(info.mesh.triangles.end(), {a, b, d});
  }
  const char* units[] = {"deg", "m", "N"};
  for (std::size_t k = 0; k < probes; ++k) {
    info.probes.push_back({"probe_" + std::to_string(k), units[k % 3], "probe number " + std::to_string(k)});
  }
  for (std::size_t k = 0; k < fields; ++k) {
    info.fields.push_back({"field_" + std::to_string(k), "Pa", "field number " + std::to_string(k)});
  }
  return info;
}

/// Frame i of a run described by `info`; values are irrational-looking doubles, with a NaN,
/// an infinity, a negative zero and a subnormal here and there to test bitwise storage.
inline Frame make_frame(const RunInfo& info, std::int64_t i) {
  Frame f;
  const double t = 1e-3 * static_cast<double>(i);
  f.step = i;
  f.time = t;
  f.load_factor = std::sqrt(static_cast<double>(i)) / 7.0;
  const std::size_t n = info.mesh.point_count();
  for (std::size_t p = 0; p < 3 * n; ++p) {
    double r = info.mesh.reference_points[p];
    f.base_points.push_back(r + std::sin(t + 0.1 * static_cast<double>(p)));
    f.points.push_back(f.base_points.back() + 1e-3 * std::cos(3.0 * t * static_cast<double>(p)));
  }
  for (std::size_t k = 0; k < info.probes.size(); ++k) {
    f.probes.push_back(std::exp(-t) * static_cast<double>(k + 1) + 1.0 / 7.0);
  }
  if (!f.probes.empty() && i % 97 == 5) f.probes[0] = std::numeric_limits<double>::quiet_NaN();
  if (f.probes.size() > 1 && i % 89 == 3) f.probes[1] = -std::numeric_limits<double>::infinity();
  if (f.probes.size() > 2 && i % 83 == 7) f.probes[2] = -0.0;
  for (std::size_t k = 0; k < info.fields.size(); ++k) {
    std::vector<double> v;
    for (std::size_t p = 0; p < n; ++p) v.push_back(std::tanh(t * static_cast<double>(p + k)) / 3.0);
    if (n > 0 && i % 71 == 1) v[0] = std::numeric_limits<double>::denorm_min();
    f.fields.push_back(std::move(v));
  }
  f.stats.dt = 1e-3 / 3.0;
  f.stats.iterations = static_cast<std::int32_t>(2 + i % 5);
  f.stats.jacobian_updates = static_cast<std::int32_t>(i % 3);
  f.stats.residual_norm = std::pow(10.0, -8.0 - static_cast<double>(i % 4)) / 3.0;
  f.stats.increment_norm = std::pow(10.0, -9.0 - static_cast<double>(i % 5)) / 7.0;
  f.stats.converged = i % 11 != 10;
  return f;
}

inline bool bitwise_equal(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

inline ::testing::AssertionResult bitwise_equal(const std::vector<double>& a,
                                                const std::vector<double>& b) {
  if (a.size() != b.size()) {
    return ::testing::AssertionFailure() << "sizes differ: " << a.size() << " vs " << b.size();
  }
  if (!a.empty() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) != 0) {
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (!bitwise_equal(a[i], b[i])) {
        return ::testing::AssertionFailure() << "element " << i << " differs: " << a[i] << " vs " << b[i];
      }
    }
  }
  return ::testing::AssertionSuccess();
}

/// Every member of frame `got` is bitwise equal to `want`.
inline ::testing::AssertionResult same_frame(const Frame& want, const Frame& got) {
  auto fail = [&](const char* what) {
    return ::testing::AssertionFailure() << "frame of step " << want.step << ": " << what;
  };
  if (got.step != want.step) return fail("step");
  if (!bitwise_equal(got.time, want.time)) return fail("time");
  if (!bitwise_equal(got.load_factor, want.load_factor)) return fail("load_factor");
  if (!bitwise_equal(got.points, want.points)) return fail("points");
  if (!bitwise_equal(got.base_points, want.base_points)) return fail("base_points");
  if (!bitwise_equal(got.probes, want.probes)) return fail("probes");
  if (got.fields.size() != want.fields.size()) return fail("field count");
  for (std::size_t k = 0; k < want.fields.size(); ++k) {
    if (!bitwise_equal(got.fields[k], want.fields[k])) return fail("fields");
  }
  const StepStats &a = want.stats, &b = got.stats;
  if (!bitwise_equal(a.dt, b.dt) || a.iterations != b.iterations ||
      a.jacobian_updates != b.jacobian_updates || !bitwise_equal(a.residual_norm, b.residual_norm) ||
      !bitwise_equal(a.increment_norm, b.increment_norm) || a.converged != b.converged) {
    return fail("stats");
  }
  return ::testing::AssertionSuccess();
}

}  // namespace ff::io::test
