// FootPedal: the turbine's speed from a foot pedal: a switch (0 or 1) or a proportional pedal with an axis.
//
// Threads: a control thread opens, services and closes it; value() is read by the haptic thread,
// never blocks, and is 0 whenever the pedal is not connected, so a pulled plug stops the turbine.
#pragma once

#include <atomic>
#include <mutex>
#include <string>

#include "core/result.h"
#include "devices/haptic_device.h"

namespace dentsim::devices {

class FootPedal {
 public:
  virtual ~FootPedal() = default;
  FootPedal() = default;
  FootPedal(const FootPedal&) = delete;
  FootPedal& operator=(const FootPedal&) = delete;

  virtual std::string name() const = 0;      // "hid:0", "hid:0c45:7403", "virtual"
  virtual Status open() = 0;                  // Ready on success
  virtual void close() = 0;                   // Disconnected, value 0; idempotent
  virtual void service() {}                   // control thread at frame rate: reconnect after a replug
  // Haptic thread, non-blocking: the latest pedal position [0, 1]; 0 unless Ready.
  virtual double value() const = 0;

  DeviceState state() const { return state_.load(std::memory_order_acquire); }
  std::string reason() const {
    std::lock_guard lock(reason_mutex_);
    return reason_;
  }

 protected:
  void setState(DeviceState s, std::string reason = {}) {
    {
      std::lock_guard lock(reason_mutex_);
      reason_ = std::move(reason);
    }
    state_.store(s, std::memory_order_release);
  }

 private:
  std::atomic<DeviceState> state_{DeviceState::Disconnected};
  mutable std::mutex reason_mutex_;
  std::string reason_;
};

}  // namespace dentsim::devices
