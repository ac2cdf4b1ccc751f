// IdleLatencyRequest: while the haptic loop runs, asks the kernel (PM QoS, /dev/cpu_dma_latency) to keep idle CPUs within a wake-up latency.
//
// Between steps the loop's thread sleeps about 0.9 ms. An idle CPU may then enter a deep sleep
// state: on bare metal a C-state that flushes the core's caches and takes tens of microseconds to
// leave, in a virtual machine a halt that hands the core to the host. Either way the next step
// starts cold and runs slower (docs/PERFORMANCE.md measures it: `dentsim bench haptic`'s "after
// idle" run). Writing a latency bound to /dev/cpu_dma_latency keeps every CPU in states that wake
// within it, for as long as the file stays open; closing it withdraws the request. Real-time Linux
// test tools do the same. It costs power while the loop runs, and needs write access to the file
// (root, or the udev rule in devices/70-dentsim.rules); without it the loop runs as before.
#pragma once

#include <cstdint>
#include <string>

namespace dentsim {

class IdleLatencyRequest {
 public:
  static constexpr const char* kDefaultPath = "/dev/cpu_dma_latency";

  IdleLatencyRequest() = default;
  // Asks for wake-ups within `microseconds` (>= 0) by writing it, as a 32-bit integer, to `path`.
  explicit IdleLatencyRequest(int32_t microseconds, const std::string& path = kDefaultPath);
  ~IdleLatencyRequest();  // withdraws the request
  IdleLatencyRequest(IdleLatencyRequest&& other) noexcept;
  IdleLatencyRequest& operator=(IdleLatencyRequest&& other) noexcept;
  IdleLatencyRequest(const IdleLatencyRequest&) = delete;
  IdleLatencyRequest& operator=(const IdleLatencyRequest&) = delete;

  bool held() const { return fd_ >= 0; }
  // The file exists but this user may not open it: what the udev rule fixes.
  bool denied() const { return denied_; }
  // One line for reports: what is held, or why not. A file that exists but may not be opened gets
  // the permission line that names the udev rule (core/permission_advice.h) and says the request is
  // optional; any other failure says "PATH: REASON" ("/dev/cpu_dma_latency: No such file or directory").
  const std::string& note() const { return note_; }

 private:
  void release();
  int fd_ = -1;
  bool denied_ = false;
  std::string note_ = "not requested";
};

}  // namespace dentsim
