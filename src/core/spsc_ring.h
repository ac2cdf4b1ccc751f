// SpscRing: a fixed-capacity queue from one producer thread to one consumer thread, without locks or allocation.
//
// The haptic thread pushes one record a step and must never wait: when the ring is full push()
// says so and the producer decides what a lost record means. The consumer pops in order.
#pragma once

#include <atomic>
#include <cassert>
#include <cstdint>
#include <vector>

namespace dentsim {

template <class T>
class SpscRing {
 public:
  // Room for 2^capacity_log2 records, allocated here once.
  explicit SpscRing(int capacity_log2) : slots_(size_t{1} << capacity_log2), mask_((uint64_t{1} << capacity_log2) - 1) {}

  // ---- producer ----
  // The slot the next push() publishes, to fill in place; null when the ring is full.
  T* reserve() {
    const uint64_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) > mask_) return nullptr;
    return &slots_[head & mask_];
  }
  // Publishes the slot reserve() gave.
  void push() { head_.store(head_.load(std::memory_order_relaxed) + 1, std::memory_order_release); }

  // ---- consumer ----
  // The oldest record, or null when empty; valid until pop().
  const T* front() const {
    const uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return nullptr;
    return &slots_[tail & mask_];
  }
  void pop() {
    assert(front() != nullptr);
    tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
  }

  size_t capacity() const { return slots_.size(); }

 private:
  std::vector<T> slots_;
  uint64_t mask_;
  alignas(64) std::atomic<uint64_t> head_{0};  // producer's count
  alignas(64) std::atomic<uint64_t> tail_{0};  // consumer's count
};

}  // namespace dentsim
