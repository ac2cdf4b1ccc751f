// Tests of BuddyAllocator: slot sizes, coalescing back to one range, growth, and bounded waste under churn.
#include "core/buddy_allocator.h"

#include <algorithm>
#include <map>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace dentsim {
namespace {

TEST(BuddyAllocator, RoundsToPowerOfTwoSlotsAndSplitsLowestFirst) {
  BuddyAllocator a(256, 4096);
  EXPECT_EQ(a.slotBytes(1), 256u);
  EXPECT_EQ(a.slotBytes(257), 512u);
  EXPECT_EQ(a.slotBytes(1024), 1024u);
  // 4096 splits into 2048 + 1024 + 512 + 256 + 256: the first 256 B request gets offset 0.
  EXPECT_EQ(a.allocate(100), 0u);
  EXPECT_EQ(a.allocate(300), 512u);   // the 512 B buddy of the split chain
  EXPECT_EQ(a.allocate(200), 256u);   // the remaining 256 B slot
  EXPECT_EQ(a.allocate(2000), 2048u);
  EXPECT_EQ(a.allocate(1024), 1024u);
  EXPECT_FALSE(a.allocate(1).has_value());  // 256 + 256 + 512 + 1024 + 2048 = 4096: full
  EXPECT_EQ(a.allocatedBytes(), 4096u);
  EXPECT_EQ(a.largestFree(), 0u);
}

TEST(BuddyAllocator, FreeingEverythingLeavesOneRange) {
  BuddyAllocator a(256, 1 << 16);
  std::mt19937 rng(7);
  std::vector<uint64_t> live;
  for (int i = 0; i < 100; ++i) {
    auto o = a.allocate(1 + rng() % 3000);
    if (o) live.push_back(*o);
  }
  std::shuffle(live.begin(), live.end(), rng);
  for (uint64_t o : live) a.release(o);
  EXPECT_EQ(a.allocatedBytes(), 0u);
  EXPECT_EQ(a.largestFree(), uint64_t{1} << 16);
}

TEST(BuddyAllocator, GrowKeepsLiveSlotsAndAddsTheUpperHalf) {
  BuddyAllocator a(256, 1024);
  const auto x = a.allocate(1024);
  ASSERT_EQ(x, 0u);
  EXPECT_FALSE(a.allocate(256).has_value());
  a.grow();
  EXPECT_EQ(a.capacity(), 2048u);
  EXPECT_EQ(a.slotBytesAt(0), 1024u);
  EXPECT_EQ(a.allocate(1024), 1024u);
  // Growing an empty allocator gives one free range of the new size.
  BuddyAllocator b(256, 1024);
  b.grow();
  EXPECT_EQ(b.largestFree(), 2048u);
}

TEST(BuddyAllocator, SlotsNeverOverlapAndChurnStaysBounded) {
  // Blocks re-meshed over and over with sizes that drift: the pool must not keep growing when the
  // live total does not. Grow only when an allocation fails, as GpuSurface does.
  BuddyAllocator a(256, 4096);
  std::mt19937 rng(11);
  std::map<uint64_t, uint64_t> live;  // offset -> requested bytes
  std::vector<uint64_t> offsets;
  uint64_t peak_rounded = 0;
  for (int step = 0; step < 20000; ++step) {
    const bool add = live.size() < 200 && (live.empty() || rng() % 2 == 0);
    if (add) {
      const uint64_t bytes = 16 + rng() % 20000;
      std::optional<uint64_t> o;
      while (!(o = a.allocate(bytes))) a.grow();
      live[*o] = bytes;
    } else {
      auto it = live.begin();
      std::advance(it, rng() % live.size());
      a.release(it->first);
      live.erase(it);
    }
    peak_rounded = std::max(peak_rounded, a.allocatedBytes());
    // No two live slots overlap.
    uint64_t end = 0;
    for (const auto& [o, bytes] : live) {
      ASSERT_GE(o, end);
      end = o + a.slotBytesAt(o);
      ASSERT_LE(end, a.capacity());
      ASSERT_GE(a.slotBytesAt(o), bytes);
    }
  }
  // Rounding at most doubles a slot; a buddy pool that only grows on failure stays within a small
  // multiple of the peak rounded live bytes (measured here: the bound is what the pool promises).
  EXPECT_LE(a.capacity(), 8 * std::bit_ceil(peak_rounded));
}

}  // namespace
}  // namespace dentsim
