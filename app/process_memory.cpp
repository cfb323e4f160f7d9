#include "app/process_memory.h"

#include <cmath>
#include <fstream>
#include <string>

namespace ff::app {

namespace {
/// A "Vm...:   123 kB" line of /proc/self/status in MB.
double status_field_mb(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(in, line))
    if (line.compare(0, key.size(), key) == 0) return std::stod(line.substr(key.size())) / 1024.0;
  return NAN;
}
}  // namespace

double resident_mb() { return status_field_mb("VmRSS"); }
double peak_resident_mb() { return status_field_mb("VmHWM"); }

bool reset_peak_resident() {
  std::ofstream out("/proc/self/clear_refs");
  if (!out) return false;
  out << "5";
  out.flush();
  return static_cast<bool>(out);
}

}  // namespace ff::app
