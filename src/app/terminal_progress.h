// TerminalProgress: an Interrupter that draws a progress bar on a terminal and stays quiet otherwise.
#pragma once

#include <chrono>
#include <string>

#include "core/interrupter.h"

namespace dentsim::app {

class TerminalProgress final : public Interrupter {
 public:
  TerminalProgress();  // draws only when stderr is a terminal
  void start(std::string_view task) override;
  bool progress(double fraction) override;
  void end() override;

 private:
  bool tty_ = false;
  std::string task_;
  int last_percent_ = -1;
  std::chrono::steady_clock::time_point started_;
};

}  // namespace dentsim::app
