// The simulator's scene: the frame the renderer draws (beside the panel, with the ghost and the score picture), the tooth's place on screen, and one frame drawn with its screenshot or frame picture.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "app/simulator_state.h"

namespace dentsim::app {

render::FrameState Simulator::frameState(const HapticState& state, VkExtent2D extent) const {
  // The parameter window covers the right edge: the view's centre moves into the rest, so that the
  // tooth sits in the middle of what the student sees.
  render::FrameState fs = sceneFrameState(camera_, extent, float(sceneShiftPx()), 0.0f, state,
                                          SceneContents{state_.view.frame, ui_.looks.looks, model_.drill_name,
                                                        model_.mirror_tool.has_value(), ui_.params.device.max_force_n});
  showGhost(fs);
  fs.lod.pixel_error = o_.frames.detail_pixels;
  // The picture window holds the score's picture or the crown's reduction map (simulator_reduction.cpp).
  if ((state_.score_shown || ui_.reduction.on_screen) && !state_.last_actions.score_image_rect.empty()) {
    fs.overlay_shown = true;
    fs.overlay_rect = state_.last_actions.score_image_rect;
  }
  return fs;
}

PixelRect Simulator::toothRect(VkExtent2D extent) const {
  // The tissue box's corners projected as drawn (shifted beside the panel).
  const TissueBox& box = model_.box;
  const int w = int(std::max(1u, extent.width)), h = int(std::max(1u, extent.height));
  float lo_x = 1e9f, lo_y = 1e9f, hi_x = -1e9f, hi_y = -1e9f;
  for (int i = 0; i < 8; ++i) {
    const Vec3 p{(i & 1) ? box.hi.x : box.lo.x, (i & 2) ? box.hi.y : box.lo.y, (i & 4) ? box.hi.z : box.lo.z};
    if (camera_.depthOf(render::toGlm(p)) <= camera_.nearMm()) return {};
    const glm::vec3 px = camera_.project(render::toGlm(p), w, h);
    lo_x = std::min(lo_x, px.x - float(sceneShiftPx()));
    hi_x = std::max(hi_x, px.x - float(sceneShiftPx()));
    lo_y = std::min(lo_y, px.y);
    hi_y = std::max(hi_y, px.y);
  }
  PixelRect r;
  r.x = int(std::floor(lo_x));
  r.y = int(std::floor(lo_y));
  r.width = int(std::ceil(hi_x)) - r.x;
  r.height = int(std::ceil(hi_y)) - r.y;
  return r;
}

Status Simulator::drawFrame(const ShotSchedule::Due& due) {
  const HapticState state = segments_.state();
  render::FrameState drawn;
  const bool read_back = !due.shot_stem.empty() || !due.frame_stem.empty();
  auto picture = painter_->draw(
      [&](VkExtent2D extent) {
        drawn = frameState(state, extent);
        return drawn;
      },
      read_back);
  if (!picture) return picture.error();
  const render::ToothDrawStats drew = painter_->renderer().toothDrawStats();
  ui_.stats.triangles = drew.main_triangles + drew.mirror_triangles;
  stats_.triangles_drawn_sum += double(ui_.stats.triangles);
  if (out_.drawn == 0) out_.first_frame_s = std::chrono::duration<double>(Clock::now() - stats_.run_t0).count();
  if (!*picture) return Ok{};
  if (!due.shot_stem.empty()) {
    ShotFacts facts;
    facts.loop_time_s = segments_.loopTime();
    facts.windowed = !headless_;
    facts.shift_px = float(sceneShiftPx());
    facts.tooth_centre = model_.box.centre();
    facts.removed_mm3 = segments_.removedMm3();
    if (painter_->panel()) facts.score_image_rect = state_.last_actions.score_image_rect;
    facts.panel_shown = painter_->panel() != nullptr;
    facts.panel_rect = state_.panel_rect;
    facts.task = model_.task ? model_.task->name : "";
    facts.view_fixed = input_.viewFixed();
    facts.tooth_top_mm = model_.box.hi.z;
    facts.tooth_rect = toothRect(painter_->extent());
    if (painter_->panel()) facts.help_rect = state_.last_actions.help_rect;
    facts.drill_contact = ui_.force.contact;
    if (ui_.guidance.active) facts.guide_pull_n = ui_.guidance.pull_n;
    if (Status st = writeShot(outPath(due.shot_stem), **picture, camera_, drawn, facts); !st) return st;
    out_.written.push_back(outPath(due.shot_stem + ".png"));
  }
  if (!due.frame_stem.empty()) {
    const std::string png = outPath(due.frame_stem + ".png");
    if (Status st = writePng(png, **picture); !st) return st;
    out_.written.push_back(png);
  }
  return Ok{};
}

}  // namespace dentsim::app
