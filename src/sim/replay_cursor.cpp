// ReplayCursor: the session's checks, its loop built and rebuilt, and its steps played with their forces compared.
#include "sim/replay_cursor.h"

#include <algorithm>

#include "sim/tool_library.h"
#include "volume/volume_hash.h"

namespace dentsim {

namespace {
constexpr const char* kWhere = "replay";
}  // namespace

ReplayCursor::ReplayCursor(const SessionRecording& session, ToothVolume& tooth, const ReplayCursorOptions& options)
    : session_(session), tooth_(tooth), start_(tooth), options_(options) {}

ReplayCursor::~ReplayCursor() = default;

Result<std::unique_ptr<ReplayCursor>> ReplayCursor::open(const SessionRecording& session, ToothVolume& tooth,
                                                         const ReplayCursorOptions& options) {
  std::unique_ptr<ReplayCursor> c(new ReplayCursor(session, tooth, options));
  if (!session.truncation_warning.empty()) c->warnings_.push_back(session.truncation_warning);
  const std::string hash = volumeHashHex(tooth.voxels, tooth.frame);
  if (hash != session.info.tooth_hash) {
    const std::string what = "the tooth's hash " + hash + " is not the session's " + session.info.tooth_hash +
                             " (" + session.info.tooth_source + "): a session replays only on the tooth it was recorded on";
    if (!options.allow_other_tooth) return makeError(kWhere, what);
    c->warnings_.push_back(what);
  }
  if (session.steps.empty()) return makeError(kWhere, "the session holds no steps");
  auto params = parseSimParams(session.info.params_json, "session parameters");
  if (!params) return params.error();
  c->params_ = std::move(*params);
  for (const SessionParams& p : session.params) {
    auto change = parseSimParams(p.params_json, "session parameters " + std::to_string(p.serial));
    if (!change) return change.error();
    c->changes_.push_back(std::move(*change));
  }
  auto drill = loadToolModel(session.info.drill_tool, c->params_.point_shell);
  if (!drill) return drill.error();
  c->drill_ = std::move(*drill);
  if (!session.info.mirror_tool.empty()) {
    auto mirror = loadToolModel(session.info.mirror_tool, c->params_.point_shell);
    if (!mirror) return mirror.error();
    c->mirror_ = std::move(*mirror);
  }
  // A guided session's forces held the guide's spring: the same guide, from the header, makes them again.
  if (!session.info.guide_json.empty()) {
    auto guide = parseGuideJson(session.info.guide_json, kWhere);
    if (!guide) return guide.error();
    c->guide_path_ = std::move(*guide);
  }
  c->rate_hz_ = session.info.rate_hz > 0 ? session.info.rate_hz : c->params_.device.rate_hz;

  // Steps up to the first gap: past it the loop's state is unknown.
  size_t count = session.steps.size();
  if (!session.gaps.empty()) {
    const uint64_t gap = session.gaps.front().first_step;
    for (size_t i = 0; i < session.steps.size(); ++i)
      if (session.steps[i].step >= gap) {
        count = i;
        break;
      }
    c->warnings_.push_back("the session lost steps from step " + std::to_string(gap) + "; replayed the " +
                           std::to_string(count) + " before them");
  }
  c->steps_ = std::span<const SessionStep>(session.steps.data(), count);
  if (c->steps_.empty()) return makeError(kWhere, "no step before the session's first gap");
  c->restart();
  return c;
}

void ReplayCursor::restart() {
  // The old loop lets go of the tooth before the tooth is put back.
  loop_.reset();
  if (position_ > 0) tooth_ = start_;
  drill_pen_ = std::make_unique<ReplayPen>(steps_, PenRole::Drill);
  mirror_pen_ = std::make_unique<ReplayPen>(steps_, PenRole::Mirror);
  loop_ = std::make_unique<HapticLoop>(tooth_.voxels, tooth_.frame, params_, drill_, mirror_ ? &*mirror_ : nullptr,
                                       options_.edits);
  loop_->attach(PenRole::Drill, drill_pen_.get());
  if (mirror_) loop_->attach(PenRole::Mirror, mirror_pen_.get());
  if (guide_path_) {
    guide_.emplace(*guide_path_);  // from its start_index again, as the recording began
    loop_->setGuide(&*guide_);
  }
  for (size_t r = 0; r < 2; ++r) {
    // Each proxy starts on its pen's first reading.
    for (const SessionStep& s : steps_)
      if (s.hasReading(r)) {
        loop_->placeTool(PenRole(r), s.reading[r].grip);
        break;
      }
  }
  position_ = 0;
  next_change_ = 0;
  force_mismatches_ = 0;
  first_mismatch_ = 0;
}

const StepReport& ReplayCursor::step() {
  const SessionStep& recorded = steps_[position_];
  while (next_change_ < session_.params.size() && session_.params[next_change_].from_step <= recorded.step) {
    loop_->setParams(changes_[next_change_]);
    ++next_change_;
  }
  // The recorded step's schedule, not this machine's clock, says how much of its work it did.
  loop_->followSchedule(&recorded.schedule);
  const StepReport& report = loop_->step();
  ++position_;
  // As the recording's loop did when it stopped: cuts still waiting go into the voxels.
  if (position_ == steps_.size()) loop_->flushCuts();
  const Vec3 force = report.stepped[0] ? report.tools[0].display.force : Vec3{};
  const Vec3& expected = recorded.force_n[0];
  if (force.x != expected.x || force.y != expected.y || force.z != expected.z) {
    if (force_mismatches_ == 0) first_mismatch_ = recorded.step;
    ++force_mismatches_;
  }
  return report;
}

size_t ReplayCursor::stepTo(size_t target, size_t max_steps) {
  target = std::min(target, steps_.size());
  // Half the channel's room stays free: more than any one step's cut edits.
  const size_t room = options_.edits ? options_.edits->capacity() / 2 : 0;
  size_t played = 0;
  while (position_ < target && played < max_steps && (!options_.edits || options_.edits->freeSlots() >= room)) {
    step();
    ++played;
  }
  return played;
}

ReplayOutcome ReplayCursor::outcome() const {
  ReplayOutcome out;
  out.steps = position_;
  out.removed_mm3 = loop_->latest().removed_mm3;
  out.final_hash = volumeHashHex(tooth_.voxels, tooth_.frame);
  out.force_mismatches = force_mismatches_;
  out.first_mismatch = first_mismatch_;
  out.warnings = warnings_;
  if (!session_.end) {
    out.warnings.push_back("the session has no end record (it was not finished cleanly)");
  } else {
    out.recorded_hash_matches = session_.end->final_hash == out.final_hash;
  }
  if (force_mismatches_ > 0)
    out.warnings.push_back("the replayed force differs from the recorded one at " + std::to_string(force_mismatches_) +
                           " steps, first at step " + std::to_string(first_mismatch_));
  return out;
}

}  // namespace dentsim
