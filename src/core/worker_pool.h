// WorkerPool: persistent threads that share an index range with the calling thread, for parallel loops on the frame thread without a thread spawn per call.
//
// run() hands out pieces of [0, count) from one atomic counter; the caller works too, so a loop
// finishes even when every worker is descheduled (a loaded machine): a worker that wakes after the
// caller has taken the last piece does not join, and the caller waits only for workers still inside
// a piece. Each thread has a fixed worker index (the caller is 0), so callers can keep per-worker
// scratch. One run() at a time; run() must not be called from inside fn.
#pragma once

#include <algorithm>
#include <atomic>
#include <cassert>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace dentsim {

class WorkerPool {
 public:
  // A piece of the range: fn(begin, end, worker), worker in [0, size()).
  using Piece = std::function<void(size_t begin, size_t end, unsigned worker)>;

  // `threads` that run a loop, the caller included (so threads - 1 are started); 0 means one per
  // hardware thread.
  explicit WorkerPool(unsigned threads = 0) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    for (unsigned i = 1; i < threads; ++i) workers_.emplace_back([this, i] { workerLoop(i); });
  }
  ~WorkerPool() {
    {
      std::lock_guard lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
  }
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  unsigned size() const { return unsigned(workers_.size()) + 1u; }

  // Calls fn over [0, count) in pieces of at most `grain` (>= 1) indices and returns when every
  // piece is done. Pieces run in any order on any worker.
  void run(size_t count, size_t grain, const Piece& fn) {
    assert(grain >= 1);
    if (count == 0) return;
    if (workers_.empty() || count <= grain) {
      fn(0, count, 0);
      return;
    }
    {
      std::lock_guard lock(mutex_);
      piece_ = &fn;
      count_ = count;
      grain_ = grain;
      next_.store(0, std::memory_order_relaxed);
      open_ = true;
      ++generation_;
    }
    wake_.notify_all();
    work(0);
    std::unique_lock lock(mutex_);
    open_ = false;  // late wakers stay out
    done_.wait(lock, [this] { return joined_ == 0; });
    piece_ = nullptr;
  }

 private:
  void work(unsigned worker) {
    for (;;) {
      const size_t begin = next_.fetch_add(grain_, std::memory_order_relaxed);
      if (begin >= count_) return;
      (*piece_)(begin, std::min(count_, begin + grain_), worker);
    }
  }

  void workerLoop(unsigned worker) {
    uint64_t seen = 0;
    std::unique_lock lock(mutex_);
    for (;;) {
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      if (!open_) continue;
      ++joined_;
      lock.unlock();
      work(worker);
      lock.lock();
      if (--joined_ == 0) done_.notify_all();
    }
  }

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;  // a new loop, or stop
  std::condition_variable done_;  // the last joined worker left its loop
  // The loop at hand, set under mutex_ before generation_ changes; read by joined workers only.
  const Piece* piece_ = nullptr;
  size_t count_ = 0;
  size_t grain_ = 1;
  std::atomic<size_t> next_{0};  // first index of the next piece
  uint64_t generation_ = 0;      // counts loops, so a worker runs each at most once
  bool open_ = false;            // workers may still join the current loop
  unsigned joined_ = 0;          // workers inside the current loop
  bool stop_ = false;
};

}  // namespace dentsim
