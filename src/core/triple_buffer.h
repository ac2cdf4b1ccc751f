// TripleBuffer: hands the latest value from one thread to another without locks, neither side ever waiting.
//
// The producer fills its private slot and swaps it with the shared middle slot; the consumer
// swaps the middle slot with its own when a fresh one is there. Each side owns one slot at a time,
// so a reader keeps a stable reference to what it read until its next read() — even for a T whose
// copy would allocate, nothing is copied on the consumer's side.
#pragma once

#include <atomic>
#include <cstdint>

namespace dentsim {

template <class T>
class TripleBuffer {
 public:
  TripleBuffer() = default;
  explicit TripleBuffer(const T& initial) : slots_{initial, initial, initial} {}

  // ---- producer ----
  T& back() { return slots_[back_]; }  // fill this, then publish()
  void publish() {
    const uint8_t old = middle_.exchange(uint8_t(back_ | kFresh), std::memory_order_acq_rel);
    back_ = old & kIndex;
  }
  void publish(const T& value) {
    back() = value;
    publish();
  }

  // ---- consumer ----
  // The newest published value (or the last one read when nothing new came); stable until the next read().
  const T& read() {
    if (middle_.load(std::memory_order_relaxed) & kFresh) {
      const uint8_t old = middle_.exchange(front_, std::memory_order_acq_rel);
      front_ = old & kIndex;
    }
    return slots_[front_];
  }
  // True when a value newer than the last read() is waiting.
  bool fresh() const { return (middle_.load(std::memory_order_acquire) & kFresh) != 0; }

 private:
  static constexpr uint8_t kFresh = 4, kIndex = 3;
  T slots_[3]{};
  uint8_t back_ = 0;                      // producer's slot
  std::atomic<uint8_t> middle_{1};        // shared slot index, plus kFresh
  uint8_t front_ = 2;                     // consumer's slot
};

}  // namespace dentsim
