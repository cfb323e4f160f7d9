#include "app/io/machine_memory.h"

#include <sys/resource.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace ff::io {

namespace {

// the first number in a file (cgroup limits: "max" means none)
double number_in(const std::string& path) {
  std::ifstream f(path);
  std::string word;
  if (!(f >> word) || word == "max") return 0.0;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  return end != word.c_str() && std::isfinite(v) && v > 0 ? v : 0.0;
}

double mem_total() {
  std::ifstream f("/proc/meminfo");
  std::string key;
  double kb = 0.0;
  std::string unit;
  while (f >> key >> kb >> unit)
    if (key == "MemTotal:") return kb * 1024.0;
  return 0.0;
}

}  // namespace

double machine_memory_limit_bytes(std::string* error) {
  double limit = 0.0;
  auto take = [&](double v) {
    // cgroup v1 reports "no limit" as a number near 2^63
    if (v > 0 && v < 1e18 && (limit == 0 || v < limit)) limit = v;
  };
  take(mem_total());
  rlimit as{};
  if (getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != RLIM_INFINITY) take(static_cast<double>(as.rlim_cur));
  take(number_in("/sys/fs/cgroup/memory.max"));
  take(number_in("/sys/fs/cgroup/memory/memory.limit_in_bytes"));
  if (const char* env = std::getenv("FLEXFRAME_MEMORY_LIMIT_GB")) {
    char* end = nullptr;
    const double gb = std::strtod(env, &end);
    if (end == env || *end != '\0' || !(gb > 0) || !std::isfinite(gb)) {
      if (error) *error = "FLEXFRAME_MEMORY_LIMIT_GB='" + std::string(env) + "' is not a positive number of GB";
      return 0.0;
    }
    take(gb * 1e9);
  }
  return limit;
}

}  // namespace ff::io
