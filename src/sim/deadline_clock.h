// DeadlineClock: the slots and deadlines of a periodic real-time thread: the haptic loop's, and the bare timer the haptic bench measures the machine with.
//
// A step's slot opens at the last deadline and closes one period later. A step that ends after its
// deadline missed it; one that began late because the kernel (or a virtual machine's host) woke the
// thread late misses it through no time of its own, so opening a slot says how late the step began
// (the loop counts the steps that themselves took longer than a period). The bench runs the same
// clock with a busy wait in place of the step, at the same priority, so the two threads' misses compare.
#pragma once

#include <cstdint>

namespace dentsim {

// The haptic loop's real-time priority (SCHED_FIFO): above the renderer and audio, below the kernel's own threads.
constexpr int kHapticPriority = 80;

// Asks for what a haptic thread needs of the kernel, for the calling thread: a 1 ns timer slack and
// SCHED_FIFO at `priority`. Returns false when the priority was refused (no privilege): the thread
// then runs at its normal policy, as it would on a student's PC without the capability.
bool enterRealTime(int priority = kHapticPriority);

// Sleeps until the steady clock (core/steady_clock.h) reads deadline_ns; at once if it has passed.
void sleepUntilNs(int64_t deadline_ns);

class DeadlineClock {
 public:
  explicit DeadlineClock(int64_t start_ns) : deadline_(start_ns) {}

  // Opens the next slot, period_ns long, for a step beginning at now_ns. Returns how late the step
  // began after its slot opened [ns] (the wake-up's lateness).
  int64_t open(int64_t period_ns, int64_t now_ns) {
    const int64_t slot = deadline_;
    deadline_ += period_ns;
    return now_ns - slot;
  }
  int64_t deadline() const { return deadline_; }
  // The step ended at end_ns. True when it met its deadline; a miss far behind (more than four
  // periods: a stall) starts a new schedule at end_ns rather than a burst of catch-up steps.
  bool close(int64_t end_ns, int64_t period_ns) {
    if (end_ns <= deadline_) return true;
    if (end_ns - deadline_ > 4 * period_ns) deadline_ = end_ns;
    return false;
  }
  // Until the deadline: the next slot opens there.
  void sleep() const { sleepUntilNs(deadline_); }

 private:
  int64_t deadline_;
};

}  // namespace dentsim
