// Tests of src/gpu/buffer.cpp: host and staged copies, the storage-range refusal, deferred deletion.
#include <gtest/gtest.h>

#include <numeric>
#include <random>
#include <vector>

#include "gpu/buffer.h"
#include "gpu/compute.h"
#include "gpu_fixture.h"

namespace dentsim::gpu::test {

using BufferTest = GpuTest;

namespace {
std::vector<std::byte> randomBytes(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<std::byte> v(n);
  for (auto& b : v) b = static_cast<std::byte>(rng() & 0xffu);
  return v;
}
}  // namespace

TEST_F(BufferTest, HostVisibleRoundTrip) {
  auto b = Buffer::create(ctx(), 1000, MemoryKind::HostVisible, BufferUse::Storage, "host round trip");
  ASSERT_TRUE(b) << b.message();
  ASSERT_NE(b->mapped(), nullptr);
  const auto data = randomBytes(1000, 1);
  ASSERT_TRUE(b->upload(ctx(), data));
  std::vector<std::byte> back(1000);
  ASSERT_TRUE(b->download(ctx(), back));
  EXPECT_EQ(back, data);
}

TEST_F(BufferTest, DeviceLocalRoundTripThroughStaging) {
  auto b = Buffer::create(ctx(), 4096, MemoryKind::DeviceLocal, BufferUse::Storage, "device round trip");
  ASSERT_TRUE(b) << b.message();
  EXPECT_EQ(b->mapped(), nullptr) << "device-local buffers are never mapped, so staging is exercised";
  const auto data = randomBytes(4096, 2);
  ASSERT_TRUE(b->upload(ctx(), data));
  // A partial upload at an offset leaves the rest alone.
  const auto patch = randomBytes(100, 3);
  ASSERT_TRUE(b->upload(ctx(), patch, 1000));
  std::vector<std::byte> back(4096);
  ASSERT_TRUE(b->download(ctx(), back));
  auto expected = data;
  std::copy(patch.begin(), patch.end(), expected.begin() + 1000);
  EXPECT_EQ(back, expected);

  ASSERT_TRUE(b->clear(ctx()));
  ASSERT_TRUE(b->download(ctx(), back));
  EXPECT_EQ(std::count(back.begin(), back.end(), std::byte{0}), 4096);
}

TEST_F(BufferTest, RefusesAStorageBufferOverMaxStorageBufferRange) {
  const uint64_t range = ctx().limits().max_storage_buffer_range;
  auto b = Buffer::create(ctx(), range + 4, MemoryKind::DeviceLocal, BufferUse::Storage, "too big");
  ASSERT_FALSE(b);
  EXPECT_NE(b.message().find("maxStorageBufferRange"), std::string::npos) << b.message();
  EXPECT_NE(b.message().find("too big"), std::string::npos) << b.message();
  auto zero = Buffer::create(ctx(), 0, MemoryKind::HostVisible, BufferUse::Storage, "empty");
  ASSERT_FALSE(zero);
  EXPECT_NE(zero.message().find("size 0"), std::string::npos) << zero.message();
}

TEST_F(BufferTest, RefusesCopiesThatOverrun) {
  auto b = Buffer::create(ctx(), 64, MemoryKind::DeviceLocal, BufferUse::Storage, "small");
  ASSERT_TRUE(b) << b.message();
  std::vector<std::byte> big(65);
  EXPECT_FALSE(b->upload(ctx(), big));
  EXPECT_FALSE(b->download(ctx(), std::span<std::byte>(big).first(10), 60));
}

TEST(RetireListTest, FreesOnlyAfterTheSubmissionThatLastUsedIt) {
  RetireList list;
  std::vector<int> freed;
  list.retire(3, [&] { freed.push_back(3); });
  list.retire(5, [&] { freed.push_back(5); });
  list.retire(0, [&] { freed.push_back(0); });  // never submitted: free at once
  EXPECT_EQ(list.collect(2), 2u);
  EXPECT_EQ(freed, (std::vector<int>{0}));
  EXPECT_EQ(list.collect(4), 1u);
  EXPECT_EQ(freed, (std::vector<int>{0, 3}));
  list.flushAll();
  EXPECT_EQ(freed, (std::vector<int>{0, 3, 5}));
  EXPECT_EQ(list.size(), 0u);
}

TEST_F(BufferTest, DestroyedBuffersAreRetiredThenFreedOnceTheirWorkIsDone) {
  {
    auto b = Buffer::create(ctx(), 256, MemoryKind::DeviceLocal, BufferUse::Storage, "short-lived");
    ASSERT_TRUE(b) << b.message();
    ASSERT_TRUE(b->clear(ctx()));  // one submission uses it
    EXPECT_GT(b->lastUse(), 0u);
  }
  // Its submission finished, so nothing waits in the list.
  EXPECT_EQ(ctx().collectRetired(), 0u);
}

}  // namespace dentsim::gpu::test
