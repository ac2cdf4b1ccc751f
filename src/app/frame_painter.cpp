// Window, device and targets of the simulator's frames, and drawing one.
#include "app/frame_painter.h"

#include <algorithm>
#include <tuple>

#include <glm/gtc/matrix_transform.hpp>

#include "gpu/compute.h"

namespace dentsim::app {

render::FrameState sceneFrameState(const render::OrbitCamera& camera, VkExtent2D extent, float shift_left_px,
                                   float shift_up_px, const HapticState& state, const SceneContents& scene) {
  render::FrameState fs;
  const float width = float(std::max(1u, extent.width)), height = float(std::max(1u, extent.height));
  fs.view = camera.view();
  // Vulkan's clip space runs right and down: left and up are negative.
  const glm::vec3 shift_ndc(-shift_left_px * 2.0f / width, -shift_up_px * 2.0f / height, 0.0f);
  fs.projection = glm::translate(glm::mat4(1.0f), shift_ndc) * camera.projection(width / height);
  fs.eye = camera.eye();
  // A lamp above and behind the operator's shoulder: from the eye, raised toward +z.
  const render::CameraBasis b = camera.basis();
  fs.light_dir = glm::normalize(-b.forward + 0.6f * b.up + 0.25f * b.right);
  fs.tooth_frame = scene.tooth_frame;
  fs.looks = scene.looks;
  const ToolState& drill = state.tools[size_t(PenRole::Drill)];
  const ToolState& mirror = state.tools[size_t(PenRole::Mirror)];
  fs.drill_shown = drill.present;
  fs.drill = drill.tool;
  fs.bur = scene.bur;
  fs.drill_force_n = norm(drill.display.force);
  fs.max_force_n = scene.max_force_n;
  fs.mirror_shown = scene.mirror_tool && mirror.present;
  fs.mirror = mirror.tool;
  return fs;
}

Result<std::unique_ptr<FramePainter>> FramePainter::create(const PainterOptions& o,
                                                           const std::function<void(ui::Window&)>& before_panel) {
  std::unique_ptr<FramePainter> p(new FramePainter());
  gpu::ContextOptions co;
  co.graphics = true;
  co.device_override = o.device;
  if (!o.headless) {
    auto w = ui::Window::open(o.width, o.height, "dentsim");
    if (!w) return w.error();
    p->window_ = std::move(*w);
    co.instance_extensions = ui::Window::requiredInstanceExtensions();
  }
  auto ctx = gpu::Context::create(gpu::withEnvironment(co));
  if (!ctx) return ctx.error();
  p->ctx_ = std::move(*ctx);
  VkFormat format = VK_FORMAT_B8G8R8A8_UNORM;
  VkImageLayout final_layout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  uint32_t image_count = 2;
  if (p->window_) {
    auto surface = p->window_->createSurface(p->ctx_->core().instance);
    if (!surface) return surface.error();
    render::SwapchainOptions so;
    so.vsync = o.vsync;
    auto sc = render::Swapchain::create(*p->ctx_, *surface, p->window_->framebufferExtent(), so);
    if (!sc) return sc.error();
    p->swapchain_ = std::move(*sc);
    format = p->swapchain_->format();
    final_layout = VK_IMAGE_LAYOUT_PRESENT_SRC_KHR;
    image_count = p->swapchain_->imageCount();
  } else {
    auto target = render::OffscreenTarget::create(*p->ctx_, uint32_t(o.width), uint32_t(o.height), format);
    if (!target) return target.error();
    p->offscreen_ = std::move(*target);
  }
  auto renderer = render::SceneRenderer::create(*p->ctx_, format, final_layout);
  if (!renderer) return renderer.error();
  p->renderer_ = std::move(*renderer);
  auto surfaces = render::ToothSurfaces::create(*p->ctx_, o.normals, render::kDefaultCoarseCopies, o.mesher);
  if (!surfaces) return surfaces.error();
  p->surfaces_ = std::move(*surfaces);
  if (p->window_ && before_panel) before_panel(*p->window_);
  if (o.panel) {
    auto layer = ui::ImGuiLayer::create(*p->ctx_, p->renderer_->renderPass(), 0, image_count,
                                        p->window_ ? p->window_->handle() : nullptr);
    if (!layer) return layer.error();
    p->panel_ = std::move(*layer);
  }
  return p;
}

VkExtent2D FramePainter::extent() const {
  return window_ ? window_->framebufferExtent() : offscreen_->image().extent;
}

Status FramePainter::remesh(const BrickVolume& voxels, std::vector<BrickCoord>* dirty, gpu::SurfaceUpdateStats* stats) {
  if (dirty->empty()) return Ok{};
  // Frames skipped headless leave the same brick listed by several drains.
  auto key = [](const BrickCoord& b) { return std::tuple(b.z, b.y, b.x); };
  std::sort(dirty->begin(), dirty->end(), [&](const BrickCoord& a, const BrickCoord& b) { return key(a) < key(b); });
  dirty->erase(std::unique(dirty->begin(), dirty->end(), [&](const BrickCoord& a, const BrickCoord& b) { return key(a) == key(b); }),
               dirty->end());
  Status st = surfaces_->update(voxels, *dirty, stats);
  dirty->clear();
  return st;
}

Result<std::optional<RgbImage>> FramePainter::draw(const std::function<render::FrameState(VkExtent2D)>& state_for,
                                                   bool read_back) {
  VkExtent2D extent;
  render::RenderImage target;
  uint32_t index = 0;
  if (swapchain_) {
    VkExtent2D fb = window_->framebufferExtent();
    if (fb.width == 0 || fb.height == 0) {  // minimised: nothing to draw
      if (panel_) panel_->discardFrame();
      ui::Window::waitEvents(0.05);
      return std::optional<RgbImage>{};
    }
    if (fb.width != swapchain_->extent().width || fb.height != swapchain_->extent().height) {
      renderer_->forgetTargets();
      if (Status st = swapchain_->recreate(fb); !st) return st.error();
    }
    auto ok = swapchain_->acquire(&index);
    if (!ok) return ok.error();
    if (!*ok) {
      renderer_->forgetTargets();
      if (panel_) panel_->discardFrame();
      if (Status st = swapchain_->recreate(window_->framebufferExtent()); !st) return st.error();
      return std::optional<RgbImage>{};
    }
    extent = swapchain_->extent();
    target = render::RenderImage{swapchain_->image(index), swapchain_->view(index), swapchain_->format(), extent};
  } else {
    target = offscreen_->image();
    extent = target.extent;
  }
  const render::FrameState fs = state_for(extent);
  Status recorded = Ok{};
  Status submitted = gpu::submitAndWait(*ctx_, "frame", [&](gpu::Commands& cmds) -> Status {
    recorded = renderer_->recordFrame(cmds.cmd(), target, *surfaces_, fs, [&](VkCommandBuffer cb) {
      if (panel_) panel_->render(cb);
    });
    renderer_->markSubmitted(cmds.serial());
    return recorded;
  });
  if (!submitted) return submitted.error();
  std::optional<RgbImage> picture;
  if (read_back) {
    const VkImageLayout layout = swapchain_ ? VK_IMAGE_LAYOUT_PRESENT_SRC_KHR : VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    auto image = render::readImage(*ctx_, target, layout);
    if (!image) return image.error();
    picture = std::move(*image);
  }
  if (swapchain_) {
    auto presented = swapchain_->present(index);
    if (!presented) return presented.error();
    if (!*presented) {
      renderer_->forgetTargets();
      if (Status st = swapchain_->recreate(window_->framebufferExtent()); !st) return st.error();
    }
  }
  return picture;
}

}  // namespace dentsim::app
