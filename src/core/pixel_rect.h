// PixelRect: a rectangle of a framebuffer in pixels, shared by the renderer and the panel that lays out where pictures go.
#pragma once

namespace dentsim {

struct PixelRect {
  int x = 0, y = 0;           // top-left corner, from the framebuffer's top-left [px]
  int width = 0, height = 0;  // [px]
  bool empty() const { return width <= 0 || height <= 0; }
};

}  // namespace dentsim
