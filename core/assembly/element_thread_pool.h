#pragma once
/// \file element_thread_pool.h
/// The element loop's std::thread back-end (element_threads.h): a pool of plain std::threads that
/// sleep on a condition variable between loops. Part of the product only when configured with
/// -DFLEXFRAME_ELEMENT_THREADS=std, where for_each_chunk uses it (ThreadSanitizer sees every
/// synchronization of it, which it cannot in the uninstrumented oneTBB: scripts/sanitize --tsan);
/// its unit test compiles it in every build. oneTBB stays the default: its workers are the faster
/// to start.

#include <functional>

namespace ff::assembly {

/// Calls body(c) once for every c in [0, chunks), on the calling thread and up to chunks - 1 pool
/// threads, and returns when all calls are done. The first exception thrown by a body reaches the
/// caller (after the other chunks have finished). Loops from several threads take turns; a loop
/// started from inside a body runs its chunks serially on that thread.
void run_chunks_on_std_threads(int chunks, const std::function<void(int chunk)>& body);

}  // namespace ff::assembly
