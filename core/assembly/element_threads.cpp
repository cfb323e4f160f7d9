#include "core/assembly/element_threads.h"

#if FF_ELEMENT_THREADS_TBB
#include <oneapi/tbb/info.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/partitioner.h>
#include <oneapi/tbb/task_arena.h>

#include <array>
#include <memory>
#include <mutex>
#else
#include <sched.h>

#include "core/assembly/element_thread_pool.h"

#include <thread>
#endif

#include <algorithm>
#include <cstdlib>

namespace ff::assembly {

namespace {
int default_threads() {
  static const int n = [] {
    if (const char* v = std::getenv("OMP_NUM_THREADS")) {
      const int t = std::atoi(v);
      if (t >= 1) return t;
    }
#if FF_ELEMENT_THREADS_TBB
    return std::max(1, tbb::info::default_concurrency());  // honours the process's CPU mask
#else
    cpu_set_t mask;  // the cores this process may run on, as TBB counts them
    if (sched_getaffinity(0, sizeof mask, &mask) == 0) return std::max(1, CPU_COUNT(&mask));
    return std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
#endif
  }();
  return n;
}

#if FF_ELEMENT_THREADS_TBB

// one arena per thread count, made on first use and kept: an arena's workers stay with it
tbb::task_arena& arena(int threads) {
  constexpr int kMax = 256;
  static std::array<std::unique_ptr<tbb::task_arena>, kMax + 1> arenas;
  static std::mutex made;
  const int t = std::clamp(threads, 1, kMax);
  std::lock_guard<std::mutex> lock(made);
  if (!arenas[t]) arenas[t] = std::make_unique<tbb::task_arena>(t);
  return *arenas[t];
}
#endif
}  // namespace

int default_element_threads() { return default_threads(); }

int ElementThreads::now() const {
  const int n = count > 0 ? count : default_threads();
  return busy && busy->load(std::memory_order_relaxed) ? std::max(1, n - 1) : n;
}

void for_each_chunk(const ElementThreads& threads, int count, const std::function<void(int begin, int end)>& chunk) {
  if (count <= 0) return;
  const int t = std::min(threads.now(), count);
  if (t == 1) return chunk(0, count);
  auto range = [count, t](int c) { return static_cast<int>(static_cast<long long>(count) * c / t); };
#if FF_ELEMENT_THREADS_TBB
  arena(t).execute([&] {
    tbb::parallel_for(0, t, [&](int c) { chunk(range(c), range(c + 1)); }, tbb::static_partitioner());
  });
#else
  run_chunks_on_std_threads(t, [&](int c) { chunk(range(c), range(c + 1)); });
#endif
}

const char* element_loop_backend() { return FF_ELEMENT_THREADS_TBB ? "tbb" : "std"; }

}  // namespace ff::assembly
