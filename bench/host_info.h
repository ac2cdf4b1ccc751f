// What the benchmarks record about the machine they ran on: CPU model, load average, Vulkan device.
#pragma once

#include <string>

#include "gpu/context.h"

namespace dentsim::bench {

// The first "model name" of /proc/cpuinfo, or "unknown CPU".
std::string cpuModel();

// The three load averages of /proc/loadavg ("0.52 0.60 0.71"), or "unknown".
std::string loadAverage();

// The device's name, with its driver in brackets where the driver says which it is.
std::string deviceLabel(const gpu::DeviceInfo& device);

}  // namespace dentsim::bench
