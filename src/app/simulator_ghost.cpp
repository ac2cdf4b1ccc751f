// The simulator's ghost: the professional's session read at set-up (--ghost) or when the panel first shows the task's ideal, followed each frame, and posed in the frame the renderer draws.
#include "app/simulator_state.h"

namespace dentsim::app {

std::string Simulator::ghostSource() const {
  if (!o_.ghost.session.empty()) return o_.ghost.session;
  // A teacher's "Record as ideal" keeps the session beside the task: the ideal to compare with.
  if (model_.task && model_.task->ideal && model_.task->ideal->kind == IdealKind::Session) return model_.task->ideal->path;
  return "";
}

// Both ways in (--ghost at set-up, the task's ideal when first shown) read and warn through here.
Status Simulator::loadGhost(const std::string& source) {
  auto g = GhostDriver::load(source, model_.params.point_shell, model_.initial);
  if (!g) return g.error();
  ghost_ = std::move(*g);
  for (const std::string& w : ghost_->warnings()) noteWarning(w);
  return Ok{};
}

Status Simulator::setUpGhost() {
  const std::optional<GhostFollow> follow = parseGhostFollow(o_.ghost.follow);
  if (!follow) return makeError("--ghost-follow", "\"" + o_.ghost.follow + "\" is not time or nearest");
  ui_.ghost_nearest = *follow == GhostFollow::Nearest;
  if (o_.ghost.session.empty()) return Ok{};
  // Asked for by name, a session that does not read ends the run before anything opens.
  if (Status st = loadGhost(o_.ghost.session); !st) return st;
  ui_.ghost_shown = true;
  ui_.ghost_source = "ghost: " + o_.ghost.session;
  return Ok{};
}

void Simulator::restartGhost() {
  ghost_t0_ = segments_.loopTime();
  if (ghost_) ghost_->restart();
}

void Simulator::followGhost(const HapticState& state) {
  const std::string source = ghostSource();
  ui_.ghost_available = !source.empty();
  if (source.empty() || !ui_.ghost_shown) return;
  if (!ghost_ || ghost_->source() != source) {
    ghost_.reset();
    if (source == ghost_failed_) {
      ui_.ghost_shown = false;
      return;
    }
    if (Status st = loadGhost(source); !st) {
      ghost_failed_ = source;
      ui_.ghost_shown = false;
      note("no ghost: " + st.message());
      ui_.ghost_source = "no ghost: " + st.message();
      return;
    }
    ui_.ghost_source = "ghost: the task's ideal, " + source;
  }
  if (ui_.ghost_nearest)
    ghost_->followNearest(state.tools[size_t(PenRole::Drill)].tool, model_.drill_tool->grip_local);
  else
    ghost_->followTime(segments_.loopTime() - ghost_t0_);
}

void Simulator::showGhost(render::FrameState& fs) const {
  if (ghost_ && ui_.ghost_shown && ghost_->source() == ghostSource()) poseGhost(*ghost_, ui_.ghost_opacity, fs);
}

}  // namespace dentsim::app
