// PenSource and PenReading: what the haptic loop reads a pen through, below both sim and devices/.
//
// The loop (sim) and every pen driver (devices/) meet at this interface, so it sits in core: a
// device then knows maths and time, and nothing of the simulation. The loop calls read() once a
// step with its own clock and display() with the force it wants rendered; neither may block.
#pragma once

#include <cstdint>

#include "core/rigid.h"

namespace dentsim {

// What a pen reports each step.
struct PenReading {
  Pose grip;               // the grip frame: position of the grip point [mm], the tool's rotation
  Vec3 velocity;           // of the grip point [mm/s]
  Vec3 angular_velocity;   // [rad/s]
  uint32_t buttons = 0;    // button bits
  double pedal = 0.0;      // foot pedal [0..1]
};

class PenSource {
 public:
  virtual ~PenSource() = default;
  // The pen's state at loop time t_s [s]. False when it has none (the tool then stays where it is).
  virtual bool read(double t_s, PenReading* out) = 0;
  // The wrench the pen should render from now on (force [N], moment about the grip [N mm]).
  virtual void display(const Wrench& wrench, double t_s) {
    (void)wrench;
    (void)t_s;
  }
};

}  // namespace dentsim
