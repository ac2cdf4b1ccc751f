// DeadlineClock: slots open at the last deadline, a step that ends late misses, a stall restarts the schedule, and a sleep never ends before its deadline.
#include "sim/deadline_clock.h"

#include <gtest/gtest.h>

#include <cstdint>

#include "core/steady_clock.h"

namespace dentsim {
namespace {

constexpr int64_t kMs = 1'000'000;

TEST(DeadlineClock, EachSlotOpensAtTheLastDeadlineAndSaysHowLateTheStepBegan) {
  DeadlineClock clock(10 * kMs);
  // First slot [10, 11) ms: the step began 30 us in.
  EXPECT_EQ(clock.open(kMs, 10 * kMs + 30'000), 30'000);
  EXPECT_EQ(clock.deadline(), 11 * kMs);
  EXPECT_TRUE(clock.close(10 * kMs + 100'000, kMs));
  // Second slot [11, 12) ms, the step woken 700 us late and done 200 us later: it ended past 12 ms.
  EXPECT_EQ(clock.open(kMs, 11 * kMs + 700'000), 700'000);
  EXPECT_FALSE(clock.close(12 * kMs + 5'000, kMs));
  EXPECT_EQ(clock.deadline(), 12 * kMs) << "a small miss keeps the schedule: the next slot opens at 12 ms";
  // A step that ends exactly on its deadline met it.
  EXPECT_EQ(clock.open(kMs, 12 * kMs + 5'000), 5'000);
  EXPECT_TRUE(clock.close(13 * kMs, kMs));
}

TEST(DeadlineClock, AStallOfMoreThanFourPeriodsStartsANewScheduleInsteadOfABurst) {
  DeadlineClock clock(0);
  clock.open(kMs, 0);
  // Four periods past the deadline: still the old schedule, the next slots catch up.
  EXPECT_FALSE(clock.close(5 * kMs, kMs));
  EXPECT_EQ(clock.deadline(), kMs);
  clock.open(kMs, 5 * kMs);  // [1, 2) ms, begun at 5 ms
  // Ended 4.5 periods past its 2 ms deadline: the schedule restarts where the step ended.
  EXPECT_FALSE(clock.close(6 * kMs + 500'000, kMs));
  EXPECT_EQ(clock.deadline(), 6 * kMs + 500'000);
  EXPECT_EQ(clock.open(kMs, 6 * kMs + 510'000), 10'000);
  EXPECT_EQ(clock.deadline(), 7 * kMs + 500'000);
}

TEST(DeadlineClock, ASleepEndsNoSoonerThanItsDeadlineAndAPassedOneReturnsAtOnce) {
  // Lower bounds only: a loaded machine may wake the thread later, never earlier.
  const int64_t deadline = steadyNowNs() + 2 * kMs;
  sleepUntilNs(deadline);
  EXPECT_GE(steadyNowNs(), deadline);
  // A deadline already passed does not block (a hang would time the test out).
  const int64_t now = steadyNowNs();
  sleepUntilNs(now - kMs);
  DeadlineClock passed(now - 3 * kMs);
  passed.open(kMs, now);
  EXPECT_LT(passed.deadline(), now);
  passed.sleep();
}

}  // namespace
}  // namespace dentsim
