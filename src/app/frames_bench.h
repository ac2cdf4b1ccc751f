// `dentsim bench frames`: the simulator's frame time while the demo drills, per level, headless or in a window.
#pragma once

#include <string>
#include <vector>

namespace dentsim::app {

struct FramesBenchOptions {
  std::vector<int> levels{8, 9};  // octree levels of the built-in molar
  int frames = 120;               // frames drawn per level (the first 3 are left out of the figures)
  double from_s = 5.0;            // loop time of the first frame: the bur is cutting by then [s]
  int width = 1280, height = 720; // [px]
  bool window = false;            // draw into a window (a display must answer) instead of offscreen
  std::string out = "bench-out";  // frames.json, frames.md, frames.svg
  std::string device;
};

int runFramesBench(const FramesBenchOptions& options);

}  // namespace dentsim::app
