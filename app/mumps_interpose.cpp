// MUMPS's per-call size statistics for its save/restore feature, skipped for the whole process.
// At the end of every call (analysis, factorization, solve) the MUMPS 5.5 driver computes how
// large a saved copy of the instance would be (DMUMPS_COMPUTE_MEMORY_SAVE, reported in
// KEEP8(55-58), RINFO(7:8), RINFOG(17:18)) by walking every field of its structure with a string
// comparison per field. FlexFrame never saves an instance (JOB = 7) nor reads those entries, and
// with one right-hand side per Newton correction that walk was 5-7 % of the main job
// (docs/performance.md, "MUMPS's per-call statistics"). Linked into the flexframe executable and
// exported (interpose.list), so libdmumps binds its calls (made through the PLT) to this one.
// FLEXFRAME_MUMPS_STATISTICS=on computes them as before (for before/after measurements).
#include <dlfcn.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <string_view>

#if __has_include(<dmumps_c.h>)
#include <dmumps_c.h>
#endif

namespace {
// The routine's arguments (the instance, two INTEGER(8) outputs) as of MUMPS 5.5; any other
// version is left to its own routine
#ifdef MUMPS_VERSION
constexpr bool known_signature = std::string_view(MUMPS_VERSION).substr(0, 4) == "5.5.";
#else
constexpr bool known_signature = false;
#endif

std::atomic<long long> skipped{0};

bool statistics_wanted() {
  static const bool wanted = [] {
    const char* e = std::getenv("FLEXFRAME_MUMPS_STATISTICS");
    return !known_signature || (e && std::strcmp(e, "on") == 0);
  }();
  return wanted;
}
using MemorySave = void (*)(void*, long long*, long long*);
}  // namespace

extern "C" void __dmumps_save_restore_MOD_dmumps_compute_memory_save(void* instance, long long* file_size,
                                                                      long long* struc_size) {
  if (statistics_wanted()) {
    static const auto next = reinterpret_cast<MemorySave>(
        dlsym(RTLD_NEXT, "__dmumps_save_restore_MOD_dmumps_compute_memory_save"));
    if (next) {
      next(instance, file_size, struc_size);
      return;
    }
  }
  *file_size = 0;  // "no saved copy"
  *struc_size = 0;
  skipped.fetch_add(1, std::memory_order_relaxed);
}

// MUMPS calls whose statistics were skipped so far, or -1 when they are computed (exported: `bench
// --solve` and the test find it with dlsym)
extern "C" long long flexframe_mumps_statistics_skipped() {
  return statistics_wanted() ? -1 : skipped.load(std::memory_order_relaxed);
}
