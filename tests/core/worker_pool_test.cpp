// WorkerPool: every index once per loop, workers named in range, loops back to back, a pool of one.
#include "core/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <vector>

namespace dentsim {
namespace {

// Runs `loops` loops of `count` indices and checks that each loop visited every index exactly once
// and only with worker indices below size().
void expectEachIndexOnce(WorkerPool& pool, size_t count, size_t grain, int loops) {
  std::vector<std::atomic<int>> visits(count);
  std::atomic<bool> bad_worker{false};
  for (int loop = 0; loop < loops; ++loop) {
    for (auto& v : visits) v.store(0);
    pool.run(count, grain, [&](size_t begin, size_t end, unsigned worker) {
      if (worker >= pool.size() || begin >= end || end > count) bad_worker = true;
      for (size_t i = begin; i < end; ++i) visits[i].fetch_add(1);
    });
    // run() returned, so every piece is done: no visit may still be on its way.
    for (size_t i = 0; i < count; ++i) ASSERT_EQ(visits[i].load(), 1) << "index " << i << " in loop " << loop;
  }
  EXPECT_FALSE(bad_worker.load());
}

TEST(WorkerPool, VisitsEveryIndexOnceInEachOfManyLoops) {
  for (unsigned threads : {1u, 2u, 4u}) {
    SCOPED_TRACE(std::to_string(threads) + " threads");
    WorkerPool pool(threads);
    EXPECT_EQ(pool.size(), threads);
    expectEachIndexOnce(pool, 1000, 7, 200);
    expectEachIndexOnce(pool, 3, 1, 200);   // fewer pieces than threads
    expectEachIndexOnce(pool, 64, 64, 10);  // one piece: the caller alone
  }
}

TEST(WorkerPool, EmptyLoopsAndDefaultSizeWork) {
  WorkerPool pool;
  EXPECT_GE(pool.size(), 1u);
  bool called = false;
  pool.run(0, 4, [&](size_t, size_t, unsigned) { called = true; });
  EXPECT_FALSE(called);
  expectEachIndexOnce(pool, 100, 1, 50);
}

// Per-worker scratch is safe: no two pieces run at once on the same worker index.
TEST(WorkerPool, AWorkerIndexRunsOnePieceAtATime) {
  WorkerPool pool(3);
  std::vector<std::atomic<int>> inside(pool.size());
  std::atomic<bool> overlap{false};
  for (int loop = 0; loop < 100; ++loop)
    pool.run(300, 2, [&](size_t, size_t, unsigned worker) {
      if (inside[worker].fetch_add(1) != 0) overlap = true;
      inside[worker].fetch_sub(1);
    });
  EXPECT_FALSE(overlap.load());
}

}  // namespace
}  // namespace dentsim
