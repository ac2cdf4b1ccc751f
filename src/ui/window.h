// Window: the simulator's GLFW window, its Vulkan surface, and whether this machine has a display at all.
//
// dentsim opens a window only where a display answers; `demo` and `run` fall back to headless
// frames otherwise, so the same command works on a desktop, over ssh and in CI.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "core/result.h"

struct GLFWwindow;

namespace dentsim::ui {

// Why no window can open here ("no display: DISPLAY and WAYLAND_DISPLAY are unset", or GLFW's own
// reason), or empty when one can. Initialises GLFW on first use.
std::string whyNoDisplay();

class Window {
 public:
  // Opens a resizable window of `width` x `height` screen units for Vulkan (no OpenGL context).
  // Errors: no display, GLFW without Vulkan support, a window the system refuses.
  static Result<std::unique_ptr<Window>> open(int width, int height, const std::string& title);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // The instance extensions the window system needs (for gpu::ContextOptions::instance_extensions).
  static std::vector<std::string> requiredInstanceExtensions();
  // A surface for this window on `instance`; the caller destroys it (the Swapchain does).
  Result<VkSurfaceKHR> createSurface(VkInstance instance) const;

  GLFWwindow* handle() const { return window_; }
  bool closeRequested() const;
  // Framebuffer size in pixels (0 x 0 while minimised).
  VkExtent2D framebufferExtent() const;
  // Handles pending window-system events (input callbacks run here, on the calling thread).
  static void pollEvents();
  // Sleeps until an event arrives or `timeout_s` passes (while minimised).
  static void waitEvents(double timeout_s);

 private:
  explicit Window(GLFWwindow* window) : window_(window) {}
  GLFWwindow* window_ = nullptr;
};

}  // namespace dentsim::ui
