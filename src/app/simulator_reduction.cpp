// The simulator's live reduction map for a crown task: the View page's switch read each frame, the map measured on a worker thread from copies of the teeth, and shown in the picture window.
//
// The picture window holds one picture: the latest asked for. Score shows the score's picture; the
// map takes the window back when the tooth next changes, and turning the map off brings the score's
// picture back. A frame that writes a picture to disk waits for the map of the tooth it shows, so
// that screenshots do not depend on how fast this machine measures.
#include <cstdio>

#include "app/simulator_state.h"

namespace dentsim::app {

Status Simulator::refreshReductionMap(const FramePlan& plan) {
  ui::ReductionMapView& view = ui_.reduction;
  view.available = model_.task && model_.task->kind == TaskKind::Crown;
  const bool on = view.available && view.shown;
  if (on != map_on_) {
    map_on_ = on;
    if (on) {
      view.status = "measuring...";
      map_.toothChanged();  // a first map at once
    } else if (Status st = hideReductionMap(); !st) {
      return st;
    }
  }
  if (!on || !plan.draw) return Ok{};
  const auto now = Clock::now();
  if (plan.picture()) {
    if (auto done = map_.wait())
      if (Status st = showReductionMap(*done); !st) return st;
    if (!map_.stale()) return Ok{};
    map_.start(now, reductionMapJob());
    if (auto done = map_.wait()) return showReductionMap(*done);
    return Ok{};
  }
  if (auto done = map_.take())
    if (Status st = showReductionMap(*done); !st) return st;
  if (map_.due(now)) map_.start(now, reductionMapJob());
  return Ok{};
}

ReductionMapRefresh::Job Simulator::reductionMapJob() {
  // Copied here, on the frame thread, between two drains of the loop's edits: the worker reads a
  // tooth nobody writes. The uncut tooth is copied once per tooth.
  if (!map_initial_) map_initial_ = std::make_shared<const ToothVolume>(model_.initial);
  auto current = std::make_shared<const ToothVolume>(state_.view);
  return [task = *model_.task, initial = map_initial_, current] { return drawReductionMap(task, *initial, *current); };
}

Status Simulator::showReductionMap(const Result<ReductionMap>& map) {
  ui::ReductionMapView& view = ui_.reduction;
  if (!map) {
    view.status = "no map: " + map.message();
    return Ok{};
  }
  if (!map_timed_) {
    std::printf("reduction map: measured and drawn in %.0f ms (level %d)\n", map->compute_ms, model_.initial.frame.level);
    std::fflush(stdout);
    map_timed_ = true;
  }
  if (Status st = painter_->renderer().setOverlayImage(map->picture); !st) return st;
  view.on_screen = true;
  view.image_width = map->picture.width;
  view.image_height = map->picture.height;
  view.legend = "bands: " + map->legend;
  char took[48];
  std::snprintf(took, sizeof took, " (%.1f s to measure)", map->compute_ms / 1000.0);
  view.status = (map->summary.empty() ? std::string("nothing measured yet") : map->summary) + took;
  return Ok{};
}

Status Simulator::hideReductionMap() {
  map_.discard();
  ui::ReductionMapView& view = ui_.reduction;
  const bool was_on_screen = view.on_screen;
  view.on_screen = false;
  view.status.clear();
  if (was_on_screen && state_.score_shown) return painter_->renderer().setOverlayImage(state_.score_picture);
  return Ok{};
}

void Simulator::reductionMapNewTooth(bool new_initial) {
  map_.discard();
  if (new_initial) map_initial_.reset();
  ui_.reduction.on_screen = false;
  if (map_on_) map_.toothChanged();
}

}  // namespace dentsim::app
