// What the simulator draws with: the window (or an offscreen image), the Vulkan device, the swapchain, the scene renderer, the tooth's surfaces and the panel's layer; one frame drawn and, when asked, read back.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "gpu/context.h"
#include "gpu/mesher_kind.h"
#include "io/png_file.h"
#include "render/camera.h"
#include "render/look_params.h"
#include "render/offscreen.h"
#include "render/scene_renderer.h"
#include "render/swapchain.h"
#include "render/tooth_surfaces.h"
#include "sim/haptic_loop.h"
#include "ui/imgui_layer.h"
#include "ui/window.h"
#include "volume/normal_mode.h"

namespace dentsim::app {

struct PainterOptions {
  bool headless = false;          // offscreen frames, no window
  int width = 1280, height = 800; // window or frame size [px]
  bool vsync = true;              // windowed: wait for the display's refresh
  std::string device;             // Vulkan device index or name part; empty: the best
  bool panel = true;              // the ImGui layer for the parameter window and the overlay
  NormalMode normals = NormalMode::Box216;  // the tooth surfaces' normal mode
  gpu::MesherKind mesher = gpu::MesherKind::Auto;  // who meshes them: the kernel, CPU threads, or what suits the device
};

// What a frame shows besides the camera: the tooth's frame and looks, and the tools.
struct SceneContents {
  VolumeFrame tooth_frame;
  std::array<TissueLook, DS_MATERIAL_COUNT> looks{};  // by Material
  std::string bur;                 // the drill's bur (a toolCatalog() name)
  bool mirror_tool = false;        // a mirror is in the scene
  double max_force_n = 8.0;        // the device's clamp: the bur is full red there [N]
};

// The scene as `run` and `replay` draw it at `extent`: the camera's view, its picture moved
// `shift_left_px` left and `shift_up_px` up (so the tooth sits in the middle of what a panel leaves
// free), a lamp above and behind the operator's shoulder, and the tools where the loop's `state`
// puts them.
render::FrameState sceneFrameState(const render::OrbitCamera& camera, VkExtent2D extent, float shift_left_px,
                                   float shift_up_px, const HapticState& state, const SceneContents& scene);

class FramePainter {
 public:
  // Opens the window (unless headless), the device, the swapchain or offscreen image, the renderer,
  // the surfaces and the panel's layer. `before_panel` runs with the window before the panel's
  // layer exists: the app's GLFW callbacks must go in first, the panel's chain to them.
  static Result<std::unique_ptr<FramePainter>> create(const PainterOptions& options,
                                                      const std::function<void(ui::Window&)>& before_panel);

  gpu::Context& context() { return *ctx_; }
  ui::Window* window() const { return window_.get(); }
  render::SceneRenderer& renderer() { return *renderer_; }
  render::ToothSurfaces& surfaces() { return *surfaces_; }
  ui::ImGuiLayer* panel() { return panel_ ? &*panel_ : nullptr; }
  bool windowed() const { return window_ != nullptr; }
  // The size frames are drawn at now: the window's framebuffer, or the offscreen image.
  VkExtent2D extent() const;

  // Re-meshes the bricks in *dirty (each once, however often it is listed) and empties it.
  Status remesh(const BrickVolume& voxels, std::vector<BrickCoord>* dirty, gpu::SurfaceUpdateStats* stats = nullptr);

  // Draws one frame: `state_for` gives the frame's state for the extent drawn at. With `read_back`
  // the picture comes back. A minimised window draws nothing and returns no picture; so does a
  // swapchain that had to be rebuilt.
  Result<std::optional<RgbImage>> draw(const std::function<render::FrameState(VkExtent2D)>& state_for, bool read_back);

 private:
  FramePainter() = default;
  // Destroyed in reverse: the panel, surfaces, renderer and targets, then the window, then the device.
  std::optional<gpu::Context> ctx_;
  std::unique_ptr<ui::Window> window_;
  std::unique_ptr<render::Swapchain> swapchain_;
  std::optional<render::OffscreenTarget> offscreen_;
  std::optional<render::SceneRenderer> renderer_;
  std::optional<render::ToothSurfaces> surfaces_;
  std::optional<ui::ImGuiLayer> panel_;
};

}  // namespace dentsim::app
