// SeqLock: one writer publishes a small value, any number of readers copy the latest; nobody waits on a lock.
//
// The writer bumps a sequence number to odd, writes, and bumps it to even; a reader copies the
// words and keeps the copy only if the number was even and unchanged around it. The value is held
// as relaxed atomic words, so a torn read is discarded rather than undefined (and ThreadSanitizer
// stays quiet). Unlike TripleBuffer (one reader, which owns what it reads), a reader here copies,
// which suits a const reader or several readers of a value of a few dozen bytes.
#pragma once

#include <atomic>
#include <cassert>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace dentsim {

template <class T>
class SeqLock {
  static_assert(std::is_trivially_copyable_v<T>, "SeqLock copies T as raw words");

 public:
  // Writer, one thread at a time.
  void store(const T& value) {
    uint64_t w[kWords] = {};
    std::memcpy(w, &value, sizeof(T));
    const uint64_t s = seq_.load(std::memory_order_relaxed);
    seq_.store(s + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    for (size_t i = 0; i < kWords; ++i) words_[i].store(w[i], std::memory_order_relaxed);
    seq_.store(s + 2, std::memory_order_release);
  }

  // Readers, any thread: copies the latest value into *out. False when nothing was stored yet, or
  // when a writer was mid-store on every one of `tries` attempts. A real-time reader prefers "no
  // value" to spinning, but a writer can be preempted inside store() for a whole time slice on a
  // loaded machine, so a reader must tell the two apart (stored()) and not treat a busy value as
  // none at all.
  bool load(T* out, int tries = 64) const {
    assert(out != nullptr && tries > 0);
    for (int attempt = 0; attempt < tries; ++attempt) {
      const uint64_t s1 = seq_.load(std::memory_order_acquire);
      if (s1 == 0) return false;
      if (s1 & 1) continue;
      uint64_t w[kWords];
      for (size_t i = 0; i < kWords; ++i) w[i] = words_[i].load(std::memory_order_relaxed);
      std::atomic_thread_fence(std::memory_order_acquire);
      if (seq_.load(std::memory_order_relaxed) != s1) continue;
      std::memcpy(out, w, sizeof(T));
      return true;
    }
    return false;
  }

  // Tests only: leaves the sequence odd, as a writer preempted halfway through store() does, until
  // called again with false. Readers then fail every try, which a loaded machine really produces.
  void holdMidStoreForTest(bool held) {
    const uint64_t s = seq_.load(std::memory_order_acquire);
    if (((s & 1) != 0) != held) seq_.store(s + 1, std::memory_order_release);
  }

  // True once store() has run (a store may still be in progress).
  bool stored() const { return seq_.load(std::memory_order_acquire) != 0; }

 private:
  static constexpr size_t kWords = (sizeof(T) + sizeof(uint64_t) - 1) / sizeof(uint64_t);
  std::atomic<uint64_t> seq_{0};            // even: stable; odd: a store is in progress; 0: never stored
  std::atomic<uint64_t> words_[kWords]{};   // the value's bytes, as 64-bit words
};

}  // namespace dentsim
