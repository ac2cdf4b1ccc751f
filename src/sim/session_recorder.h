// SessionRecorder: writes a session file while the haptic loop runs, from a thread of its own, so that the loop never waits on the disk.
//
// The loop pushes each step's readings into a ring (HapticLoop::recordInto); the recorder's thread
// drains it, writes the records, hands them to the kernel every 200 ms of wall time or of loop time,
// whichever comes first, and to the disk every second, so a crash of dentsim loses nothing it has
// flushed and a power cut at most a second. A loop stepped back to back (lockstep, a scripted run)
// runs many times faster than the wall clock: it calls keepUp() after each step, so what the kernel
// holds never lags the loop by more than half a second of loop time (a kill -9 loses at most that).
// Parameter changes during a session go through the recorder, which records each set from the step
// that first used it. Steps the ring had no room for are written as a gap: replay stops there.
#pragma once

#include <atomic>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core/result.h"
#include "core/spsc_ring.h"
#include "io/session_file.h"
#include "sim/haptic_loop.h"
#include "sim/sim_params.h"

namespace dentsim {

class SessionRecorder {
 public:
  // The ring holds 2^ring_log2 steps: 16 s at 1 kHz by default, far more than a stalled disk
  // usually takes to come back.
  explicit SessionRecorder(int ring_log2 = 14);
  ~SessionRecorder();  // stops the thread (stop the loop first); an unfinished file stays as PATH.part
  SessionRecorder(const SessionRecorder&) = delete;
  SessionRecorder& operator=(const SessionRecorder&) = delete;

  // Creates the file (PATH.part until finish) with `info` as its header, starts the writing thread
  // and has `loop` record every later step. The loop's thread must be stopped.
  Status start(HapticLoop& loop, const std::string& path, const SessionInfo& info);
  // A new parameter set for the loop, recorded from the step that first uses it as simParamsJson.
  void setParams(const SimParams& params);
  // The same, recorded as `params_json`: the whole preset's text (ui::presetJson), whose tactile
  // sections are `params`.
  void setParams(const SimParams& params, std::string params_json);
  // A pen's device changed state (any thread; the app calls it from its frame loop): recorded
  // before the next step the loop runs, so the file says which pen failed and when.
  void noteDevice(PenRole pen, const std::string& state, const std::string& reason);
  // After the loop has stopped: writes what is left and the end record, and renames the file.
  // Returns the first write error of the session, if any.
  Status finish(const SessionEnd& end);

  // The loop's thread, or whoever steps the loop back to back, after each step: waits while the
  // steps handed to the kernel lag the loop's steps by more than kMaxLagS of loop time. Returns at
  // once when the loop has dropped records (the ring overflowed: the file has a gap anyway).
  // Never call it from the real-time thread: that one runs at the wall clock's pace.
  void keepUp() const;
  static constexpr double kFlushLoopS = 0.2;  // loop time between flushes to the kernel [s]
  static constexpr double kMaxLagS = 0.5;     // most loop time a back-to-back loop runs ahead of the kernel's copy [s]

  uint64_t stepsWritten() const { return steps_written_.load(std::memory_order_relaxed); }
  // The loop step up to which (exclusive) records are in the kernel's hands: what a kill -9 keeps.
  uint64_t stepsFlushed() const { return steps_flushed_.load(std::memory_order_acquire); }
  uint64_t stepsLost() const { return steps_lost_.load(std::memory_order_relaxed); }

 private:
  void run();
  uint64_t drain(uint64_t max_steps);
  void writeDevices(uint64_t up_to_step, bool all);

  SpscRing<SessionStep> ring_;
  SessionWriter writer_;
  HapticLoop* loop_ = nullptr;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  int64_t start_ns_ = 0;
  // Parameter sets by the loop's serial, until they come into force (then they are written).
  std::mutex params_mutex_;
  std::map<uint32_t, std::string> pending_params_;
  uint32_t loop_serial_ = 0;   // the loop's serial of the set in force
  uint32_t file_serial_ = 0;   // its serial in the file (1, 2, ... as they come into force)
  std::mutex devices_mutex_;
  std::vector<SessionDeviceEvent> pending_devices_;  // in step order, until written
  bool have_step_ = false;
  uint64_t next_step_ = 0;     // the step expected next
  std::atomic<uint64_t> steps_written_{0};
  std::atomic<uint64_t> steps_lost_{0};
  std::atomic<uint64_t> steps_flushed_{0};  // loop steps before this one are flushed (keepUp waits on it)
  uint64_t flush_steps_ = 200;  // kFlushLoopS in steps at the session's rate
  uint64_t max_lag_steps_ = 500;  // kMaxLagS in steps at the session's rate
  std::string error_;          // first write error (the thread's, read after join)
};

}  // namespace dentsim
