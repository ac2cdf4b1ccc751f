// SessionRecorder: the writing thread between the loop's ring and the session file.
#include "sim/session_recorder.h"

#include <algorithm>
#include <chrono>
#include <system_error>

#include "core/steady_clock.h"

namespace dentsim {

namespace {
constexpr int64_t kFlushNs = 200'000'000;   // to the kernel
constexpr int64_t kSyncNs = 1'000'000'000;  // to the disk
constexpr auto kIdle = std::chrono::milliseconds(20);
// A back-to-back loop fills the ring far faster than 20 ms allows for: after a drain this full the
// thread only yields for a moment, so keepUp() does not hold the loop for long.
constexpr auto kBusy = std::chrono::milliseconds(1);
}  // namespace

SessionRecorder::SessionRecorder(int ring_log2) : ring_(ring_log2) {}

SessionRecorder::~SessionRecorder() {
  if (thread_.joinable()) {
    if (loop_ != nullptr && !loop_->running()) loop_->recordInto(nullptr);
    stop_.store(true);
    thread_.join();
  }
}

Status SessionRecorder::start(HapticLoop& loop, const std::string& path, const SessionInfo& info) {
  if (thread_.joinable()) return makeError(path, "the recorder is already recording");
  if (loop.running()) return makeError(path, "the haptic loop must be stopped when recording starts");
  if (Status st = writer_.open(path, info); !st) return st;
  loop_ = &loop;
  loop_serial_ = loop.activeParamsSerial();
  const double rate_hz = info.rate_hz > 0.0 ? info.rate_hz : 1000.0;
  flush_steps_ = std::max<uint64_t>(1, uint64_t(rate_hz * kFlushLoopS));
  max_lag_steps_ = std::max<uint64_t>(flush_steps_ + 1, uint64_t(rate_hz * kMaxLagS));
  steps_flushed_.store(loop.stepsRun(), std::memory_order_release);
  start_ns_ = steadyNowNs();
  stop_.store(false);
  loop.recordInto(&ring_);
  try {
    thread_ = std::thread([this] { run(); });
  } catch (const std::system_error& e) {
    loop.recordInto(nullptr);
    return makeError(path, std::string("cannot start the recording thread: ") + e.what());
  }
  return Ok{};
}

void SessionRecorder::setParams(const SimParams& params) { setParams(params, simParamsJson(params)); }

void SessionRecorder::setParams(const SimParams& params, std::string json) {
  std::lock_guard<std::mutex> lock(params_mutex_);
  const uint32_t serial = loop_->setParams(params);
  pending_params_[serial] = std::move(json);
}

void SessionRecorder::noteDevice(PenRole pen, const std::string& state, const std::string& reason) {
  if (loop_ == nullptr) return;
  SessionDeviceEvent e;
  e.step = loop_->stepsRun();
  e.pen = uint8_t(pen);
  e.state = state;
  // The file keeps printable ASCII of at most 200 bytes: a device's own words are cut to fit.
  for (char c : reason)
    if (e.reason.size() < 200) e.reason.push_back(c >= 0x20 && c < 0x7f ? c : '?');
  std::lock_guard<std::mutex> lock(devices_mutex_);
  if (!pending_devices_.empty()) e.step = std::max(e.step, pending_devices_.back().step);
  pending_devices_.push_back(std::move(e));
}

void SessionRecorder::writeDevices(uint64_t up_to_step, bool all) {
  std::lock_guard<std::mutex> lock(devices_mutex_);
  size_t n = 0;
  while (n < pending_devices_.size() && (all || pending_devices_[n].step <= up_to_step)) writer_.add(pending_devices_[n++]);
  pending_devices_.erase(pending_devices_.begin(), pending_devices_.begin() + long(n));
}

void SessionRecorder::keepUp() const {
  if (loop_ == nullptr || !thread_.joinable()) return;
  while (loop_->droppedRecords() == 0 && loop_->stepsRun() > stepsFlushed() + max_lag_steps_)
    std::this_thread::sleep_for(std::chrono::microseconds(200));
}

uint64_t SessionRecorder::drain(uint64_t max_steps) {
  uint64_t taken = 0;
  for (const SessionStep* s; taken < max_steps && (s = ring_.front()) != nullptr; ++taken) {
    if (have_step_ && s->step != next_step_) {
      const SessionGap gap{next_step_, s->step - next_step_};
      writer_.add(gap);
      steps_lost_.fetch_add(gap.steps, std::memory_order_relaxed);
    }
    have_step_ = true;
    next_step_ = s->step + 1;
    if (s->params_serial != loop_serial_) {
      std::string json;
      {
        std::lock_guard<std::mutex> lock(params_mutex_);
        auto it = pending_params_.find(s->params_serial);
        if (it != pending_params_.end()) {
          json = std::move(it->second);
          // Sets the loop skipped (a newer one came before it could use them) are never written.
          pending_params_.erase(pending_params_.begin(), std::next(it));
        }
      }
      if (json.empty()) {
        // A set that did not come through setParams(): its values are unknown, so the step cannot
        // be replayed; it is written as lost.
        writer_.add(SessionGap{s->step, 1});
        steps_lost_.fetch_add(1, std::memory_order_relaxed);
        ring_.pop();
        continue;
      }
      loop_serial_ = s->params_serial;
      writer_.add(SessionParams{++file_serial_, s->step, std::move(json)});
    }
    writeDevices(s->step, false);
    SessionStep out = *s;
    ring_.pop();
    out.wall_ns -= start_ns_;
    out.params_serial = file_serial_;
    writer_.add(out);
    steps_written_.fetch_add(1, std::memory_order_relaxed);
  }
  return taken;
}

void SessionRecorder::run() {
  int64_t last_flush = steadyNowNs(), last_sync = last_flush;
  auto note = [&](Status st) {
    if (!st && error_.empty()) error_ = st.error().message;
  };
  // After each flush, keepUp() may let the loop run on. A failed flush marks the steps too: they
  // are lost either way (finish() reports it), and the loop must not wait for them forever.
  auto flushed = [&] {
    if (have_step_) steps_flushed_.store(next_step_, std::memory_order_release);
  };
  while (!stop_.load(std::memory_order_relaxed)) {
    // At most one flush interval of loop time per pass, so a loop that outruns the wall clock
    // still gets a flush every kFlushLoopS of its own time.
    const uint64_t taken = drain(flush_steps_);
    const int64_t now = steadyNowNs();
    const uint64_t flushed_to = stepsFlushed();
    const bool loop_due = have_step_ && next_step_ >= flushed_to + flush_steps_;
    if (now - last_sync >= kSyncNs) {
      note(writer_.sync());
      flushed();
      last_sync = last_flush = now;
    } else if (now - last_flush >= kFlushNs || loop_due) {
      note(writer_.flush());
      flushed();
      last_flush = now;
    }
    if (taken < flush_steps_) std::this_thread::sleep_for(taken * 4 >= flush_steps_ ? kBusy : kIdle);
  }
  drain(UINT64_MAX);
  note(writer_.flush());
  flushed();
}

Status SessionRecorder::finish(const SessionEnd& end) {
  if (!thread_.joinable()) return makeError(writer_.partPath(), "the recorder is not recording");
  if (loop_->running()) return makeError(writer_.partPath(), "stop the haptic loop before finishing its session");
  loop_->recordInto(nullptr);
  stop_.store(true);
  thread_.join();
  // Steps dropped after the last one written leave no later step to show the gap.
  const uint64_t run = loop_->stepsRun();
  if (have_step_ && run > next_step_) {
    writer_.add(SessionGap{next_step_, run - next_step_});
    steps_lost_.fetch_add(run - next_step_, std::memory_order_relaxed);
  }
  writeDevices(0, true);
  if (Status st = writer_.finish(end); !st) return st;
  if (!error_.empty()) return makeError(writer_.partPath(), error_);
  return Ok{};
}

}  // namespace dentsim
