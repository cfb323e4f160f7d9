#include "app/launcher_watchdog.h"

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <mutex>

#include "app/run_summary.h"

namespace ff::app {

std::string launcher_stop_reason(long long steps, double t, const std::string& unit) {
  char at[96];
  std::snprintf(at, sizeof at, " at step %lld, t = %g %s", steps, t, unit.c_str());
  return std::string("stopped by SIGTERM from the MPI launcher") + at +
         ": another rank may have died, or the job was cancelled";
}

LauncherWatchdog::LauncherWatchdog(WatchedRun run, bool on) : run_(std::move(run)) {
  if (on) thread_ = std::thread([this] { watch(); });
}

LauncherWatchdog::~LauncherWatchdog() {
  over_ = true;
  if (thread_.joinable()) thread_.join();
}

void LauncherWatchdog::watch() {
  using namespace std::chrono_literals;
  StoredResults& results = *run_.results;
  while (!over_ && run_.stop_signal->load() != SIGTERM) std::this_thread::sleep_for(20ms);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(kLauncherGraceS);
  while (!over_ && !results.closed && std::chrono::steady_clock::now() < deadline) std::this_thread::sleep_for(5ms);
  std::unique_lock lock(results.mutex);  // not while the store thread appends a frame
  if (over_ || results.closed) return;  // the run closed its results in time and ends as usual
  RunOutcome o;
  o.status = RunStatus::interrupted;
  o.steps = results.last_step;  // the last frame stored: the store thread sets them after its append
  o.stop_time = results.last_time;
  o.reason = launcher_stop_reason(o.steps, o.stop_time, run_.time_unit) +
             "; the solver did not return from a call shared with the other ranks, so rank 0 closed results.h5 "
             "itself with the frames stored until then";
  {
    std::lock_guard done_lock(run_.solver->mutex);
    if (run_.solver->done) {  // the solve had ended: the SIGTERM came while the frames or other outputs were made
      o = run_.solver->outcome;
      const std::string after = "stopped by SIGTERM from the MPI launcher while the run wrote its outputs";
      if (o.status == RunStatus::completed) {
        o.status = RunStatus::interrupted;
        o.reason = after + ", after the solve had completed; results.h5 holds every frame: `flexframe replay` draws them";
      } else {
        o.reason += " (then " + after + ")";
      }
    }
  }
  o.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - run_.run_start).count();
  run_.folder->release_reserve();  // room for the outcome and summary.json
  std::string e;
  if (!results.writer->finish(o, {}, &e)) std::fprintf(stderr, "error: results.h5 is incomplete: %s\n", e.c_str());
  results.closed = true;  // the lock is kept until the process ends: nothing touches the writer again
  // summary.json without the metrics: the blocked solver thread holds them
  try {
    write_summary(*run_.folder, summary_without_metrics(run_.scene_name, run_.scene_path, o, run_.time_unit));
  } catch (const std::exception& x) {
    std::fprintf(stderr, "error: %s\n", x.what());
  }
  std::printf("%s: %s at t = %g after %lld steps\n  reason: %s\n  outputs: %s/{results.h5, summary.json}\n",
              run_.scene_name.c_str(), to_string(o.status), o.stop_time, static_cast<long long>(o.steps), o.reason.c_str(),
              run_.out_dir.c_str());
  std::fflush(stdout);
  std::fflush(stderr);
  std::_Exit(exit_code(o));  // without joining the blocked solver thread; the launcher ends the others
}

}  // namespace ff::app
