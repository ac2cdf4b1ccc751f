// The simulator's pictures on disk: when screenshots and frames fall due, and each screenshot's JSON of where things are in it.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "core/pixel_rect.h"
#include "core/result.h"
#include "core/rigid.h"
#include "io/png_file.h"
#include "render/camera.h"
#include "render/scene_renderer.h"

namespace dentsim::app {

// Which pictures a frame at a loop time owes: shot-N at the asked times, frame-NNNNN every so
// often, and shot-final once after the end.
class ShotSchedule {
 public:
  ShotSchedule(std::vector<double> shots_s, double frame_every_s);
  struct Due {
    std::string shot_stem;   // "shot-3", "shot-final"; empty: none
    std::string frame_stem;  // "frame-00012"; empty: none
  };
  Due at(double loop_time_s);
  void finalShot() { final_due_ = true; }
  bool finalShotPending() const { return final_due_; }

 private:
  std::vector<double> shots_s_;  // sorted
  size_t next_shot_ = 0;
  double frame_every_s_ = 0.0;
  double next_frame_s_ = 0.0;
  int frames_written_ = 0;
  bool final_due_ = false;
};

// What a screenshot's JSON says beside its picture: where the test and the reader find things in it.
struct ShotFacts {
  double loop_time_s = 0.0;
  bool windowed = false;
  float shift_px = 0.0f;             // the scene moved left by this, to centre it beside the panel
  Vec3 tooth_centre;                 // the tissue box's centre [mm]
  double removed_mm3 = 0.0;
  PixelRect score_image_rect;        // empty: no score picture shown
  bool panel_shown = false;
  PixelRect panel_rect;              // empty: none
  std::string task;                  // the task's name
  bool view_fixed = false;           // the task's view: the mouse and keys cannot move the camera
  double tooth_top_mm = 0.0;         // the tissue box's top (the occlusal surface's height) [mm]
  PixelRect tooth_rect;              // the tissue box's projection on screen; empty: not computed
  PixelRect help_rect;               // the controls overlay's window; empty: not shown
  bool drill_contact = false;        // the bur touches tissue (the force gauge's CONTACT)
  double guide_pull_n = -1.0;        // the guide's pull on the overlay [N]; < 0: the segment is not guided
};

// Writes STEM.png and STEM.json (the projected bur tip and shank, the ghost bur's too when shown, the
// mirror's centre, radius and facing, the tooth's centre and rectangle, the camera, the panel), atomically.
Status writeShot(const std::string& stem_path, const RgbImage& image, const render::OrbitCamera& camera,
                 const render::FrameState& frame, const ShotFacts& facts);

}  // namespace dentsim::app
