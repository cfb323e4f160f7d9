#pragma once
/// \file machine_memory.h
/// How much memory a run may use on this machine, so that `check` and `run` refuse a scene whose
/// estimated peak cannot fit (SceneContext::memory_limit_bytes) instead of dying in bad_alloc.

#include <string>

namespace ff::io {

/// The smallest of: physical memory (/proc/meminfo MemTotal), the address-space limit
/// (RLIMIT_AS), the cgroup memory limit (v2 memory.max, v1 memory.limit_in_bytes), and
/// FLEXFRAME_MEMORY_LIMIT_GB when set (for batch jobs with a memory request, and for tests).
/// 0 when none is known. An unparsable FLEXFRAME_MEMORY_LIMIT_GB sets *error and returns 0.
double machine_memory_limit_bytes(std::string* error = nullptr);

/// The bound a mesh or CAD file's size is checked against (ff::open_input_file, core/frame/input_file.h),
/// for messages: a mesh takes more memory than its file, so a file larger than the memory limit
/// cannot be read.
inline constexpr const char* kMemoryLimitBound =
    "of memory this machine allows (FLEXFRAME_MEMORY_LIMIT_GB, or the machine's own); a mesh takes more memory "
    "than its file";

}  // namespace ff::io
