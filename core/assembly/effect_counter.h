#pragma once
/// \file effect_counter.h
/// What one effect of a model cost (summary.json "effect_stats"): evaluations and seconds.
#include <chrono>

namespace ff::assembly {

struct EffectCounter {
  long long evaluations = 0;
  double seconds = 0.0;
  void add(long long n, double s) { evaluations += n, seconds += s; }
};

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace ff::assembly
