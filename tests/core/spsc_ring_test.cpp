// Tests for core/spsc_ring.h: power-of-two capacity, empty and full edges, FIFO order across many wraps, and every record exactly once between two threads.
#include "core/spsc_ring.h"


#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include "test_stamp.h"

namespace dentsim {
namespace {

using test::Stamp;
using test::fill;
using test::whole;

// Pushes n into the ring; false when it was full.
bool tryPush(SpscRing<uint64_t>& ring, uint64_t n) {
  uint64_t* slot = ring.reserve();
  if (!slot) return false;
  *slot = n;
  ring.push();
  return true;
}

TEST(SpscRing, CapacityIsTwoToTheGivenPower) {
  EXPECT_EQ(SpscRing<int>(0).capacity(), 1u);
  EXPECT_EQ(SpscRing<int>(1).capacity(), 2u);
  EXPECT_EQ(SpscRing<int>(3).capacity(), 8u);
  EXPECT_EQ(SpscRing<int>(12).capacity(), 4096u);
}

TEST(SpscRing, EmptyAtStart) {
  SpscRing<uint64_t> ring(2);
  EXPECT_EQ(ring.front(), nullptr);
  EXPECT_NE(ring.reserve(), nullptr);
}

// reserve() alone publishes nothing and, called again, hands the same slot.
TEST(SpscRing, ReserveWithoutPushPublishesNothing) {
  SpscRing<uint64_t> ring(2);
  uint64_t* first = ring.reserve();
  ASSERT_NE(first, nullptr);
  *first = 7;
  EXPECT_EQ(ring.front(), nullptr);
  EXPECT_EQ(ring.reserve(), first);
  ring.push();
  ASSERT_NE(ring.front(), nullptr);
  EXPECT_EQ(*ring.front(), 7u);
}

// Exactly capacity() records fit; the next reserve says full, and one pop makes room for one more.
TEST(SpscRing, FullAtCapacityAndRoomAgainAfterOnePop) {
  SpscRing<uint64_t> ring(3);
  for (uint64_t n = 0; n < 8; ++n) ASSERT_TRUE(tryPush(ring, n)) << "record " << n;
  EXPECT_EQ(ring.reserve(), nullptr);
  EXPECT_FALSE(tryPush(ring, 99));  // refused, and must not have overwritten anything
  ring.pop();
  EXPECT_TRUE(tryPush(ring, 8));
  EXPECT_EQ(ring.reserve(), nullptr);
  // Everything still there, oldest first: 1..8.
  for (uint64_t n = 1; n <= 8; ++n) {
    ASSERT_NE(ring.front(), nullptr);
    EXPECT_EQ(*ring.front(), n);
    ring.pop();
  }
  EXPECT_EQ(ring.front(), nullptr);
}

// A ring of one: full after one push, empty after one pop, over and over.
TEST(SpscRing, RingOfOneAlternatesFullAndEmpty) {
  SpscRing<uint64_t> ring(0);
  for (uint64_t n = 0; n < 100; ++n) {
    ASSERT_TRUE(tryPush(ring, n));
    ASSERT_EQ(ring.reserve(), nullptr);
    ASSERT_NE(ring.front(), nullptr);
    ASSERT_EQ(*ring.front(), n);
    ring.pop();
    ASSERT_EQ(ring.front(), nullptr);
  }
}

// front() names the same record until pop(), however often it is asked.
TEST(SpscRing, FrontIsStableUntilPop) {
  SpscRing<uint64_t> ring(2);
  ASSERT_TRUE(tryPush(ring, 1));
  ASSERT_TRUE(tryPush(ring, 2));
  const uint64_t* a = ring.front();
  EXPECT_EQ(ring.front(), a);
  ASSERT_TRUE(tryPush(ring, 3));  // a push behind it does not move the front
  EXPECT_EQ(ring.front(), a);
  EXPECT_EQ(*a, 1u);
  ring.pop();
  EXPECT_EQ(*ring.front(), 2u);
}

// A ring of four driven for 10 000 rounds with push and pop counts on different cycles, so its fill
// level wanders over 0..4, the counters pass the index range thousands of times and the wrap lands
// at every offset: order holds, nothing is lost, and reserve() says full exactly when it is.
TEST(SpscRing, FifoOrderAcrossManyWraps) {
  SpscRing<uint64_t> ring(2);
  const uint64_t capacity = ring.capacity();
  uint64_t pushed = 0, popped = 0, full_rounds = 0, empty_rounds = 0;
  for (uint64_t round = 0; round < 10'000; ++round) {
    const uint64_t to_push = std::min<uint64_t>(1 + round % 4, capacity - (pushed - popped));
    for (uint64_t i = 0; i < to_push; ++i) ASSERT_TRUE(tryPush(ring, pushed++)) << "round " << round;
    ASSERT_EQ(ring.reserve() == nullptr, pushed - popped == capacity) << "round " << round;
    full_rounds += pushed - popped == capacity;
    const uint64_t to_pop = std::min<uint64_t>(1 + (round * 3) % 5, pushed - popped);
    for (uint64_t i = 0; i < to_pop; ++i) {
      ASSERT_NE(ring.front(), nullptr) << "round " << round;
      ASSERT_EQ(*ring.front(), popped++) << "round " << round;
      ring.pop();
    }
    ASSERT_EQ(ring.front() == nullptr, pushed == popped) << "round " << round;
    empty_rounds += pushed == popped;
  }
  while (const uint64_t* v = ring.front()) {
    ASSERT_EQ(*v, popped++);
    ring.pop();
  }
  EXPECT_EQ(popped, pushed);
  EXPECT_GT(pushed / capacity, 5'000u);  // the indices wrapped thousands of times
  EXPECT_GT(full_rounds, 1'000u);        // and both edges were reached often
  EXPECT_GT(empty_rounds, 1'000u);
}

// Moves `count` numbered records from a producer thread to this one through a ring of 2^log2 and
// returns the first breach, or "" when every record arrived once, whole and in order.
std::string streamThroughRing(int log2, uint64_t count) {
  SpscRing<Stamp> ring(log2);
  std::atomic<bool> stop{false};  // set by the consumer on a breach so a blocked producer gives up
  std::thread producer([&] {
    for (uint64_t n = 1; n <= count; ++n) {
      Stamp* slot;
      while (!(slot = ring.reserve())) {
        if (stop.load(std::memory_order_relaxed)) return;
        std::this_thread::yield();  // full: let the consumer drain
      }
      fill(slot, n);
      ring.push();
    }
  });

  std::string failure;
  uint64_t expected = 1;
  while (expected <= count) {
    const Stamp* s = ring.front();
    if (!s) {
      std::this_thread::yield();  // empty: let the producer fill
      continue;
    }
    if (!whole(*s)) {
      failure = "torn record where " + std::to_string(expected) + " was due";
      break;
    }
    if (s->n != expected) {
      failure = "got " + std::to_string(s->n) + " where " + std::to_string(expected) + " was due";
      break;
    }
    ring.pop();
    ++expected;
  }
  stop.store(true, std::memory_order_relaxed);
  producer.join();
  // Every record was taken and the producer has finished: nothing may be left over.
  if (failure.empty() && ring.front() != nullptr) failure = "a record beyond the last one";
  return failure;
}

// Sizes are set by the number of waits, not the number of records: on a loaded two-core machine
// a side that finds the ring full or empty can wait a whole scheduler slice (~2 ms measured under
// stress-ng, more at a load of 7) for the other to run again. A ring of 64 with 4 million records
// took up to 50 s there; 4096 slots bound the waits to about a thousand, and the ring of one gets
// few enough hand-offs to stay within seconds.
TEST(SpscRing, TwoThreadsEveryRecordOnceInOrder) {
  EXPECT_EQ(streamThroughRing(12, 2'000'000), "");  // wraps ~490 times
}

TEST(SpscRing, TwoThreadsThroughARingOfOne) {
  EXPECT_EQ(streamThroughRing(0, 500), "");  // every record a hand-off at the full/empty edge
}

}  // namespace
}  // namespace dentsim
