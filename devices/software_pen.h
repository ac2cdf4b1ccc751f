// SoftwarePen: a pen with no hardware (the virtual pen, a pen script, a recorded session) behind the HapticDevice interface.
//
// It opens straight to Ready, reads from its PenSource at the loop's own time, and runs the same
// safety layer as a real pen, on loop time: what it would have sent to motors goes to the source's
// display() and to lastOutput(), so a software pen behaves, and is tested, like hardware.
#pragma once

#include <memory>
#include <string>

#include "core/pen_source.h"
#include "devices/haptic_device.h"

namespace dentsim::devices {

class SoftwarePen final : public HapticDevice {
 public:
  // `keep_alive` holds whatever the source reads from (a pen path, a session's steps).
  SoftwarePen(std::string name, std::unique_ptr<PenSource> source, DeviceSpec spec,
              std::shared_ptr<const void> keep_alive = {}, const SafetyParams& safety = {});
  ~SoftwarePen() override { SoftwarePen::close(); }

  std::string name() const override { return name_; }
  const DeviceSpec& spec() const override { return spec_; }
  Status open() override;
  void close() override;
  bool read(double t_s, DeviceReading* out) override;

  PenSource& source() { return *source_; }
  // The wrench the safety layer let out at the latest read (what motors would have got).
  const SafetyLayer::Output& lastOutput() const { return last_output_; }

 private:
  std::string name_;
  std::unique_ptr<PenSource> source_;
  DeviceSpec spec_;
  std::shared_ptr<const void> keep_alive_;
  SafetyLayer::Output last_output_;
};

// The spec of a software pen: the force limit of the parameter set, an unbounded workspace.
DeviceSpec softwarePenSpec(const std::string& model, double max_force_n, double max_torque_n_mm);

}  // namespace dentsim::devices
