// ForceOutput: a sequence-locked wrench with its stamp; stale commands read as zero.
#include "sim/force_output.h"

namespace dentsim {

void ForceOutput::publish(const Wrench& w, int64_t stamp_ns) {
  const uint64_t s = seq_.load(std::memory_order_relaxed);
  seq_.store(s + 1, std::memory_order_relaxed);
  std::atomic_thread_fence(std::memory_order_release);
  const double v[6] = {w.force.x, w.force.y, w.force.z, w.moment.x, w.moment.y, w.moment.z};
  for (int i = 0; i < 6; ++i) values_[i].store(v[i], std::memory_order_relaxed);
  stamp_ns_.store(stamp_ns, std::memory_order_relaxed);
  published_.store(true, std::memory_order_relaxed);
  seq_.store(s + 2, std::memory_order_release);
}

ForceOutput::Command ForceOutput::current(int64_t now_ns, int64_t stale_after_ns) const {
  Command c;
  // A writer is never preempted for long inside publish(); give up (zero force) rather than spin.
  for (int attempt = 0; attempt < 64; ++attempt) {
    const uint64_t s1 = seq_.load(std::memory_order_acquire);
    if (s1 & 1) continue;
    double v[6];
    for (int i = 0; i < 6; ++i) v[i] = values_[i].load(std::memory_order_relaxed);
    const int64_t stamp = stamp_ns_.load(std::memory_order_relaxed);
    const bool published = published_.load(std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_acquire);
    if (seq_.load(std::memory_order_relaxed) != s1) continue;
    c.stamp_ns = stamp;
    c.stale = !published || now_ns - stamp > stale_after_ns;
    if (!c.stale) c.wrench = Wrench{{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
    return c;
  }
  return c;
}

}  // namespace dentsim
