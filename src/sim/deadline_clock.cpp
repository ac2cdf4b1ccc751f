// DeadlineClock: the real-time set-up and the sleep of a periodic thread.
#include "sim/deadline_clock.h"

#include <pthread.h>
#include <sched.h>
#include <sys/prctl.h>
#include <time.h>

#include <cerrno>

#include "core/steady_clock.h"

namespace dentsim {

bool enterRealTime(int priority) {
  // Wake-ups as close to the deadline as the kernel allows; real-time priority where permitted.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  sched_param sp{};
  sp.sched_priority = priority;
  return pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp) == 0;
}

void sleepUntilNs(int64_t deadline_ns) {
  if (steadyNowNs() >= deadline_ns) return;
  timespec ts{};
  ts.tv_sec = time_t(deadline_ns / 1'000'000'000);
  ts.tv_nsec = long(deadline_ns % 1'000'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

}  // namespace dentsim
