// ImGuiLayer: creates, drives and tears down the ImGui context and its GLFW and Vulkan backends.
#include "ui/imgui_layer.h"

#include <algorithm>
#include <cstdio>

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>

#include "gpu/compute.h"

namespace dentsim::ui {
namespace {

constexpr float kDefaultDt = 1.0f / 60.0f;        // [s], when the caller has no clock yet
constexpr uint32_t kPoolDescriptors = 8;          // the font needs one set; the rest is slack

// The backend reports Vulkan errors through a plain function pointer with no user data; the
// only useful thing it can do is say so.
void reportVkResult(VkResult r) {
  if (r != VK_SUCCESS) std::fprintf(stderr, "dentsim: imgui vulkan backend: VkResult %d\n", int(r));
}

}  // namespace

struct ImGuiLayer::State {
  std::shared_ptr<gpu::ContextCore> core;  // keeps the device alive for the pool and the backend
  ImGuiContext* imgui = nullptr;
  GLFWwindow* window = nullptr;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  bool glfw_ready = false;
  bool vulkan_ready = false;
  bool in_frame = false;
  // A scripted mouse for the next frame (app/scripted_input.h): where it is and whether its left
  // button is down, over whatever the backend polled.
  bool scripted = false;
  float scripted_x = 0, scripted_y = 0;
  bool scripted_down = false;

  State() = default;
  State(const State&) = delete;
  State& operator=(const State&) = delete;

  // Tears down in reverse order of creation; safe on a half-built state.
  ~State() {
    if (imgui) {
      ImGuiContext* previous = ImGui::GetCurrentContext();
      ImGui::SetCurrentContext(imgui);
      if (vulkan_ready) {
        vkDeviceWaitIdle(core->device);
        ImGui_ImplVulkan_Shutdown();
      }
      if (glfw_ready) ImGui_ImplGlfw_Shutdown();
      ImGui::DestroyContext(imgui);
      ImGui::SetCurrentContext(previous == imgui ? nullptr : previous);
    }
    if (pool != VK_NULL_HANDLE) vkDestroyDescriptorPool(core->device, pool, nullptr);
  }
};

ImGuiLayer::ImGuiLayer(std::unique_ptr<State> state) : s_(std::move(state)) {}
ImGuiLayer::ImGuiLayer(ImGuiLayer&&) noexcept = default;
ImGuiLayer& ImGuiLayer::operator=(ImGuiLayer&&) noexcept = default;
ImGuiLayer::~ImGuiLayer() = default;

Result<ImGuiLayer> ImGuiLayer::create(gpu::Context& ctx, VkRenderPass render_pass, uint32_t subpass,
                                      uint32_t image_count, GLFWwindow* window, VkSampleCountFlagBits samples) {
  assert(render_pass != VK_NULL_HANDLE);
  auto s = std::make_unique<State>();
  s->core = ctx.sharedCore();
  s->window = window;

  // The context, set up for reproducible frames.
  ImGuiContext* previous = ImGui::GetCurrentContext();
  s->imgui = ImGui::CreateContext();
  ImGui::SetCurrentContext(s->imgui);
  ImGuiIO& io = ImGui::GetIO();
  io.IniFilename = nullptr;
  io.LogFilename = nullptr;
  io.ConfigInputTextCursorBlink = false;
  ImGui::StyleColorsDark();

  if (window) {
    if (!ImGui_ImplGlfw_InitForVulkan(window, true)) {
      ImGui::SetCurrentContext(previous);
      return Error{"imgui: the GLFW backend failed to initialise"};
    }
    s->glfw_ready = true;
  }

  // The descriptor pool the backend takes its font set from.
  const VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, kPoolDescriptors};
  VkDescriptorPoolCreateInfo pool_info{};
  pool_info.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  pool_info.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
  pool_info.maxSets = kPoolDescriptors;
  pool_info.poolSizeCount = 1;
  pool_info.pPoolSizes = &size;
  if (VkResult r = vkCreateDescriptorPool(s->core->device, &pool_info, nullptr, &s->pool); r != VK_SUCCESS) {
    ImGui::SetCurrentContext(previous);
    return Error{"imgui: vkCreateDescriptorPool failed (VkResult " + std::to_string(int(r)) + ")"};
  }
  s->core->name(VK_OBJECT_TYPE_DESCRIPTOR_POOL, s->pool, "imgui descriptors");

  ImGui_ImplVulkan_InitInfo info{};
  info.Instance = s->core->instance;
  info.PhysicalDevice = s->core->physical;
  info.Device = s->core->device;
  info.QueueFamily = s->core->queue_family;
  info.Queue = s->core->queue;
  info.PipelineCache = VK_NULL_HANDLE;
  info.DescriptorPool = s->pool;
  info.Subpass = subpass;
  info.MinImageCount = std::max(2u, image_count);
  info.ImageCount = info.MinImageCount;
  info.MSAASamples = samples;
  info.Allocator = nullptr;
  info.CheckVkResultFn = reportVkResult;
  if (!ImGui_ImplVulkan_Init(&info, render_pass)) {
    ImGui::SetCurrentContext(previous);
    return Error{"imgui: the Vulkan backend failed to initialise"};
  }
  s->vulkan_ready = true;

  // The font atlas: one upload submission, then the staging buffer goes.
  Status uploaded = gpu::submitAndWait(ctx, "imgui font upload", [](gpu::Commands& c) -> Status {
    if (!ImGui_ImplVulkan_CreateFontsTexture(c.cmd())) return Error{"imgui: font texture creation failed"};
    return Ok{};
  });
  ImGui_ImplVulkan_DestroyFontUploadObjects();
  if (!uploaded) {
    ImGui::SetCurrentContext(previous);
    return Error{uploaded.message()};
  }
  return ImGuiLayer(std::move(s));
}

void ImGuiLayer::newFrame(int width, int height, double dt_s) {
  assert(s_ && !s_->in_frame && width >= 0 && height >= 0);
  ImGui::SetCurrentContext(s_->imgui);
  ImGuiIO& io = ImGui::GetIO();
  ImGui_ImplVulkan_NewFrame();
  if (s_->window) {
    // The backend polls the mouse in window coordinates; ImGui here works in framebuffer pixels,
    // the renderer's units, so that a HiDPI window and a headless frame lay out alike.
    ImGui_ImplGlfw_NewFrame();
    int ww = 0, wh = 0;
    glfwGetWindowSize(s_->window, &ww, &wh);
    if (ww > 0 && wh > 0 && ImGui::IsMousePosValid(&io.MousePos)) {
      io.MousePos.x *= float(width) / float(ww);
      io.MousePos.y *= float(height) / float(wh);
    }
  }
  if (s_->scripted) {
    io.MousePos = ImVec2(s_->scripted_x, s_->scripted_y);
    io.MouseDown[0] = s_->scripted_down;
    s_->scripted = false;
  }
  io.DisplaySize = ImVec2(float(width), float(height));
  io.DisplayFramebufferScale = ImVec2(1.0f, 1.0f);
  io.DeltaTime = dt_s > 0.0 ? float(dt_s) : kDefaultDt;
  ImGui::NewFrame();
  s_->in_frame = true;
}

void ImGuiLayer::render(VkCommandBuffer cmd) {
  assert(s_ && s_->in_frame && cmd != VK_NULL_HANDLE);
  ImGui::SetCurrentContext(s_->imgui);
  ImGui::Render();
  ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
  s_->in_frame = false;
}

void ImGuiLayer::scriptMouse(float x, float y, bool left_down) {
  s_->scripted = true;
  s_->scripted_x = x;
  s_->scripted_y = y;
  s_->scripted_down = left_down;
}

void ImGuiLayer::discardFrame() {
  assert(s_ && s_->in_frame);
  ImGui::SetCurrentContext(s_->imgui);
  ImGui::EndFrame();
  s_->in_frame = false;
}

bool ImGuiLayer::wantsMouse() const {
  ImGui::SetCurrentContext(s_->imgui);
  return ImGui::GetIO().WantCaptureMouse;
}

bool ImGuiLayer::wantsKeyboard() const {
  ImGui::SetCurrentContext(s_->imgui);
  return ImGui::GetIO().WantCaptureKeyboard;
}

ImGuiContext* ImGuiLayer::context() const { return s_->imgui; }

}  // namespace dentsim::ui
