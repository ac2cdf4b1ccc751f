// `dentsim bench frames`: the simulator's frame time while the demo drills, full detail against screen-sized detail in one run, per level, headless or in a window; and the same frames compared pixel by pixel.
#pragma once

#include <string>
#include <vector>

#include "gpu/mesher_kind.h"

namespace dentsim::app {

struct FramesBenchOptions {
  std::vector<int> levels{8, 9};  // octree levels of the built-in molar
  int frames = 120;               // frames drawn per level and path (the first 3 are left out of the figures)
  double from_s = 5.0;            // loop time of the first frame: the bur is cutting by then [s]
  int width = 1280, height = 720; // [px]
  bool window = false;            // draw into a window (a display must answer) instead of offscreen
  float detail_pixels = 1.0f;     // screen-sized detail's error [px] (the full-detail path draws 0)
  bool first_frame = true;        // also time the first frame of the demo, whole build against in parts
  gpu::MesherKind mesher = gpu::MesherKind::Auto;  // who meshes the tooth
  std::string out = "bench-out";  // frames.json, frames.md, frames.svg
  std::string device;
};

int runFramesBench(const FramesBenchOptions& options);

}  // namespace dentsim::app
