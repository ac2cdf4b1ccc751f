// ForceOutput: the latest force for one pen, stamped by the haptic loop, which a device reads as zero once it is stale.
//
// The haptic loop publishes a wrench every step; a device's I/O thread asks for the wrench to send
// at its own time. If the loop has not published for longer than `stale_after`, the answer is zero:
// a stalled loop (a page fault, a debugger, a starved core) can never leave the pen pushing. With
// stale_after = 1 ms and a device polling at 1 kHz, a stall reaches the pen as zero force within
// 2 ms. Lock-free: a SeqLock, one writer, any number of readers, nobody waits on a lock. It lives in
// core because both sides use it: sim publishes, devices/ reads.
#pragma once

#include <atomic>
#include <cstdint>

#include "core/rigid.h"
#include "core/seqlock.h"

namespace dentsim {

class ForceOutput {
 public:
  struct Command {
    Wrench wrench;           // what to send: the published wrench, or zero when stale
    int64_t stamp_ns = 0;    // when the loop published it (steady clock) [ns]
    bool stale = true;       // nothing published, or older than the limit: wrench is zero
    // A publish was in progress on every try (the writer was preempted inside it): nothing could be
    // read, so stale is set too. Not "nothing was ever published": a reader that judges age keeps
    // the last command it did read.
    bool busy = false;
  };

  // Writer (the haptic loop).
  void publish(const Wrench& w, int64_t stamp_ns) {
    latest_.store(Stamped{w, stamp_ns});
    last_stamp_.store(stamp_ns, std::memory_order_release);
  }
  // Any thread: the stamp of the newest publish that has completed (INT64_MIN before any). Read
  // when the value itself is busy: a reader that judges age then knows how fresh the loop is.
  int64_t lastStamp() const { return last_stamp_.load(std::memory_order_acquire); }

  // Tests only: readers find a publish in progress until released (SeqLock::holdMidStoreForTest).
  void holdPublishForTest(bool held) { latest_.holdMidStoreForTest(held); }

  // Readers (device threads, tests): the command for time now_ns. A writer that keeps the lock busy
  // reads as nothing published: zero force rather than a spin.
  Command current(int64_t now_ns, int64_t stale_after_ns) const {
    Command c;
    Stamped s;
    if (!latest_.load(&s)) {
      c.busy = latest_.stored();
      return c;
    }
    c.stamp_ns = s.stamp_ns;
    c.stale = now_ns - s.stamp_ns > stale_after_ns;
    if (!c.stale) c.wrench = s.wrench;
    return c;
  }

 private:
  struct Stamped {
    Wrench wrench;           // force [N], moment [N mm]
    int64_t stamp_ns = 0;    // steady clock [ns]
  };
  SeqLock<Stamped> latest_;
  std::atomic<int64_t> last_stamp_{INT64_MIN};
};

}  // namespace dentsim
