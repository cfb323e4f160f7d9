#pragma once
/// \file element_threads.h
/// How many threads the element loops (OpenMP, in the shell models) use. A run that renders
/// frames beside the solver gives one core to the renderer: on two cores the element loop's
/// waiting threads otherwise spin on the core the renderer needs (docs/performance.md).

namespace ff::assembly {

/// Threads of the element loops started from the calling thread from now on (n >= 1). Returns
/// false, doing nothing, in a build without OpenMP.
bool set_element_threads(int n);
/// The number the next element loop started from the calling thread would use (1 without OpenMP).
int element_threads();

}  // namespace ff::assembly
