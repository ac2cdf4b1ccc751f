// Starting and ending the simulator's segments: the starting tooth, the loop, the session file.
#include "app/segments.h"

#include <filesystem>

#include "io/session_file.h"
#include "sim/session_run.h"
#include "volume/tooth_file.h"
#include "volume/volume_hash.h"

namespace dentsim::app {

uint64_t Segments::steps() const {
  if (!loop_) return 0;
  return lockstep_ ? loop_->stepsRun() : loop_->counters().steps.load(std::memory_order_relaxed);
}

double Segments::loopTime() const {
  if (!loop_) return t0_;
  return t0_ + double(steps()) / rate_hz_;
}

Status Segments::start(ToothVolume& tooth, const SegmentSetup& setup, std::vector<std::string>* written) {
  namespace fs = std::filesystem;
  const int index = ++count_;
  const std::string suffix = index == 1 ? "" : "-" + std::to_string(index);
  const std::string tooth_name = "initial" + suffix + ".dvol";
  auto out_path = [&](const std::string& name) { return (fs::path(setup.out) / name).string(); };
  initial_path_.clear();
  last_session_path_.clear();
  if (!setup.out.empty()) {
    if (Status st = saveTooth(out_path(tooth_name), tooth); !st) return st;
    written->push_back(out_path(tooth_name));
    initial_path_ = out_path(tooth_name);
  }
  rate_hz_ = setup.params->device.rate_hz;
  lockstep_ = setup.lockstep;
  loop_ = std::make_unique<HapticLoop>(tooth.voxels, tooth.frame, *setup.params, *setup.drill, setup.mirror, &edits_);
  loop_->setIdleLatencyUs(setup.idle_latency_us);
  if (setup.guide) {
    GuidePath g = *setup.guide;
    if (setup.guide_goes_on && guide_) g.start_index = guide_->cursor();
    guide_.emplace(std::move(g));
    loop_->setGuide(&*guide_);
  } else {
    guide_.reset();
  }
  for (PenRole role : {PenRole::Drill, PenRole::Mirror}) {
    if (role == PenRole::Mirror && !setup.mirror) continue;
    PenSource* pen = setup.pens[size_t(role)];
    if (!pen) continue;
    loop_->attach(role, pen);
    // A new loop's time starts at 0, and a session's proxies start on the reading its first step
    // consumes, which is what replay assumes.
    PenReading first;
    if (pen->read(0.0, &first)) loop_->placeTool(role, first.grip);
  }
  if (!setup.out.empty()) {
    SessionInfo info;
    info.created_utc = utcNow();
    info.program = std::string("dentsim ") + DENTSIM_VERSION;
    info.task = setup.task_name;
    info.tooth_file = tooth_name;
    info.tooth_source = setup.tooth_source;
    info = sessionHeader(std::move(info), tooth, *setup.params, setup.drill_name, setup.mirror ? setup.mirror_name : "");
    if (!setup.params_json.empty()) info.params_json = setup.params_json;
    if (guide_) info.guide_json = guideJson(guide_->path());
    session_path_ = out_path("session" + suffix + ".dses");
    last_session_path_ = session_path_;
    recorder_ = std::make_unique<SessionRecorder>();
    if (Status st = recorder_->start(*loop_, session_path_, info); !st) return st;
  }
  if (!lockstep_)
    if (Status st = loop_->start(); !st) return st;
  return Ok{};
}

Status Segments::end(const std::string& reason, const ToothVolume& tooth, std::vector<std::string>* written) {
  if (!loop_) return Ok{};
  loop_->stop();
  // The thread's request is read only after it stopped; every segment would say the same, so once.
  if (loop_->idleLatencyDenied() && !idle_latency_denial_seen_) {
    idle_latency_denial_seen_ = true;
    idle_latency_denial_ = loop_->idleLatencyNote();
  }
  t0_ = loopTime();
  steps_done_ += loop_->stepsRun();
  last_state_ = loop_->latest();
  for (ToolState& t : last_state_.tools) t.display = Wrench{};
  last_state_.pedal = 0.0;
  removed_done_mm3_ += last_state_.removed_mm3;
  Status result = Ok{};
  if (recorder_) {
    const SessionEnd end{loop_->stepsRun(), volumeHashHex(tooth.voxels, tooth.frame), reason};
    if (Status st = recorder_->finish(end); !st) result = st;
    else written->push_back(session_path_);
  }
  recorder_.reset();
  session_path_.clear();
  // The loop goes after the recorder, which reads from it until finish().
  loop_.reset();
  return result;
}

void Segments::drainEdits(BrickVolume& view, std::vector<BrickCoord>* dirty) {
  batch_.clear();
  edits_.drain(&batch_);
  if (!batch_.empty()) applyVoxelEdits(view, batch_, dirty);
}

void Segments::stepTo(double t) {
  if (!loop_) return;
  HapticLoop& loop = *loop_;
  while (t0_ + double(loop.stepsRun()) / rate_hz_ < t - 1e-9) {
    loop.step();
    // Back to back, the loop outruns the disk; let the recorder keep up, so a kill loses at most
    // half a second of loop time.
    if (recorder_) recorder_->keepUp();
  }
}

}  // namespace dentsim::app
