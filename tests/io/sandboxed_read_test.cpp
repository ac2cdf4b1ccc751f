// Tests of io/sandboxed_read: a child that succeeds, fails, outgrows its memory cap, crashes, spins or hangs.
#include "io/sandboxed_read.h"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

namespace dentsim {
namespace {

// Small caps, so that the failing children end in about a second.
SandboxLimits quickLimits() {
  SandboxLimits limits;
  limits.data_growth_bytes = uint64_t{64} << 20;
  limits.cpu_s = 1;
  limits.wall_s = 2;
  return limits;
}

// For a child that ends by itself: limits a loaded machine's slow fork cannot reach, so that only
// the child's own answer decides the test.
SandboxLimits roomyLimits() {
  SandboxLimits limits = quickLimits();
  limits.cpu_s = 60;
  limits.wall_s = 120;
  return limits;
}

void expectOneLine(const Status& s) {
  ASSERT_FALSE(s);
  EXPECT_EQ(s.message().find('\n'), std::string::npos) << s.message();
  EXPECT_FALSE(s.message().empty());
}

TEST(SandboxedRead, WorkThatSucceedsIsOk) {
  // Ok means the caller's own read of the same input will not crash; the child's results are not
  // kept, since what it allocated dies with it.
  const Status s = runSandboxed("start.dcm", roomyLimits(), [](SandboxNote& note) -> Status {
    note.file("slice-0002.dcm");
    return Ok{};
  });
  EXPECT_TRUE(s) << s.message();
}

TEST(SandboxedRead, TheChildsErrorIsTheAnswer) {
  const Status s = runSandboxed("scan", roomyLimits(), [](SandboxNote&) -> Status {
    return makeError("scan/slice-0001.dcm", "a colour image");
  });
  expectOneLine(s);
  EXPECT_EQ(s.message(), "scan/slice-0001.dcm: a colour image");
}

TEST(SandboxedRead, WhatTheChildChangesStaysInTheChild) {
  int counter = 0;
  const Status s = runSandboxed("x", roomyLimits(), [&counter](SandboxNote&) -> Status {
    counter = 7;
    return Ok{};
  });
  EXPECT_TRUE(s);
  EXPECT_EQ(counter, 0);
}

TEST(SandboxedRead, AnAllocationBeyondTheCapEndsTheChildNotTheCaller) {
  // 1 GiB against a 64 MiB cap: malloc refuses it (the child reports so) or the allocator aborts
  // (a sanitizer's does); either way the caller gets one line and keeps running.
  const Status s = runSandboxed("big.dcm", quickLimits(), [](SandboxNote& note) -> Status {
    note.file("big.dcm");
    const size_t bytes = size_t{1} << 30;
    void* p = std::malloc(bytes);
    if (!p) return makeError("big.dcm", "memory cap reached");
    std::memset(p, 1, bytes);
    std::free(p);
    return Ok{};
  });
  expectOneLine(s);
  EXPECT_EQ(s.message().rfind("big.dcm: ", 0), 0u) << s.message();
}

TEST(SandboxedRead, ACrashNamesTheFileLastNotedAndTheSignal) {
  SandboxWords words;
  words.crashed = "truncated or damaged test file: the test reader stops on it";
  const Status s = runSandboxed(
      "folder",
      roomyLimits(),
      [](SandboxNote& note) -> Status {
        note.file("folder/slice-0001.dcm");
        note.file("folder/slice-0002.dcm");
        std::abort();
      },
      words);
  expectOneLine(s);
  EXPECT_EQ(s.message(), "folder/slice-0002.dcm: truncated or damaged test file: the test reader stops on it (signal " +
                             std::to_string(SIGABRT) + ")");
}

TEST(SandboxedRead, AChildThatSpinsIsStoppedByItsProcessorLimit) {
  SandboxWords words;
  words.reader = "GDCM";
  words.slow_cause = "deeply nested, or damaged";
  const Status s = runSandboxed(
      "spin.dcm", quickLimits(),
      [](SandboxNote&) -> Status {
        volatile uint64_t n = 0;
        for (;;) n = n + 1;
      },
      words);
  expectOneLine(s);
  // Under a loaded machine the wall limit may come first; both are a time limit named in one line.
  const bool cpu = s.message() == "spin.dcm: GDCM took more than 1 s of processor time on it (deeply nested, or damaged)";
  const bool wall = s.message() == "spin.dcm: GDCM did not finish reading it within 2 s (deeply nested, or damaged)";
  EXPECT_TRUE(cpu || wall) << s.message();
}

TEST(SandboxedRead, AChildThatSleepsIsKilledAfterTheWallLimit) {
  const auto t0 = std::chrono::steady_clock::now();
  const Status s = runSandboxed("hang.dcm", quickLimits(), [](SandboxNote&) -> Status {
    std::this_thread::sleep_for(std::chrono::seconds(60));
    return Ok{};
  });
  const double waited_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  expectOneLine(s);
  EXPECT_EQ(s.message(), "hang.dcm: the reader did not finish reading it within 2 s (damaged)");
  EXPECT_LT(waited_s, 10.0);  // no hang: the 60 s sleep is cut at the 2 s wall limit
}

TEST(SandboxedRead, AChildThatExitsWithoutReportingIsNamedByItsExitCode) {
  const Status s = runSandboxed("exit.dcm", roomyLimits(), [](SandboxNote&) -> Status { std::_Exit(3); });
  expectOneLine(s);
  EXPECT_EQ(s.message(), "exit.dcm: damaged file: the reader stops on it (exit code 3)");
}

TEST(SandboxedRead, ANoteWritesItsSlotCutToFitAndADefaultOneWritesNothing) {
  char slot[8];
  std::memset(slot, 'x', sizeof slot);
  SandboxNote note(slot, sizeof slot);
  note.file("a.dcm");
  EXPECT_STREQ(slot, "a.dcm");
  note.file("slice-0001.dcm");  // longer than the slot: cut, and still ended
  EXPECT_EQ(std::string(slot, strnlen(slot, sizeof slot)), "slice-0");
  EXPECT_EQ(slot[sizeof slot - 1], '\0');
  SandboxNote outside;  // the caller's own read: no slot, so nothing is written anywhere
  outside.file("anything");
  EXPECT_STREQ(slot, "slice-0");
}

}  // namespace
}  // namespace dentsim
