// Screenshot and frame schedule, and the screenshot's JSON.
#include "app/screenshots.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <nlohmann/json.hpp>

#include "io/atomic_file.h"
#include "model/tool_generator.h"

namespace dentsim::app {

ShotSchedule::ShotSchedule(std::vector<double> shots_s, double frame_every_s)
    : shots_s_(std::move(shots_s)), frame_every_s_(frame_every_s) {
  std::sort(shots_s_.begin(), shots_s_.end());
}

ShotSchedule::Due ShotSchedule::at(double t) {
  Due due;
  if (next_shot_ < shots_s_.size() && t >= shots_s_[next_shot_] - 1e-9) {
    due.shot_stem = "shot-" + std::to_string(++next_shot_);
    while (next_shot_ < shots_s_.size() && t >= shots_s_[next_shot_] - 1e-9) ++next_shot_;
  }
  if (frame_every_s_ > 0 && t >= next_frame_s_ - 1e-9) {
    char name[32];
    std::snprintf(name, sizeof name, "frame-%05d", frames_written_++);
    due.frame_stem = name;
    next_frame_s_ += frame_every_s_;
  }
  if (final_due_) {
    due.shot_stem = "shot-final";
    final_due_ = false;
  }
  return due;
}

Status writeShot(const std::string& stem_path, const RgbImage& image, const render::OrbitCamera& camera,
                 const render::FrameState& fs, const ShotFacts& facts) {
  if (Status st = writePng(stem_path + ".png", image); !st) return st;
  const int w = image.width, h = image.height;
  const float shift = facts.shift_px;
  auto point = [&](const Vec3& p) {
    const glm::vec3 q = camera.project(render::toGlm(p), w, h);
    return nlohmann::json::array({q.x - shift, q.y});
  };
  nlohmann::ordered_json j;
  j["loop_time_s"] = facts.loop_time_s;
  j["width"] = w;
  j["height"] = h;
  j["windowed"] = facts.windowed;
  j["bur_tip_px"] = point(fs.drill.position);
  j["bur_shank_px"] = point(fs.drill.apply({0.0, 0.0, 4.0}));  // on the shank, below the handpiece's nose
  if (fs.ghost_drill_shown) {
    j["ghost_bur_tip_px"] = point(fs.ghost_drill.position);
    j["ghost_bur_shank_px"] = point(fs.ghost_drill.apply({0.0, 0.0, 4.0}));
  }
  if (fs.mirror_shown) {
    const Vec3 centre = fs.mirror.position;
    const glm::vec3 pc = camera.project(render::toGlm(centre), w, h);
    // The face's on-screen half-extent: the farthest of a few rim points from the centre.
    double radius_px = 0;
    for (int k = 0; k < 8; ++k) {
      const double a = 2 * std::numbers::pi * k / 8;
      const Vec3 rim = fs.mirror.apply({kMirrorGlassRadiusMm * std::cos(a), kMirrorGlassRadiusMm * std::sin(a), 0.0});
      const glm::vec3 pr = camera.project(render::toGlm(rim), w, h);
      radius_px = std::max(radius_px, double(glm::length(glm::vec2(pr.x - pc.x, pr.y - pc.y))));
    }
    j["mirror_centre_px"] = nlohmann::json::array({pc.x - shift, pc.y});
    j["mirror_radius_px"] = radius_px;
    j["mirror_faces_eye"] = glm::dot(render::toGlm(fs.mirror.applyDirection({0, 0, 1})), fs.eye - render::toGlm(centre)) > 0;
  }
  j["tooth_centre_px"] = point(facts.tooth_centre);
  j["removed_mm3"] = facts.removed_mm3;
  if (!facts.score_image_rect.empty()) {
    const PixelRect& r = facts.score_image_rect;
    j["score_image_rect"] = {r.x, r.y, r.width, r.height};
  }
  if (!facts.tooth_rect.empty()) {
    const PixelRect& r = facts.tooth_rect;
    j["tooth_rect"] = {r.x, r.y, r.width, r.height};
  }
  // Where the eye is: a view from below the occlusal surface cannot see it but in the mirror.
  const glm::vec3 eye = camera.eye();
  j["camera"] = {{"yaw_deg", camera.yaw() * 180.0 / std::numbers::pi},
                 {"pitch_deg", camera.pitch() * 180.0 / std::numbers::pi},
                 {"eye_mm", {eye.x, eye.y, eye.z}},
                 {"fixed", facts.view_fixed}};
  // World [mm] to Vulkan clip space as drawn (panel shift included), columns first: a reader
  // projects any point with it (pixel = (ndc * 0.5 + 0.5) * size).
  const glm::mat4 vp = fs.projection * fs.view;
  nlohmann::ordered_json columns = nlohmann::ordered_json::array();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) columns.push_back(vp[c][r]);
  j["camera"]["view_proj"] = columns;
  j["tooth_top_mm"] = facts.tooth_top_mm;
  if (!facts.task.empty()) j["task"] = facts.task;
  j["panel_shown"] = facts.panel_shown;
  if (facts.panel_rect.width > 0) {
    const PixelRect& r = facts.panel_rect;
    j["panel_rect"] = {r.x, r.y, r.width, r.height};
  }
  if (facts.help_rect.width > 0) {
    const PixelRect& r = facts.help_rect;
    j["help_rect"] = {r.x, r.y, r.width, r.height};
  }
  j["drill_contact"] = facts.drill_contact;
  if (facts.guide_pull_n >= 0.0) j["guide_pull_n"] = facts.guide_pull_n;
  return writeFileAtomic(stem_path + ".json", j.dump(2) + "\n");
}

}  // namespace dentsim::app
