#pragma once
/// \file element_threads.h
/// How many threads the element loops (OpenMP, in the shell models) use. A run that renders
/// frames beside the solver leaves one core to the renderer while a frame is being rendered
/// (share_cores_with): a loop thread preempted by the renderer would hold every other thread at
/// the loop's barrier (docs/performance.md).

#include <atomic>

namespace ff::assembly {

/// Threads of the element loops started from the calling thread from now on (n >= 1). Returns
/// false, doing nothing, in a build without OpenMP.
bool set_element_threads(int n);
/// The number the next element loop started from the calling thread would use (1 without OpenMP).
int element_threads();

/// Shares the cores with another part of the program that says when it is busy (the frame
/// renderer): while *busy is true, element loops started from the calling thread use one thread
/// fewer than element_threads(), so no loop thread waits at a barrier for a core the renderer
/// holds; while it is false they use all. Null stops the sharing. The flag must outlive the loops.
void share_cores_with(const std::atomic<bool>* busy);
/// Threads for an element loop started now from the calling thread (the `num_threads` of the loop).
int element_threads_now();

}  // namespace ff::assembly
