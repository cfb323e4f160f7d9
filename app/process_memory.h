#pragma once
/// \file process_memory.h
/// Resident memory of this process (Linux /proc), for the memory column of `flexframe study`.

namespace ff::app {

/// Resident set size now [MB]; NaN where /proc is unavailable.
double resident_mb();
/// Peak resident set size since start or the last successful reset_peak_resident() [MB].
double peak_resident_mb();
/// Resets the peak to the current size (writes 5 to /proc/self/clear_refs); false when the
/// kernel or container refuses, in which case the peak is the process's running maximum.
bool reset_peak_resident();

}  // namespace ff::app
