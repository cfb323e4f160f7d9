#include "core/assembly/element_threads.h"

#include <algorithm>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace ff::assembly {

bool set_element_threads(int n) {
#ifdef _OPENMP
  omp_set_num_threads(std::max(1, n));  // the calling thread's nthreads-var: its later parallel regions
  return true;
#else
  (void)n;
  return false;
#endif
}

namespace {
thread_local const std::atomic<bool>* other_busy = nullptr;
}

void share_cores_with(const std::atomic<bool>* busy) { other_busy = busy; }

int element_threads_now() {
  const int n = element_threads();
  return other_busy && other_busy->load(std::memory_order_relaxed) ? std::max(1, n - 1) : n;
}

int element_threads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

}  // namespace ff::assembly
