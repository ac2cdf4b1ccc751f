// Mouse and keys in the simulator window.
#include "app/window_input.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include "app/tool_placement.h"

namespace dentsim::app {

void WindowInput::attach(ui::Window& window) {
  window_ = &window;
  GLFWwindow* w = window.handle();
  glfwSetWindowUserPointer(w, this);
  glfwSetMouseButtonCallback(w, [](GLFWwindow* win, int b, int a, int m) {
    static_cast<WindowInput*>(glfwGetWindowUserPointer(win))->onMouseButton(b, a, m);
  });
  glfwSetCursorPosCallback(w, [](GLFWwindow* win, double x, double y) {
    static_cast<WindowInput*>(glfwGetWindowUserPointer(win))->onCursor(x, y);
  });
  glfwSetScrollCallback(w, [](GLFWwindow* win, double dx, double dy) {
    static_cast<WindowInput*>(glfwGetWindowUserPointer(win))->onScroll(dx, dy);
  });
  glfwSetKeyCallback(w, [](GLFWwindow* win, int key, int, int action, int mods) {
    static_cast<WindowInput*>(glfwGetWindowUserPointer(win))->onKey(key, action, mods);
  });
}

void WindowInput::onMouseButton(int button, int action, int mods) {
  const bool down = action == GLFW_PRESS;
  if (down && panel_ && panel_->wantsMouse()) return;
  if (button == GLFW_MOUSE_BUTTON_LEFT) {
    dragging_pen_ = down && pens_ != nullptr;
    // Shift holds the mirror: the drill hand and the mirror hand take turns on one mouse.
    if (pens_ && down) pens_->setActive((mods & GLFW_MOD_SHIFT) ? PenRole::Mirror : PenRole::Drill);
  } else if (button == GLFW_MOUSE_BUTTON_RIGHT) {
    orbiting_ = down;
  } else if (button == GLFW_MOUSE_BUTTON_MIDDLE) {
    panning_ = down;
  }
}

void WindowInput::onCursor(double x, double y) {
  const double dx = x - cursor_x_, dy = y - cursor_y_;
  cursor_x_ = x;
  cursor_y_ = y;
  if (dragging_pen_ && pens_) pens_->drag(float(dx), float(dy));
  if (orbiting_) control_.orbit(dx, dy);
  if (panning_ && window_) control_.pan(dx, dy, int(std::max(1u, window_->framebufferExtent().height)));
}

void WindowInput::onScroll(double, double dy) {
  if (!window_) return;
  GLFWwindow* w = window_->handle();
  auto held = [&](int a, int b) { return glfwGetKey(w, a) == GLFW_PRESS || glfwGetKey(w, b) == GLFW_PRESS; };
  const int mods = (held(GLFW_KEY_LEFT_CONTROL, GLFW_KEY_RIGHT_CONTROL) ? GLFW_MOD_CONTROL : 0) |
                   (held(GLFW_KEY_LEFT_ALT, GLFW_KEY_RIGHT_ALT) ? GLFW_MOD_ALT : 0) |
                   (held(GLFW_KEY_LEFT_SHIFT, GLFW_KEY_RIGHT_SHIFT) ? GLFW_MOD_SHIFT : 0);
  scroll(dy, mods);
}

void WindowInput::scroll(double dy, int mods) {
  if (panel_ && panel_->wantsMouse()) return;
  if (mods & GLFW_MOD_ALT) {
    control_.zoom(dy);
  } else if ((mods & GLFW_MOD_CONTROL) && pens_) {
    pens_->wheelPedal(float(dy));
    hooks_.turbine_speed(pens_->pedal());
  } else if (pens_) {
    pens_->setActive((mods & GLFW_MOD_SHIFT) ? PenRole::Mirror : PenRole::Drill);
    pens_->wheel(float(dy));
  }
}

void WindowInput::dragBy(double dx, double dy, int mods) {
  const double x = cursor_x_, y = cursor_y_;
  onMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_PRESS, mods);
  onCursor(x + dx, y + dy);
  onMouseButton(GLFW_MOUSE_BUTTON_LEFT, GLFW_RELEASE, mods);
}

std::vector<Vec3> WindowInput::toolPoints() const {
  if (!pens_) return {};
  const Pose mirror = pens_->target(PenRole::Mirror);
  return toolSightPoints(pens_->target(PenRole::Drill), mirror_diameter_mm_ > 0 ? &mirror : nullptr, mirror_diameter_mm_);
}

void WindowInput::onKey(int key, int action, int mods) {
  if (action == GLFW_RELEASE) return;
  if (panel_ && panel_->wantsKeyboard()) return;
  const Vec3 c = box_.centre();
  const float radius = float(0.5 * norm(box_.hi - box_.lo) * 1.25);
  const std::vector<Vec3> tools = toolPoints();
  auto view = [&](render::ViewPreset p) { control_.showPreset(p, c, radius, tools); };
  switch (key) {
    case GLFW_KEY_1: view(render::ViewPreset::Occlusal); break;
    case GLFW_KEY_2: view(render::ViewPreset::Buccal); break;
    case GLFW_KEY_3: view(render::ViewPreset::Lingual); break;
    case GLFW_KEY_4: view(render::ViewPreset::Mesial); break;
    case GLFW_KEY_5: view(render::ViewPreset::Distal); break;
    case GLFW_KEY_ESCAPE: hooks_.quit(); break;
    case GLFW_KEY_F1:
      if (action == GLFW_PRESS && hooks_.toggle_help) hooks_.toggle_help();
      return;
    default: break;
  }
  if (!pens_) return;
  if (key == GLFW_KEY_B) {
    // The drill only: the mirror hand has no target on the tooth.
    if (action == GLFW_PRESS && hooks_.bring_to_tooth) hooks_.bring_to_tooth();
    return;
  }
  const PenRole role = (mods & GLFW_MOD_SHIFT) ? PenRole::Mirror : PenRole::Drill;
  pens_->setActive(role);
  constexpr double kStep = 3.0 * std::numbers::pi / 180.0;
  switch (key) {
    case GLFW_KEY_PAGE_UP: pens_->setPedal(pens_->pedal() + 0.1); break;
    case GLFW_KEY_PAGE_DOWN: pens_->setPedal(pens_->pedal() - 0.1); break;
    case GLFW_KEY_SPACE: pens_->setPedal(pens_->pedal() > 0 ? 0.0 : 1.0); break;
    case GLFW_KEY_LEFT: pens_->rotate(-kStep, 0); break;
    case GLFW_KEY_RIGHT: pens_->rotate(kStep, 0); break;
    case GLFW_KEY_UP: pens_->rotate(0, kStep); break;
    case GLFW_KEY_DOWN: pens_->rotate(0, -kStep); break;
    case GLFW_KEY_W: pens_->alongTool(pens_->params().key_lift_mm); break;
    case GLFW_KEY_S: pens_->alongTool(-pens_->params().key_lift_mm); break;
    case GLFW_KEY_R:
      pens_->reset(PenRole::Drill, drillStartGrip(box_, 3.0));
      pens_->reset(PenRole::Mirror, mirrorGrip(box_, render::fromGlm(camera_.eye())));
      break;
    default: break;
  }
  hooks_.turbine_speed(pens_->pedal());
}

}  // namespace dentsim::app
