// SceneRenderer: draws the tooth's tissue surfaces, the drill and the dental mirror (with its reflection pass) into a caller's colour image.
//
// Contents
//   1. RenderImage, FrameState and options: what a frame is drawn into and from
//   2. SceneRenderer: creation, the frame's recording, the overlay picture, cached targets
//
// Frames. The world is the tooth frame in mm (see camera.h). FrameState carries glm matrices in
// Vulkan clip space (y down, depth 0..1), so camera.h's OrbitCamera feeds it directly.
//
// One frame records, in the caller's command buffer:
//   1. the mirror pass (when the mirror is shown, on the target and its face turned to the eye): the
//      scene seen from the eye reflected in the mirror's plane, with everything behind the glass
//      discarded, into the renderer's own image: only the glass's rectangle on the target, pixel for
//      pixel (mirrorRect), so that the reflection is exactly as sharp as the main view;
//   2. the main pass into the target: opaque tissues and the tools (depth written), the mirror's
//      face (the mirror image, projectively mapped), the translucent tissues (blended, depth
//      tested, not written, back faces culled), the ghost tools (see below), the overlay picture,
//      then the caller's in-pass callback (the parameter window).
// The ghost tools come after all of the scene, in both passes: first their depth alone (so that
// where the handpiece covers the bur's shank only the nearest surface shows), then their colour,
// blended, where that depth is nearest. Nothing of the scene is drawn after them, so their depth
// hides nothing; the overlay and the panel do not test depth.
// The render pass is the same for a swapchain image and an offscreen image except its final
// layout, so headless frames equal windowed ones for the same state and colour format.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <glm/glm.hpp>
#include <vulkan/vulkan.h>

#include "core/pixel_rect.h"
#include "core/result.h"
#include "core/rigid.h"
#include "core/volume_frame.h"
#include "gpu/context.h"
#include "io/png_file.h"
#include "model/tool_generator.h"
#include "render/tooth_lod.h"
#include "render/tooth_surfaces.h"
#include "render/look_params.h"

namespace dentsim::render {

// ---- 1. what a frame is drawn into and from ----------------------------------------------------------

// A colour image the caller owns (a swapchain image or an OffscreenTarget). It needs
// COLOR_ATTACHMENT usage, and TRANSFER_SRC for read-back.
struct RenderImage {
  VkImage image = VK_NULL_HANDLE;
  VkImageView view = VK_NULL_HANDLE;
  VkFormat format = VK_FORMAT_UNDEFINED;
  VkExtent2D extent{0, 0};  // [px]
};


// Everything one frame shows; the app fills it from the camera, the haptic state and SimParams.
struct FrameState {
  glm::mat4 view{1.0f};                              // world [mm] to eye
  glm::mat4 projection{1.0f};                        // eye to Vulkan clip space
  glm::vec3 eye{0.0f, 0.0f, 100.0f};                 // eye position [mm] (specular highlights, the mirror)
  glm::vec3 light_dir{0.0f, 0.0f, 1.0f};             // direction toward the light (normalized here)
  std::array<float, 3> background{0.08f, 0.09f, 0.11f};  // clear colour, linear [0..1]
  // The main pass keeps only points x with dot(clip_plane, (x, 1)) >= 0 (a cut-away view; the
  // default keeps everything). The mirror pass clips at the mirror's plane instead.
  glm::vec4 clip_plane{0.0f, 0.0f, 0.0f, 1.0f};

  bool tooth_shown = true;
  VolumeFrame tooth_frame;                           // voxel units to mm
  std::array<TissueLook, DS_MATERIAL_COUNT> looks{}; // by Material (LookParams::looks)

  bool drill_shown = true;
  Pose drill;                                        // the bur's tool frame (ToolState::tool) [mm]
  std::string bur = kDefaultBur;                     // a toolCatalog() bur name
  bool handpiece_shown = true;                       // the turbine, sharing the bur's frame
  double drill_force_n = 0.0;                        // contact force magnitude on the drill [N]
  double max_force_n = 8.0;                          // the device's force clamp [N]; full red there

  bool mirror_shown = false;
  Pose mirror;                                       // the mirror's tool frame: face z = 0, normal +Z [mm]

  // The professional's ghost: another session's tools, drawn translucent in options.ghost's tint
  // after everything opaque, so that they never hide the student's own tools or the tooth.
  bool ghost_drill_shown = false;
  Pose ghost_drill;                                  // the ghost bur's tool frame [mm]
  std::string ghost_bur = kDefaultBur;               // a toolCatalog() bur name
  bool ghost_handpiece_shown = true;                 // the ghost's turbine, sharing its bur's frame
  bool ghost_mirror_shown = false;
  Pose ghost_mirror;                                 // the ghost mirror's tool frame [mm]
  float ghost_opacity = 0.4f;                        // [0..1]

  bool overlay_shown = false;                        // draws the setOverlayImage picture into overlay_rect
  PixelRect overlay_rect;

  // Screen-sized detail (render/tooth_lod.h): each pass draws each region of the tooth from the
  // coarsest copy within lod.pixel_error pixels. pixel_error 0 draws the full copy everywhere,
  // frustum and all: the full-detail path benchmarks compare against.
  LodSettings lod;
};

// What the last recorded frame drew of the tooth.
struct ToothDrawStats {
  uint64_t main_triangles = 0;    // tooth triangles of the main pass (every tissue)
  uint64_t mirror_triangles = 0;  // of the mirror pass (0 when it did not run)
  std::array<uint32_t, 4> main_regions{};  // regions of the main pass drawn from copy k (k < 4)
};

struct SceneRendererOptions {
  // The mirror pass's image. 0: the glass's rectangle on the target, one texel a target pixel (a
  // swapchain's pixels are the window's times the device pixel ratio, so it follows that too), with the
  // main pass's sample count (the two passes share their pipelines, so they cannot differ). N > 0: the
  // old way, a fixed N x N image of the whole view, resampled onto the glass (stair-stepped where it
  // is magnified); kept so that `bench frames` can set the two side by side.
  uint32_t mirror_resolution = 0;  // [px]
  // Steel of the bur and the handpiece, and the mirror's slightly blue rim (Phong, opaque).
  TissueLook steel{0.10, 0.10, 0.11, 0.50, 0.51, 0.53, 0.60, 0.60, 0.60, 1.0, 40.0};
  TissueLook mirror_rim{0.09, 0.10, 0.12, 0.44, 0.48, 0.56, 0.50, 0.50, 0.55, 1.0, 32.0};
  // The bur's diffuse colour at the device's maximum force; it blends from steel toward this.
  std::array<float, 3> hot_diffuse{0.90f, 0.10f, 0.06f};
  std::array<float, 3> mirror_tint{0.92f, 0.93f, 0.95f};  // the glass's reflectance per channel [0..1]
  // The ghost's pale blue: no tissue or steel is blue, so it reads as "not a real tool" at a glance
  // (its opacity is FrameState::ghost_opacity, not this alpha).
  TissueLook ghost{0.22, 0.32, 0.48, 0.40, 0.58, 0.85, 0.35, 0.38, 0.45, 1.0, 24.0};
};

// ---- 2. the renderer ---------------------------------------------------------------------------------

class SceneRenderer {
 public:
  // Render pass (colour `colour_format` ending in `final_layout`: PRESENT_SRC_KHR for a swapchain,
  // TRANSFER_SRC_OPTIMAL offscreen; depth D32 or the best the device has), pipelines, the mirror
  // image and every built-in tool mesh. The context must have been made with graphics = true.
  // Errors: no depth format, a Vulkan failure, missing tool assets.
  static Result<SceneRenderer> create(gpu::Context& ctx, VkFormat colour_format, VkImageLayout final_layout,
                                      const SceneRendererOptions& options = {});

  // Subpass 0 of this pass is where the in-pass callback (and Dear ImGui's pipeline) draws.
  VkRenderPass renderPass() const;
  VkFormat colourFormat() const;
  VkImageLayout finalLayout() const;

  // Records the mirror pass and the main pass into `cmd` (recording, outside a render pass). The
  // target's format must be colourFormat(). `in_pass` (may be empty) records last inside the main
  // pass. The tooth is skipped until `tooth` is built. Errors: an unknown bur, a target of another
  // format, a Vulkan failure making the target's depth buffer and framebuffer.
  Status recordFrame(VkCommandBuffer cmd, const RenderImage& target, const ToothSurfaces& tooth,
                     const FrameState& frame, const std::function<void(VkCommandBuffer)>& in_pass = {});

  // What the last recordFrame drew of the tooth.
  ToothDrawStats toothDrawStats() const;

  // Uploads the overlay picture (e.g. the score's over/under-cut image). Waits for the device to be
  // idle first, as a frame in flight may still sample the old one. Error: an empty image.
  Status setOverlayImage(const RgbImage& image);

  // The mirror pass's colour image (colourFormat()); after a frame whose mirrorDrawn() is true its
  // top-left mirrorRect().width x height texels hold that pass, in SHADER_READ_ONLY_OPTIMAL. It grows to
  // the largest target drawn (never shrinks); growing waits for the device to be idle, as frames in
  // flight may still sample it. Empty before the first mirror pass.
  RenderImage mirrorImage() const;
  bool mirrorDrawn() const;  // the last recorded frame ran the mirror pass
  // The part of the last target the mirror pass drew, texel (i, j) of mirrorImage() being pixel
  // (x + i, y + j) of the target [px]; with a fixed mirror_resolution, the whole target (resampled).
  PixelRect mirrorRect() const;

  // The renderer keeps a depth buffer and framebuffer per target view. Forget one before its image
  // is destroyed, or all of them when the swapchain is recreated, once the device is idle.
  void forgetTarget(VkImageView view);
  void forgetTargets();

  // Records that submission `serial` ran frames of this renderer, so that its handles outlive it.
  void markSubmitted(uint64_t serial);

  SceneRenderer(SceneRenderer&&) noexcept;
  SceneRenderer& operator=(SceneRenderer&&) noexcept;
  SceneRenderer(const SceneRenderer&) = delete;
  SceneRenderer& operator=(const SceneRenderer&) = delete;
  ~SceneRenderer();

  struct State;

 private:
  explicit SceneRenderer(std::unique_ptr<State> state);
  std::unique_ptr<State> state_;
};

// The projection that draws only `rect` of a frame `target` pixels large that `projection` draws,
// onto an image rect.width x rect.height large: pixel (i, j) of it is pixel (rect.x + i, rect.y + j)
// of the frame. Depth is unchanged. Precondition: rect is not empty.
glm::mat4 cropProjection(const glm::mat4& projection, const PixelRect& rect, VkExtent2D target);

// The colour a Phong look gives a surface point: ambient + diffuse (N.L) + specular (R.V)^shininess
// with one white light of intensity 1, each channel clamped to [0,1]; `normal`, `to_light` and
// `to_eye` are unit vectors. The shaders evaluate the same formula.
glm::vec3 phongColour(const TissueLook& look, const glm::vec3& normal, const glm::vec3& to_light,
                      const glm::vec3& to_eye);

// The bur's look under `force_n` of `max_force_n`: steel whose diffuse colour blends toward
// options.hot_diffuse by force / max (clamped to [0,1]).
TissueLook burLook(const SceneRendererOptions& options, double force_n, double max_force_n);

}  // namespace dentsim::render
