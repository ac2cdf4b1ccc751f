// steadyNowNs: the one monotonic clock every stage stamps with (the haptic loop, the recorder, the device threads).
//
// Forces are stamped on the haptic thread and judged stale on a device's own thread, so both must
// read the same clock; a wall clock would jump with NTP and fire the watchdog.
#pragma once

#include <chrono>
#include <cstdint>

namespace dentsim {

// Nanoseconds since an arbitrary fixed point (boot, on Linux) [ns]; never goes backward.
inline int64_t steadyNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace dentsim
