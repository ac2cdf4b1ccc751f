// cpuModel, loadAverage and deviceLabel: read from /proc and the Vulkan context.
#include "bench/host_info.h"

#include <fstream>

namespace dentsim::bench {

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  return "unknown CPU";
}

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  if (!(in >> one >> five >> fifteen)) return "unknown";
  return one + " " + five + " " + fifteen;
}

std::string deviceLabel(const gpu::DeviceInfo& device) {
  return device.name + (device.driver_info.empty() ? "" : " (" + device.driver_info + ")");
}

}  // namespace dentsim::bench
