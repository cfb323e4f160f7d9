#pragma once
/// \file element_threads.h
/// The threaded element loop, and how many threads it uses. Loops run on oneTBB with one
/// contiguous chunk per thread, split the same way on every call. Its workers go to sleep soon
/// after a loop, where OpenMP's (libgomp's) spun at the barrier for milliseconds, which with
/// ~0.6 ms between two loops of a dynamics run kept a second core busy doing nothing: the core the
/// frame renderer, or another job of a study, needs (docs/performance.md). A run that renders
/// frames beside the solver also leaves one core to the renderer while a frame is being rendered
/// (share_cores_with): a loop thread preempted by the renderer would hold the others at the end of
/// the loop. Configured with -DFLEXFRAME_ELEMENT_THREADS=std the loops run on a std::thread pool
/// instead (element_thread_pool.h), same ranges, same results, for ThreadSanitizer.

#include <atomic>
#include <functional>

namespace ff::assembly {

/// Threads of the element loops started from the calling thread from now on (n >= 1).
void set_element_threads(int n);
/// The number the next element loop started from the calling thread would use: the value given to
/// set_element_threads on this thread, else OMP_NUM_THREADS when set (the variable every BLAS and
/// cluster script already sets), else the cores this process may run on.
int element_threads();

/// Shares the cores with another part of the program that says when it is busy (the frame
/// renderer): while *busy is true, element loops started from the calling thread use one thread
/// fewer than element_threads(), so no loop thread waits for a core the renderer holds; while it
/// is false they use all. Null stops the sharing. The flag must outlive the loops.
void share_cores_with(const std::atomic<bool>* busy);
/// Threads for an element loop started now from the calling thread.
int element_threads_now();

/// Calls chunk(begin, end) on element_threads_now() threads for contiguous ranges that together
/// cover [0, count) once, and returns when all are done; an exception thrown by chunk reaches the
/// caller. Each range is a fixed share of count, so which thread does which item never changes
/// the results: loops write per-item buffers and sum them afterwards in item order.
void for_each_chunk(int count, const std::function<void(int begin, int end)>& chunk);

/// The threads for_each_chunk runs on in this build: "tbb" (oneTBB, the default) or "std" (the
/// std::thread pool of element_thread_pool.h; CMake option FLEXFRAME_ELEMENT_THREADS).
const char* element_loop_backend();

}  // namespace ff::assembly
