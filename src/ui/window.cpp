// GLFW set-up: one initialisation per process, errors kept as text, window and surface creation.
#include "ui/window.h"

#include <cstdlib>
#include <mutex>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

namespace dentsim::ui {
namespace {

std::mutex g_glfw_mutex;
std::string g_last_glfw_error;  // GLFW reports errors through a callback; keep the latest as text

void onGlfwError(int code, const char* description) {
  g_last_glfw_error = std::string(description ? description : "unknown error") + " (GLFW error " + std::to_string(code) + ")";
}

// glfwInit's result for the process; GLFW is torn down at exit.
const std::string& initResult() {
  static const std::string result = [] {
    glfwSetErrorCallback(onGlfwError);
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!x11 || !*x11) && (!wayland || !*wayland)) return std::string("no display: DISPLAY and WAYLAND_DISPLAY are unset");
    if (glfwInit() != GLFW_TRUE) return "no display: " + g_last_glfw_error;
    std::atexit(glfwTerminate);
    if (glfwVulkanSupported() != GLFW_TRUE) return std::string("no display: GLFW finds no Vulkan loader for windows");
    return std::string();
  }();
  return result;
}

}  // namespace

std::string whyNoDisplay() {
  std::lock_guard lock(g_glfw_mutex);
  return initResult();
}

Result<std::unique_ptr<Window>> Window::open(int width, int height, const std::string& title) {
  if (std::string why = whyNoDisplay(); !why.empty()) return makeError("window", why);
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  GLFWwindow* w = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!w) return makeError("window", "cannot open a " + std::to_string(width) + "x" + std::to_string(height) + " window: " + g_last_glfw_error);
  return std::unique_ptr<Window>(new Window(w));
}

Window::~Window() {
  if (window_) glfwDestroyWindow(window_);
}

std::vector<std::string> Window::requiredInstanceExtensions() {
  std::vector<std::string> out;
  if (!whyNoDisplay().empty()) return out;
  uint32_t n = 0;
  const char** names = glfwGetRequiredInstanceExtensions(&n);
  for (uint32_t i = 0; names && i < n; ++i) out.emplace_back(names[i]);
  return out;
}

Result<VkSurfaceKHR> Window::createSurface(VkInstance instance) const {
  VkSurfaceKHR surface = VK_NULL_HANDLE;
  if (const VkResult r = glfwCreateWindowSurface(instance, window_, nullptr, &surface); r != VK_SUCCESS)
    return makeError("window", "cannot create a Vulkan surface (VkResult " + std::to_string(int(r)) + "): " + g_last_glfw_error);
  return surface;
}

bool Window::closeRequested() const { return glfwWindowShouldClose(window_) == GLFW_TRUE; }

VkExtent2D Window::framebufferExtent() const {
  int w = 0, h = 0;
  glfwGetFramebufferSize(window_, &w, &h);
  return VkExtent2D{uint32_t(w > 0 ? w : 0), uint32_t(h > 0 ? h : 0)};
}

void Window::pollEvents() { glfwPollEvents(); }
void Window::waitEvents(double timeout_s) { glfwWaitEventsTimeout(timeout_s); }

}  // namespace dentsim::ui
