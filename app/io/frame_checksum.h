#pragma once
/// \file frame_checksum.h
/// Per-frame checksum stored in /frames/checksum: 64-bit FNV-1a over the frame's row of every
/// other /frames data set, in the order of kChecksumOrder, as little-endian bytes of the
/// stored types. The reader uses it to find frames damaged when a writer was killed during a
/// flush (results_layout.md, "Interrupted runs").

#include <cstddef>
#include <cstdint>

namespace ff::io {

inline constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;
inline constexpr std::uint64_t kFnvPrime = 1099511628211ull;

inline std::uint64_t fnv1a(std::uint64_t hash, const void* data, std::size_t bytes) {
  auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i) {
    hash ^= p[i];
    hash *= kFnvPrime;
  }
  return hash;
}

}  // namespace ff::io
