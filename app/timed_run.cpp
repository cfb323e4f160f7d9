#include "app/timed_run.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <thread>

#include "app/io/mesh_import.h"
#include "core/scene/scene.h"

namespace ff::app {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? NAN : v[v.size() / 2];
}
}  // namespace

TimedRun timed_run(const std::string& scene_path, const std::vector<std::string>& overrides,
                   const std::atomic<bool>& stop) {
  TimedRun r;
  auto t0 = std::chrono::steady_clock::now();
  scene::LoadedScene s = scene::load_scene(scene_path, overrides, io::scene_context(&stop));
  s.simulation->prepare();  // the model's matrices count as set-up; a failure is the run's (start() says it again)
  r.setup_s = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  // the solver runs on a worker thread, as in `run`, so thread-local state and stack are the same
  std::exception_ptr failure;
  std::thread worker([&] {
    try {
      r.outcome = s.simulation->run([](Frame&&) {}, stop);
    } catch (...) {
      failure = std::current_exception();
    }
  });
  worker.join();
  if (failure) std::rethrow_exception(failure);
  r.run_s = seconds_since(t0);
  r.metrics = s.simulation->metrics();
  r.metrics_unreached = s.simulation->metrics_unreached();
  r.totals = s.simulation->totals();
  return r;
}

TimedRun timed_run_median(const std::string& scene_path, const std::vector<std::string>& overrides, int repeat,
                          const std::atomic<bool>& stop) {
  TimedRun first;
  std::vector<double> setup, run, total;
  for (int i = 0; i < std::max(1, repeat) && !stop; ++i) {
    TimedRun r = timed_run(scene_path, overrides, stop);
    if (i == 0) first = r;
    setup.push_back(r.setup_s);
    run.push_back(r.run_s);
    total.push_back(r.total_s());
  }
  // keep setup + run == median total by scaling the split of the median run
  const double t = median(total), s = median(setup), u = median(run);
  first.setup_s = t * s / std::max(s + u, 1e-300);
  first.run_s = t - first.setup_s;
  return first;
}

double metric(const Metrics& m, const std::string& name) { return find_metric(m, name).value_or(NAN); }

}  // namespace ff::app
