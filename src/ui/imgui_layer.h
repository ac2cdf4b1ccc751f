// ImGuiLayer: the Dear ImGui context with its GLFW input backend (optional) and Vulkan draw backend, drawn inside the caller's render pass.
//
// One frame:
//   layer.newFrame(fb_width, fb_height, dt_s);     // input, display size, clock
//   PanelActions a = drawParamPanel(state);        // any ImGui calls
//   drawOverlay(state);
//   ... the renderer draws the scene (and the score picture in a.score_image_rect) ...
//   layer.render(cmd);                             // inside the same render pass, last
//
// Input and callbacks. With a window, create() installs the GLFW backend's callbacks (mouse button,
// scroll, key, char, focus, cursor enter), which first call whatever callback the window had and
// then record the event for ImGui. So the app must install its own GLFW callbacks BEFORE create():
// they keep running, chained, and check wantsMouse() / wantsKeyboard() to ignore what the panel
// uses. A callback the app installs after create() replaces ImGui's and the panel goes deaf to it.
// Destroying the layer puts the app's callbacks back. The cursor position is polled, not a callback.
// The backend finds its state through ImGui's current context, so glfwPollEvents must run while this
// layer's context is current (create() and newFrame() leave it so; the app should not switch it).
// Those callbacks see wantsMouse() as of the last newFrame, which is the frame the user looked at.
//
// Reproducible pixels: the display size is the framebuffer size given to newFrame (the mouse is
// mapped from window to framebuffer coordinates), the clock is dt_s, there is no .ini file, the
// text cursor does not blink, and windows open at fixed places; the same inputs give the same frame
// headless and windowed.
#pragma once

#include <cstdint>
#include <memory>

#include <vulkan/vulkan.h>

#include "core/result.h"
#include "gpu/context.h"

struct GLFWwindow;
struct ImGuiContext;

namespace dentsim::ui {

class ImGuiLayer {
 public:
  // Creates the ImGui context and the backends for `render_pass`'s `subpass`, and uploads the font
  // atlas with one submission on the context's queue (which must do graphics: ContextOptions::graphics).
  // `image_count` (>= 2 is used) is how many frames may be in flight: each gets its own vertex
  // buffers, reused after that many render() calls. `window` null: headless, no input backend; drive
  // ImGui::GetIO() directly. The new context is left current. Errors: descriptor pool or backend
  // creation, the font upload.
  static Result<ImGuiLayer> create(gpu::Context& ctx, VkRenderPass render_pass, uint32_t subpass, uint32_t image_count,
                                   GLFWwindow* window, VkSampleCountFlagBits samples = VK_SAMPLE_COUNT_1_BIT);

  ImGuiLayer(ImGuiLayer&&) noexcept;
  ImGuiLayer& operator=(ImGuiLayer&&) noexcept;
  ImGuiLayer(const ImGuiLayer&) = delete;
  ImGuiLayer& operator=(const ImGuiLayer&) = delete;
  // Waits for the device to be idle (the backend's buffers may be in flight), then frees everything.
  ~ImGuiLayer();

  // Starts a frame of `width` x `height` framebuffer pixels, `dt_s` [s] after the last (<= 0: 1/60).
  // Makes this layer's ImGui context current.
  void newFrame(int width, int height, double dt_s);
  // Ends the frame and records its draws into `cmd`, which must be inside the render pass given to
  // create(), at its subpass.
  void render(VkCommandBuffer cmd);
  // The next newFrame sees the mouse at (x, y) framebuffer pixels with its left button down or up,
  // whatever the window's own mouse does: a scripted click is one frame down, the next up.
  void scriptMouse(float x, float y, bool left_down);
  // Ends the frame without drawing (a minimised window).
  void discardFrame();

  // The panel has the mouse / keyboard (as of the last newFrame): the camera and the virtual pen
  // should ignore them.
  bool wantsMouse() const;
  bool wantsKeyboard() const;

  ImGuiContext* context() const;

 private:
  struct State;
  explicit ImGuiLayer(std::unique_ptr<State> state);
  std::unique_ptr<State> s_;
};

}  // namespace dentsim::ui
