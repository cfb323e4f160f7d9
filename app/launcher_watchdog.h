#pragma once
/// \file launcher_watchdog.h
/// Over MPI ranks (core/solve/distributed.md) Open MPI's launcher answers a rank's death with
/// SIGTERM to every other rank and SIGKILL a second later. The solver thread may then wait inside
/// a MUMPS call for the dead rank and never return: unless the run has closed results.h5 within
/// kLauncherGraceS of the SIGTERM, the watchdog closes it, with an outcome that says so, writes
/// summary.json and ends the process (rank 0 alone watches; the other ranks write nothing).

#include <atomic>
#include <chrono>
#include <string>
#include <thread>

#include "app/output_folder.h"
#include "app/run_shared.h"

namespace ff::app {

/// Over MPI ranks, how long after SIGTERM the run may take to close results.h5 itself before the
/// launcher watchdog closes it (Open MPI sends SIGKILL 1 s after SIGTERM: odls_base_sigkill_timeout)
inline constexpr double kLauncherGraceS = 0.3;

/// The outcome's reason when the MPI launcher's SIGTERM stopped a run shared over ranks.
std::string launcher_stop_reason(long long steps, double t, const std::string& unit);

/// What the watchdog needs of the run it watches.
struct WatchedRun {
  const std::atomic<int>* stop_signal = nullptr;  ///< the signal that set the stop flag
  StoredResults* results = nullptr;
  SolverEnd* solver = nullptr;
  OutputFolder* folder = nullptr;
  std::string scene_name, scene_path, time_unit, out_dir;
  std::chrono::steady_clock::time_point run_start;
};

/// Watches from construction (when `on`) until destruction, which also ends the watch when the
/// run throws.
class LauncherWatchdog {
 public:
  LauncherWatchdog(WatchedRun run, bool on);
  ~LauncherWatchdog();
  LauncherWatchdog(const LauncherWatchdog&) = delete;
  LauncherWatchdog& operator=(const LauncherWatchdog&) = delete;

 private:
  void watch();
  WatchedRun run_;
  std::atomic<bool> over_{false};
  std::thread thread_;
};

}  // namespace ff::app
