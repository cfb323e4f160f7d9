#pragma once
/// \file element_threads.h
/// The threaded element loop, and how many threads it uses (passed to every loop as an
/// ElementThreads value, which the model keeps). Loops run on oneTBB with one contiguous chunk per thread, split the same way on every call. Its workers go to sleep soon
/// after a loop, where OpenMP's (libgomp's) spun at the barrier for milliseconds, which with
/// ~0.6 ms between two loops of a dynamics run kept a second core busy doing nothing: the core the
/// frame renderer, or another job of a study, needs (docs/performance.md). A run that renders
/// frames beside the solver also leaves one core to the renderer while a frame is being rendered
/// (ElementThreads::busy): a loop thread preempted by the renderer would hold the others at the end of
/// the loop. Configured with -DFLEXFRAME_ELEMENT_THREADS=std the loops run on a std::thread pool
/// instead (element_thread_pool.h), same ranges, same results, for ThreadSanitizer.

#include <atomic>
#include <functional>

namespace ff::assembly {

/// How many threads an element loop uses, handed to every loop by the model that runs it (no
/// per-thread or process-wide setting): a model keeps the value its Simulation was given.
struct ElementThreads {
  /// threads; 0 = OMP_NUM_THREADS when set (the variable every BLAS and cluster script already
  /// sets), else the cores this process may run on
  int count = 0;
  /// shares the cores with another part of the program that says when it is busy (the frame
  /// renderer): while *busy is true a loop uses one thread fewer, so no loop thread waits for a
  /// core the renderer holds; null: no sharing. The flag must outlive the loops.
  const std::atomic<bool>* busy = nullptr;
  /// the threads a loop started now uses
  int now() const;
};

/// OMP_NUM_THREADS when set, else the cores this process may run on.
int default_element_threads();

/// Calls chunk(begin, end) on threads.now() threads for contiguous ranges that together cover
/// [0, count) once, and returns when all are done; an exception thrown by chunk reaches the
/// caller. Each range is a fixed share of count, so which thread does which item never changes
/// the results: loops write per-item buffers and sum them afterwards in item order.
void for_each_chunk(const ElementThreads& threads, int count, const std::function<void(int begin, int end)>& chunk);

/// The threads for_each_chunk runs on in this build: "tbb" (oneTBB, the default) or "std" (the
/// std::thread pool of element_thread_pool.h; CMake option FLEXFRAME_ELEMENT_THREADS).
const char* element_loop_backend();

}  // namespace ff::assembly
