// Progress bar on stderr for long jobs; silent when stderr is a pipe or a file, so logs stay clean.
#include "app/terminal_progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace dentsim::app {

TerminalProgress::TerminalProgress() : tty_(isatty(STDERR_FILENO) == 1) {}

void TerminalProgress::start(std::string_view task) {
  task_ = std::string(task);
  last_percent_ = -1;
  started_ = std::chrono::steady_clock::now();
  progress(0.0);
}

bool TerminalProgress::progress(double fraction) {
  if (!tty_) return true;
  const int percent = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * 100.0);
  if (percent == last_percent_) return true;
  last_percent_ = percent;
  constexpr int kWidth = 30;  // characters of the bar
  const int filled = percent * kWidth / 100;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
  std::fprintf(stderr, "\r%-24.24s [%.*s%*s] %3d%% %6.1fs", task_.c_str(), filled,
               "##############################", kWidth - filled, "", percent, seconds);
  std::fflush(stderr);
  return true;
}

void TerminalProgress::end() {
  if (!tty_) return;
  progress(1.0);
  std::fprintf(stderr, "\n");
}

}  // namespace dentsim::app
