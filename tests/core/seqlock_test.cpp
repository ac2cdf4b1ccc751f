// Tests for core/seqlock.h: a reader sees nothing before the first store, then whole values only, never a torn mix.
#include "core/seqlock.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cstdint>
#include <thread>

namespace dentsim {
namespace {

// Five words, all equal in one store: a reader that mixed two stores would see unequal words.
struct Words {
  uint64_t w[5] = {};
};

TEST(SeqLock, EmptyUntilTheFirstStore) {
  SeqLock<Words> lock;
  Words out;
  out.w[0] = 7;
  EXPECT_FALSE(lock.stored());
  EXPECT_FALSE(lock.load(&out));
  EXPECT_EQ(out.w[0], 7u);  // a failed load leaves the output alone
}

TEST(SeqLock, LoadsTheLatestStore) {
  SeqLock<Words> lock;
  lock.store(Words{{1, 2, 3, 4, 5}});
  lock.store(Words{{6, 7, 8, 9, 10}});
  Words out;
  ASSERT_TRUE(lock.load(&out));
  EXPECT_TRUE(lock.stored());
  for (int i = 0; i < 5; ++i) EXPECT_EQ(out.w[i], uint64_t(6 + i));
}

// A value whose size is no multiple of 8 comes back byte for byte.
TEST(SeqLock, OddSizedValues) {
  struct Odd {
    double d = 0.0;
    uint8_t b = 0;
  };
  SeqLock<Odd> lock;
  lock.store(Odd{2.5, 9});
  Odd out;
  ASSERT_TRUE(lock.load(&out));
  EXPECT_EQ(out.d, 2.5);
  EXPECT_EQ(out.b, 9);
}

// One writer storing as fast as it can, one reader: every successful load is one whole store, and
// the loaded values never go backward.
TEST(SeqLock, ConcurrentReadsAreNeverTorn) {
  SeqLock<Words> lock;
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (uint64_t n = 1; n <= 200'000; ++n) lock.store(Words{{n, n, n, n, n}});
    done.store(true, std::memory_order_release);
  });
  uint64_t last = 0;
  while (!done.load(std::memory_order_acquire)) {
    Words out;
    if (!lock.load(&out)) continue;
    for (int i = 1; i < 5; ++i) ASSERT_EQ(out.w[i], out.w[0]);
    ASSERT_GE(out.w[0], last);
    last = out.w[0];
  }
  writer.join();
  Words out;
  ASSERT_TRUE(lock.load(&out));
  EXPECT_EQ(out.w[0], 200'000u);
}

}  // namespace
}  // namespace dentsim
