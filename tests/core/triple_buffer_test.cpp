// Tests for core/triple_buffer.h: latest value wins, a read is stable until the next one, and a reader never sees a torn or older value.
#include "core/triple_buffer.h"


#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "test_stamp.h"

namespace dentsim {
namespace {

using test::Stamp;
using test::stampOf;
using test::whole;

TEST(TripleBuffer, BeforeAnyPublishTheReaderSeesTheInitialValue) {
  TripleBuffer<int> zero;
  EXPECT_FALSE(zero.fresh());
  EXPECT_EQ(zero.read(), 0);  // slots are value-initialised

  TripleBuffer<std::string> named(std::string("start"));
  EXPECT_FALSE(named.fresh());
  EXPECT_EQ(named.read(), "start");
  EXPECT_EQ(named.read(), "start");
}

TEST(TripleBuffer, FreshFromPublishUntilRead) {
  TripleBuffer<int> tb;
  tb.publish(1);
  EXPECT_TRUE(tb.fresh());
  EXPECT_EQ(tb.read(), 1);
  EXPECT_FALSE(tb.fresh());
  // A read with nothing new keeps the flag clear and returns what it returned before.
  EXPECT_EQ(tb.read(), 1);
  EXPECT_FALSE(tb.fresh());
}

// Only the newest publish reaches the reader; the ones it replaced are gone, never read later.
TEST(TripleBuffer, LatestPublishWins) {
  TripleBuffer<int> tb;
  tb.publish(1);
  tb.publish(2);
  tb.publish(3);
  EXPECT_EQ(tb.read(), 3);
  EXPECT_EQ(tb.read(), 3);  // not 1 or 2 coming back out of a spare slot
  tb.publish(4);
  tb.publish(5);
  EXPECT_EQ(tb.read(), 5);
  EXPECT_EQ(tb.read(), 5);
}

// The contract says the reference stays valid and unchanged until the next read(), however many
// times the producer publishes meanwhile: the producer must never be handed the reader's slot.
TEST(TripleBuffer, AReadIsStableUntilTheNextRead) {
  TripleBuffer<Stamp> tb;
  tb.publish(stampOf(1));
  const Stamp& held = tb.read();
  const Stamp* address = &held;
  for (uint64_t n = 2; n <= 50; ++n) {
    Stamp& slot = tb.back();
    ASSERT_NE(&slot, address) << "producer handed the reader's slot at publish " << n;
    slot = stampOf(n);
    tb.publish();
    ASSERT_EQ(held.n, 1u);
  }
  // With nothing new, a second read returns the very same object, not a copy.
  const Stamp& newest = tb.read();
  EXPECT_EQ(newest.n, 50u);
  EXPECT_EQ(&tb.read(), &newest);
}

// Filling back() in place and publishing is the same as publish(value).
TEST(TripleBuffer, InPlaceFillPublishesTheFilledSlot) {
  TripleBuffer<std::string> tb;
  tb.back() = "drill";
  tb.back() += " on";
  tb.publish();
  EXPECT_EQ(tb.read(), "drill on");
}

// Read after every publish, and after every second one, for many cycles: each slot rotation the
// three indices go through must keep delivering exactly the newest value.
TEST(TripleBuffer, ManyRotationsStayLatestWins) {
  TripleBuffer<uint64_t> tb;
  uint64_t n = 0;
  for (int cycle = 0; cycle < 10'000; ++cycle) {
    const int publishes = 1 + cycle % 4;
    for (int i = 0; i < publishes; ++i) tb.publish(++n);
    ASSERT_TRUE(tb.fresh());
    ASSERT_EQ(tb.read(), n) << "cycle " << cycle;
    ASSERT_FALSE(tb.fresh());
  }
}

// One producer publishing as fast as it can, one reader: every value read is whole, values never
// go backward, a read after fresh() is strictly newer, a held value does not change under the
// reader, and the last publish is always delivered.
TEST(TripleBuffer, ConcurrentReadsAreWholeAndNeverOlder) {
  constexpr uint64_t kCount = 3'000'000;
  TripleBuffer<Stamp> tb(stampOf(0));  // whole from the start, so the first read passes the check
  std::atomic<bool> done{false};
  std::thread producer([&] {
    for (uint64_t n = 1; n <= kCount; ++n) {
      // Field by field into the slot, so a shared slot would show up as a torn read.
      Stamp& slot = tb.back();
      slot.n = n;
      slot.hash = n * 2654435761u;
      slot.inv = ~n;
      tb.publish();
      if (n % 4096 == 0) std::this_thread::yield();  // let the reader run on a single free core
    }
    done.store(true, std::memory_order_release);
  });

  // The reader records the first breach instead of asserting, so the producer is always joined.
  std::string failure;
  uint64_t last = 0;
  for (;;) {
    // Read `done` first: once the producer has finished, this read must bring its last value.
    const bool producer_done = done.load(std::memory_order_acquire);
    const bool was_fresh = tb.fresh();
    const Stamp& seen = tb.read();
    const Stamp copy = seen;
    if (!whole(copy)) {
      failure = "torn value after " + std::to_string(last);
      break;
    }
    if (copy.n < last || (was_fresh && copy.n == last)) {
      failure = "saw " + std::to_string(copy.n) + " after " + std::to_string(last);
      break;
    }
    last = copy.n;
    if (last == kCount) break;
    if (producer_done) {
      failure = "the last publish never arrived; reader stuck at " + std::to_string(last);
      break;
    }
    std::this_thread::yield();
    // The producer ran meanwhile; what we hold must not have moved.
    if (seen.n != copy.n || seen.hash != copy.hash || seen.inv != copy.inv) {
      failure = "held value " + std::to_string(copy.n) + " changed before the next read";
      break;
    }
  }
  producer.join();
  EXPECT_EQ(failure, "");
  EXPECT_EQ(last, kCount);
}

}  // namespace
}  // namespace dentsim
