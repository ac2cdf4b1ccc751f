// Progress and cancellation for long jobs (import, voxelize, full re-mesh), shown on a terminal or in the UI.
#pragma once

#include <string_view>

namespace dentsim {

// Long jobs call start(), then progress() with a fraction in [0, 1], then end().
// progress() returning false asks the job to stop early and return an error.
class Interrupter {
 public:
  virtual ~Interrupter() = default;
  virtual void start(std::string_view task) { (void)task; }
  virtual bool progress(double fraction) { (void)fraction; return true; }
  virtual void end() {}
};

// The interrupter for callers that want neither progress nor cancellation.
inline Interrupter& nullInterrupter() {
  static Interrupter none;  // stateless, so sharing one instance is safe
  return none;
}

}  // namespace dentsim
