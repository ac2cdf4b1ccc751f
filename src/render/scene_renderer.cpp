// SceneRenderer: render passes, pipelines, tool meshes, the mirror pass and the frame's recording.
//
// Contents
//   1. Small helpers: Vulkan errors, matrices to layout structs, looks to push constants
//   2. State: every handle the renderer owns, and their release
//   3. Creation: render passes, descriptor sets, pipelines, tool meshes, the mirror image (and its growth)
//   4. Targets: a depth buffer and framebuffer per colour view
//   5. Recording: frame uniforms, the mirror pass, the main pass
#include "render/scene_renderer.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "dentsim_render_spirv_spirv.h"
#include "gpu/buffer.h"
#include "gpu/compute.h"
#include "gpu/vk_check.h"
#include "model/builtin_assets.h"
#include "model/tool_generator.h"
#include "render/camera.h"
#include "render/gpu_image.h"
#include "render/render_layout.h"
#include "render/tool_mesh.h"
#include "volume/surface_layout.h"

namespace dentsim::render {

// ==== 1. helpers =====================================================================================
namespace {

constexpr const char* kWhere = "render";
constexpr double kGlassLiftMm = 0.02;         // the glass disc sits this far in front of the face [mm]
constexpr int kGlassSegments = 96;
constexpr const char* kHandpieceName = "turbine_handpiece";
constexpr const char* kMirrorName = kDefaultMirror;

layout::vec4 toVec4(const glm::vec4& v) { return {v.x, v.y, v.z, v.w}; }

void putMatrix(layout::vec4 (&out)[4], const glm::mat4& m) {
  for (int c = 0; c < 4; ++c) out[c] = toVec4(m[c]);
}

void putLook(layout::DrawConstants& dc, const TissueLook& look) {
  dc.ambient = {float(look.ambient_r), float(look.ambient_g), float(look.ambient_b), float(look.alpha)};
  dc.diffuse = {float(look.diffuse_r), float(look.diffuse_g), float(look.diffuse_b), 0.0f};
  dc.specular = {float(look.specular_r), float(look.specular_g), float(look.specular_b), float(look.shininess)};
}

// Mirrored views (determinant < 0) wind every triangle the other way.
bool mirrored(const glm::mat4& view) { return glm::determinant(glm::mat3(view)) < 0.0f; }

uint64_t roundUp(uint64_t v, uint64_t a) { return a ? (v + a - 1) / a * a : v; }

}  // namespace

glm::vec3 phongColour(const TissueLook& look, const glm::vec3& normal, const glm::vec3& to_light,
                      const glm::vec3& to_eye) {
  const float nl = std::max(glm::dot(normal, to_light), 0.0f);
  const glm::vec3 r = glm::reflect(-to_light, normal);
  const float rv = std::max(glm::dot(r, to_eye), 0.0f);
  const float spec = nl > 0.0f ? std::pow(rv, float(look.shininess)) : 0.0f;
  const glm::vec3 c = glm::vec3(float(look.ambient_r), float(look.ambient_g), float(look.ambient_b)) +
                      glm::vec3(float(look.diffuse_r), float(look.diffuse_g), float(look.diffuse_b)) * nl +
                      glm::vec3(float(look.specular_r), float(look.specular_g), float(look.specular_b)) * spec;
  return glm::clamp(c, glm::vec3(0.0f), glm::vec3(1.0f));
}

TissueLook burLook(const SceneRendererOptions& options, double force_n, double max_force_n) {
  TissueLook look = options.steel;
  const double t = max_force_n > 0.0 ? std::clamp(force_n / max_force_n, 0.0, 1.0) : 0.0;
  look.diffuse_r += t * (double(options.hot_diffuse[0]) - look.diffuse_r);
  look.diffuse_g += t * (double(options.hot_diffuse[1]) - look.diffuse_g);
  look.diffuse_b += t * (double(options.hot_diffuse[2]) - look.diffuse_b);
  return look;
}

// ==== 2. state =======================================================================================

// One uploaded tool mesh: three ToolVertex per triangle.
struct ToolMesh {
  std::optional<gpu::Buffer> vertices;
  uint32_t count = 0;  // vertices
};

// A colour view's depth buffer and framebuffer.
struct Target {
  std::optional<GpuImage> depth;
  VkFramebuffer framebuffer = VK_NULL_HANDLE;
  VkExtent2D extent{0, 0};
  VkImage image = VK_NULL_HANDLE;
};

// Pipelines by what they draw; [mirrored] picks the front face.
struct Pipelines {
  std::array<VkPipeline, 2> tooth_opaque{};
  std::array<VkPipeline, 2> tooth_blend{};
  std::array<VkPipeline, 2> tooth_blend_depth{};  // the translucent tissues' depth alone, before their colour
  std::array<VkPipeline, 2> tool{};
  std::array<VkPipeline, 2> glass{};
  std::array<VkPipeline, 2> ghost_depth{};  // the ghost tools' depth only, no colour
  std::array<VkPipeline, 2> ghost{};        // the ghost tools' colour, blended where their depth is nearest
  VkPipeline overlay = VK_NULL_HANDLE;
};

struct SceneRenderer::State {
  gpu::Context* ctx = nullptr;
  std::shared_ptr<gpu::ContextCore> core;
  SceneRendererOptions options;
  VkFormat colour_format = VK_FORMAT_UNDEFINED;
  VkFormat depth_format = VK_FORMAT_UNDEFINED;
  VkImageLayout final_layout = VK_IMAGE_LAYOUT_UNDEFINED;

  VkRenderPass main_pass = VK_NULL_HANDLE;
  VkRenderPass mirror_pass = VK_NULL_HANDLE;
  VkDescriptorSetLayout frame_set_layout = VK_NULL_HANDLE;
  VkDescriptorSetLayout texture_set_layout = VK_NULL_HANDLE;
  VkPipelineLayout pipeline_layout = VK_NULL_HANDLE;
  std::vector<VkShaderModule> modules;
  Pipelines pipes;
  VkSampler sampler = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkDescriptorSet main_frame_set = VK_NULL_HANDLE, mirror_frame_set = VK_NULL_HANDLE;
  VkDescriptorSet mirror_texture_set = VK_NULL_HANDLE, overlay_texture_set = VK_NULL_HANDLE;

  std::optional<gpu::Buffer> uniforms;  // two FrameUniforms: main pass at 0, mirror pass at mirror_offset
  uint64_t mirror_offset = 0;           // [B]

  std::map<std::string, ToolMesh> tools;  // by catalog name
  ToolMesh glass;

  std::optional<GpuImage> mirror_colour, mirror_depth;  // the capacity; a pass draws their top-left mirror_rect
  VkFramebuffer mirror_framebuffer = VK_NULL_HANDLE;
  bool mirror_drawn = false;
  PixelRect mirror_rect;                      // the target's pixels the last mirror pass drew [px]
  std::vector<glm::vec3> glass_corners;       // the glass disc's rim, tool frame [mm]: its rectangle on screen

  std::optional<GpuImage> overlay;
  ToothDrawStats tooth_stats;

  std::map<VkImageView, Target> targets;
  uint64_t last_serial = 0;

  ~State();
  void retireTarget(Target& t);

  Status createPasses();
  Status createLayouts();
  Result<VkPipeline> createPipeline(const char* name, std::span<const uint32_t> vert, std::span<const uint32_t> frag,
                                    int vertex_kind, bool blend, bool depth_write, bool depth_test, bool cull,
                                    bool flip, bool colour_write = true, bool yield_depth = false);
  Status createPipelines();
  Status createTools();
  Status createMirrorTarget(VkExtent2D extent);
  Status growMirrorTarget(VkExtent2D needed);
  PixelRect glassRect(const FrameState& frame, VkExtent2D target) const;
  Result<Target*> target(const RenderImage& image);

  // Draws the opaque or the translucent tissues; with a choice, each copy's blocks where it says.
  void drawTooth(VkCommandBuffer cmd, const ToothSurfaces& tooth, const FrameState& frame, bool translucent, bool flip,
                 const LodChoice* choice, uint64_t& triangles);
  void drawTool(VkCommandBuffer cmd, const ToolMesh& mesh, VkPipeline pipe, const glm::mat4& model, const TissueLook& look);
  void drawTools(VkCommandBuffer cmd, const FrameState& frame, bool with_mirror, bool flip);
  void drawGhost(VkCommandBuffer cmd, const FrameState& frame, bool with_mirror, bool flip);
};

SceneRenderer::State::~State() {
  if (!core) return;
  for (auto& [view, t] : targets) retireTarget(t);
  targets.clear();
  // Pipelines, passes and sets may still be in a submission up to last_serial.
  VkDevice device = core->device;
  std::vector<VkPipeline> pipelines;
  for (auto* arr : {&pipes.tooth_opaque, &pipes.tooth_blend, &pipes.tooth_blend_depth, &pipes.tool, &pipes.glass, &pipes.ghost_depth, &pipes.ghost})
    for (VkPipeline p : *arr) pipelines.push_back(p);
  pipelines.push_back(pipes.overlay);
  core->retired.retire(last_serial, [=, modules = modules, passes = std::array{main_pass, mirror_pass},
                                     fb = mirror_framebuffer, layouts = std::array{frame_set_layout, texture_set_layout},
                                     layout = pipeline_layout, smp = sampler, dp = pool] {
    for (VkPipeline p : pipelines)
      if (p) vkDestroyPipeline(device, p, nullptr);
    for (VkShaderModule m : modules) vkDestroyShaderModule(device, m, nullptr);
    if (fb) vkDestroyFramebuffer(device, fb, nullptr);
    for (VkRenderPass p : passes)
      if (p) vkDestroyRenderPass(device, p, nullptr);
    if (layout) vkDestroyPipelineLayout(device, layout, nullptr);
    for (VkDescriptorSetLayout l : layouts)
      if (l) vkDestroyDescriptorSetLayout(device, l, nullptr);
    if (smp) vkDestroySampler(device, smp, nullptr);
    if (dp) vkDestroyDescriptorPool(device, dp, nullptr);  // frees its sets
  });
  // Buffers and images retire themselves at the serial they were last marked with.
  for (auto& [name, mesh] : tools)
    if (mesh.vertices) mesh.vertices->markUsed(last_serial);
  if (glass.vertices) glass.vertices->markUsed(last_serial);
  if (uniforms) uniforms->markUsed(last_serial);
  for (auto* img : {&mirror_colour, &mirror_depth, &overlay})
    if (*img) (*img)->markUsed(last_serial);
}

void SceneRenderer::State::retireTarget(Target& t) {
  if (t.depth) t.depth->markUsed(last_serial);
  if (t.framebuffer) {
    VkDevice device = core->device;
    VkFramebuffer fb = t.framebuffer;
    core->retired.retire(last_serial, [device, fb] { vkDestroyFramebuffer(device, fb, nullptr); });
  }
  t.framebuffer = VK_NULL_HANDLE;
  t.depth.reset();
}

// ==== 3. creation ====================================================================================

Status SceneRenderer::State::createPasses() {
  // Both passes: colour cleared and stored, depth cleared and dropped. Only the colour's final
  // layout differs between a swapchain and an offscreen target, so their frames are the same.
  // The dependencies cover both passes' readers (sampling, copies), as passes must match in them for
  // the pipelines to serve both.
  const VkPipelineStageFlags after_stages = VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT;
  const VkAccessFlags after_access = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_TRANSFER_READ_BIT;
  const auto make = [&](VkImageLayout colour_final, const char* name, VkRenderPass& out) -> Status {
    VkAttachmentDescription att[2]{};
    att[0].format = colour_format;
    att[0].samples = VK_SAMPLE_COUNT_1_BIT;
    att[0].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    att[0].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att[0].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att[0].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[0].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    att[0].finalLayout = colour_final;
    att[1] = att[0];
    att[1].format = depth_format;
    att[1].storeOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[1].finalLayout = VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
    VkAttachmentReference colour_ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkAttachmentReference depth_ref{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &colour_ref;
    sub.pDepthStencilAttachment = &depth_ref;
    // Before: the last frame's use of the same images (reads by transfer or sampling, depth writes).
    // After: whoever reads the colour next.
    const VkPipelineStageFlags attachment_stages = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                                   VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                                   VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
    VkSubpassDependency deps[2]{};
    deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
    deps[0].dstSubpass = 0;
    deps[0].srcStageMask = attachment_stages | after_stages;
    deps[0].srcAccessMask = VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    deps[0].dstStageMask = attachment_stages;
    deps[0].dstAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_COLOR_ATTACHMENT_READ_BIT |
                            VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
    deps[1].srcSubpass = 0;
    deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
    deps[1].srcStageMask = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT;
    deps[1].srcAccessMask = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT;
    deps[1].dstStageMask = after_stages;
    deps[1].dstAccessMask = after_access;
    VkRenderPassCreateInfo rpci{};
    rpci.sType = VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO;
    rpci.attachmentCount = 2;
    rpci.pAttachments = att;
    rpci.subpassCount = 1;
    rpci.pSubpasses = &sub;
    rpci.dependencyCount = 2;
    rpci.pDependencies = deps;
    DS_VK_TRY(vkCreateRenderPass(core->device, &rpci, nullptr, &out), std::string("vkCreateRenderPass ") + name);
    core->name(VK_OBJECT_TYPE_RENDER_PASS, out, name);
    return Ok{};
  };
  DS_TRY_STATUS(make(final_layout, "scene pass", main_pass));
  return make(VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL, "mirror pass", mirror_pass);
}

Status SceneRenderer::State::createLayouts() {
  VkDevice device = core->device;
  VkDescriptorSetLayoutBinding frame_binding{};
  frame_binding.binding = 0;
  frame_binding.descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
  frame_binding.descriptorCount = 1;
  frame_binding.stageFlags = VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;
  VkDescriptorSetLayoutCreateInfo dslci{};
  dslci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO;
  dslci.bindingCount = 1;
  dslci.pBindings = &frame_binding;
  DS_VK_TRY(vkCreateDescriptorSetLayout(device, &dslci, nullptr, &frame_set_layout), "frame set layout");
  VkDescriptorSetLayoutBinding tex_binding = frame_binding;
  tex_binding.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  tex_binding.stageFlags = VK_SHADER_STAGE_FRAGMENT_BIT;
  dslci.pBindings = &tex_binding;
  DS_VK_TRY(vkCreateDescriptorSetLayout(device, &dslci, nullptr, &texture_set_layout), "texture set layout");

  const VkDescriptorSetLayout sets[2] = {frame_set_layout, texture_set_layout};
  VkPushConstantRange push{VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                           uint32_t(sizeof(layout::DrawConstants))};
  VkPipelineLayoutCreateInfo plci{};
  plci.sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO;
  plci.setLayoutCount = 2;
  plci.pSetLayouts = sets;
  plci.pushConstantRangeCount = 1;
  plci.pPushConstantRanges = &push;
  DS_VK_TRY(vkCreatePipelineLayout(device, &plci, nullptr, &pipeline_layout), "scene pipeline layout");
  core->name(VK_OBJECT_TYPE_PIPELINE_LAYOUT, pipeline_layout, "scene pipeline layout");

  VkSamplerCreateInfo sci{};
  sci.sType = VK_STRUCTURE_TYPE_SAMPLER_CREATE_INFO;
  sci.magFilter = VK_FILTER_LINEAR;
  sci.minFilter = VK_FILTER_LINEAR;
  sci.mipmapMode = VK_SAMPLER_MIPMAP_MODE_NEAREST;
  sci.addressModeU = sci.addressModeV = sci.addressModeW = VK_SAMPLER_ADDRESS_MODE_CLAMP_TO_EDGE;
  sci.maxLod = 0.0f;
  DS_VK_TRY(vkCreateSampler(device, &sci, nullptr, &sampler), "scene sampler");

  const VkDescriptorPoolSize sizes[2] = {{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2},
                                         {VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 2}};
  VkDescriptorPoolCreateInfo dpci{};
  dpci.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO;
  dpci.maxSets = 4;
  dpci.poolSizeCount = 2;
  dpci.pPoolSizes = sizes;
  DS_VK_TRY(vkCreateDescriptorPool(device, &dpci, nullptr, &pool), "scene descriptor pool");
  const VkDescriptorSetLayout wanted[4] = {frame_set_layout, frame_set_layout, texture_set_layout, texture_set_layout};
  VkDescriptorSet got[4]{};
  VkDescriptorSetAllocateInfo dsai{};
  dsai.sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO;
  dsai.descriptorPool = pool;
  dsai.descriptorSetCount = 4;
  dsai.pSetLayouts = wanted;
  DS_VK_TRY(vkAllocateDescriptorSets(device, &dsai, got), "scene descriptor sets");
  main_frame_set = got[0];
  mirror_frame_set = got[1];
  mirror_texture_set = got[2];
  overlay_texture_set = got[3];

  // The two passes' uniforms live in one buffer, each at a storage-offset-aligned place.
  mirror_offset = roundUp(sizeof(layout::FrameUniforms), std::max<uint64_t>(core->limits.min_storage_buffer_offset_alignment, 16));
  auto buf = gpu::Buffer::create(*ctx, mirror_offset * 2, gpu::MemoryKind::DeviceLocal, gpu::BufferUse::Storage,
                                 "scene frame uniforms");
  if (!buf) return buf.error();
  uniforms.emplace(std::move(*buf));
  VkDescriptorBufferInfo infos[2] = {{uniforms->handle(), 0, sizeof(layout::FrameUniforms)},
                                     {uniforms->handle(), mirror_offset, sizeof(layout::FrameUniforms)}};
  VkWriteDescriptorSet writes[2]{};
  for (int i = 0; i < 2; ++i) {
    writes[i].sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
    writes[i].dstSet = i == 0 ? main_frame_set : mirror_frame_set;
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(device, 2, writes, 0, nullptr);
  return Ok{};
}

// vertex_kind: 0 none (overlay), 1 MeshVertex (tooth), 2 ToolVertex (tools), 3 ToolVertex position (glass).
// colour_write false: depth only; yield_depth: a slight depth bias away from the eye.
Result<VkPipeline> SceneRenderer::State::createPipeline(const char* name, std::span<const uint32_t> vert,
                                                        std::span<const uint32_t> frag, int vertex_kind, bool blend,
                                                        bool depth_write, bool depth_test, bool cull, bool flip,
                                                        bool colour_write, bool yield_depth) {
  VkDevice device = core->device;
  VkShaderModule mods[2]{};
  for (int i = 0; i < 2; ++i) {
    const std::span<const uint32_t> code = i == 0 ? vert : frag;
    VkShaderModuleCreateInfo smci{};
    smci.sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO;
    smci.codeSize = code.size() * sizeof(uint32_t);
    smci.pCode = code.data();
    DS_VK_TRY(vkCreateShaderModule(device, &smci, nullptr, &mods[i]), std::string("shader module for ") + name);
    modules.push_back(mods[i]);
  }
  VkPipelineShaderStageCreateInfo stages[2]{};
  for (int i = 0; i < 2; ++i) {
    stages[i].sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO;
    stages[i].stage = i == 0 ? VK_SHADER_STAGE_VERTEX_BIT : VK_SHADER_STAGE_FRAGMENT_BIT;
    stages[i].module = mods[i];
    stages[i].pName = "main";
  }

  VkVertexInputBindingDescription binding{};
  VkVertexInputAttributeDescription attrs[2]{};
  VkPipelineVertexInputStateCreateInfo vi{};
  vi.sType = VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO;
  if (vertex_kind != 0) {
    binding.binding = 0;
    binding.inputRate = VK_VERTEX_INPUT_RATE_VERTEX;
    attrs[0] = {0, 0, VK_FORMAT_R32G32B32_SFLOAT, 0};
    if (vertex_kind == 1) {
      binding.stride = sizeof(dentsim::layout::MeshVertex);
      attrs[1] = {1, 0, VK_FORMAT_R32_UINT, uint32_t(offsetof(dentsim::layout::MeshVertex, packed))};
    } else {  // ToolVertex; kind 3 reads its position only
      binding.stride = sizeof(ToolVertex);
      attrs[1] = {1, 0, VK_FORMAT_R32G32B32_SFLOAT, uint32_t(offsetof(ToolVertex, nx))};
    }
    vi.vertexBindingDescriptionCount = 1;
    vi.pVertexBindingDescriptions = &binding;
    vi.vertexAttributeDescriptionCount = vertex_kind == 3 ? 1u : 2u;
    vi.pVertexAttributeDescriptions = attrs;
  }
  VkPipelineInputAssemblyStateCreateInfo ia{};
  ia.sType = VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO;
  ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkPipelineViewportStateCreateInfo vp{};
  vp.sType = VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO;
  vp.viewportCount = 1;
  vp.scissorCount = 1;
  VkPipelineRasterizationStateCreateInfo rs{};
  rs.sType = VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO;
  rs.polygonMode = VK_POLYGON_MODE_FILL;
  rs.cullMode = cull ? VK_CULL_MODE_BACK_BIT : VK_CULL_MODE_NONE;
  // Counter-clockwise from outside in the world; a mirrored view turns that clockwise.
  rs.frontFace = flip ? VK_FRONT_FACE_CLOCKWISE : VK_FRONT_FACE_COUNTER_CLOCKWISE;
  rs.lineWidth = 1.0f;
  // A surface that yields its depth loses to one of the scene's at the same depth: the ghost at the
  // student's own pose must not paint over the student's tool.
  if (yield_depth) {
    rs.depthBiasEnable = VK_TRUE;
    rs.depthBiasConstantFactor = 8.0f;
    rs.depthBiasSlopeFactor = 1.0f;
  }
  VkPipelineMultisampleStateCreateInfo ms{};
  ms.sType = VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO;
  ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo ds{};
  ds.sType = VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO;
  ds.depthTestEnable = depth_test ? VK_TRUE : VK_FALSE;
  ds.depthWriteEnable = depth_write ? VK_TRUE : VK_FALSE;
  ds.depthCompareOp = VK_COMPARE_OP_LESS_OR_EQUAL;
  VkPipelineColorBlendAttachmentState cb{};
  cb.colorWriteMask = colour_write ? VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT |
                                         VK_COLOR_COMPONENT_A_BIT
                                   : 0;
  if (blend) {
    cb.blendEnable = VK_TRUE;
    cb.srcColorBlendFactor = VK_BLEND_FACTOR_SRC_ALPHA;
    cb.dstColorBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    cb.colorBlendOp = VK_BLEND_OP_ADD;
    cb.srcAlphaBlendFactor = VK_BLEND_FACTOR_ONE;
    cb.dstAlphaBlendFactor = VK_BLEND_FACTOR_ONE_MINUS_SRC_ALPHA;
    cb.alphaBlendOp = VK_BLEND_OP_ADD;
  }
  VkPipelineColorBlendStateCreateInfo cbs{};
  cbs.sType = VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO;
  cbs.attachmentCount = 1;
  cbs.pAttachments = &cb;
  const VkDynamicState dyn[2] = {VK_DYNAMIC_STATE_VIEWPORT, VK_DYNAMIC_STATE_SCISSOR};
  VkPipelineDynamicStateCreateInfo dys{};
  dys.sType = VK_STRUCTURE_TYPE_PIPELINE_DYNAMIC_STATE_CREATE_INFO;
  dys.dynamicStateCount = 2;
  dys.pDynamicStates = dyn;

  VkGraphicsPipelineCreateInfo gpci{};
  gpci.sType = VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO;
  gpci.stageCount = 2;
  gpci.pStages = stages;
  gpci.pVertexInputState = &vi;
  gpci.pInputAssemblyState = &ia;
  gpci.pViewportState = &vp;
  gpci.pRasterizationState = &rs;
  gpci.pMultisampleState = &ms;
  gpci.pDepthStencilState = &ds;
  gpci.pColorBlendState = &cbs;
  gpci.pDynamicState = &dys;
  gpci.layout = pipeline_layout;
  // The mirror pass has the same attachment formats, so these pipelines serve it too.
  gpci.renderPass = main_pass;
  gpci.subpass = 0;
  VkPipeline pipe = VK_NULL_HANDLE;
  DS_VK_TRY(vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &gpci, nullptr, &pipe),
               std::string("vkCreateGraphicsPipelines ") + name);
  core->name(VK_OBJECT_TYPE_PIPELINE, pipe, name);
  return pipe;
}

Status SceneRenderer::State::createPipelines() {
  const std::span<const uint32_t> tooth_vert{tooth_vert_spv, tooth_vert_spv_words};
  const std::span<const uint32_t> tool_vert{tool_vert_spv, tool_vert_spv_words};
  const std::span<const uint32_t> surface_frag{surface_frag_spv, surface_frag_spv_words};
  const std::span<const uint32_t> glass_vert{glass_vert_spv, glass_vert_spv_words};
  const std::span<const uint32_t> mirror_frag{mirror_frag_spv, mirror_frag_spv_words};
  const std::span<const uint32_t> overlay_vert{overlay_vert_spv, overlay_vert_spv_words};
  const std::span<const uint32_t> overlay_frag{overlay_frag_spv, overlay_frag_spv_words};
  for (int f = 0; f < 2; ++f) {
    const bool flip = f == 1;
    const size_t i = size_t(f);
    auto p = createPipeline("tooth opaque", tooth_vert, surface_frag, 1, false, true, true, true, flip);
    if (!p) return p.error();
    pipes.tooth_opaque[i] = *p;
    p = createPipeline("tooth translucent", tooth_vert, surface_frag, 1, true, false, true, true, flip);
    if (!p) return p.error();
    pipes.tooth_blend[i] = *p;
    p = createPipeline("tooth translucent depth", tooth_vert, surface_frag, 1, false, true, true, true, flip, false);
    if (!p) return p.error();
    pipes.tooth_blend_depth[i] = *p;
    p = createPipeline("tool", tool_vert, surface_frag, 2, false, true, true, true, flip);
    if (!p) return p.error();
    pipes.tool[i] = *p;
    p = createPipeline("mirror glass", glass_vert, mirror_frag, 3, false, true, true, true, flip);
    if (!p) return p.error();
    pipes.glass[i] = *p;
    p = createPipeline("ghost depth", tool_vert, surface_frag, 2, false, true, true, true, flip, false, true);
    if (!p) return p.error();
    pipes.ghost_depth[i] = *p;
    p = createPipeline("ghost tool", tool_vert, surface_frag, 2, true, false, true, true, flip, true, true);
    if (!p) return p.error();
    pipes.ghost[i] = *p;
  }
  auto p = createPipeline("overlay", overlay_vert, overlay_frag, 0, false, false, false, false, false);
  if (!p) return p.error();
  pipes.overlay = *p;
  return Ok{};
}

Status SceneRenderer::State::createTools() {
  const auto upload = [&](const std::string& name, const std::vector<ToolVertex>& verts, ToolMesh& out) -> Status {
    const std::span<const ToolVertex> v(verts);
    auto buf = gpu::Buffer::create(*ctx, std::max<uint64_t>(v.size_bytes(), 16), gpu::MemoryKind::DeviceLocal,
                                   gpu::BufferUse::Geometry, "tool mesh " + name);
    if (!buf) return buf.error();
    DS_TRY_STATUS(buf->upload(*ctx, std::as_bytes(v)));
    out.vertices.emplace(std::move(*buf));
    out.count = uint32_t(verts.size());
    return Ok{};
  };
  for (const ToolSpec& spec : toolCatalog()) {
    auto mesh = loadBuiltinTool(spec.name);
    if (!mesh) return mesh.error();
    DS_TRY_STATUS(upload(spec.name, creasedVertices(*mesh), tools[spec.name]));
  }
  return upload("mirror glass", discVertices(kMirrorGlassRadiusMm, kGlassLiftMm, kGlassSegments), glass);
}

Status SceneRenderer::State::createMirrorTarget(VkExtent2D extent) {
  auto colour = GpuImage::create(*ctx, extent, colour_format,
                                 VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT,
                                 VK_IMAGE_ASPECT_COLOR_BIT, "mirror image");
  if (!colour) return colour.error();
  auto depth = GpuImage::create(*ctx, extent, depth_format, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                                VK_IMAGE_ASPECT_DEPTH_BIT, "mirror depth");
  if (!depth) return depth.error();
  mirror_colour.emplace(std::move(*colour));
  mirror_depth.emplace(std::move(*depth));
  const VkImageView views[2] = {mirror_colour->view(), mirror_depth->view()};
  VkFramebufferCreateInfo fci{};
  fci.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO;
  fci.renderPass = mirror_pass;
  fci.attachmentCount = 2;
  fci.pAttachments = views;
  fci.width = extent.width;
  fci.height = extent.height;
  fci.layers = 1;
  DS_VK_TRY(vkCreateFramebuffer(core->device, &fci, nullptr, &mirror_framebuffer), "mirror framebuffer");
  VkDescriptorImageInfo info{sampler, mirror_colour->view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  VkWriteDescriptorSet w{};
  w.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
  w.dstSet = mirror_texture_set;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  w.pImageInfo = &info;
  vkUpdateDescriptorSets(core->device, 1, &w, 0, nullptr);
  return Ok{};
}

// The mirror's image drawn at the size it is shown at needs at most the target's size. It grows when a
// larger target comes (the first frame, a larger window), never with the mirror's every move: growing
// waits for the device, since frames in flight may still sample the image through the one set.
Status SceneRenderer::State::growMirrorTarget(VkExtent2D needed) {
  if (mirror_colour && mirror_colour->extent().width >= needed.width && mirror_colour->extent().height >= needed.height)
    return Ok{};
  const VkExtent2D extent{std::max(needed.width, mirror_colour ? mirror_colour->extent().width : 0u),
                          std::max(needed.height, mirror_colour ? mirror_colour->extent().height : 0u)};
  if (mirror_colour) {
    DS_TRY_STATUS(ctx->waitIdle());
    mirror_colour->markUsed(last_serial);
    mirror_depth->markUsed(last_serial);
    VkDevice device = core->device;
    VkFramebuffer fb = mirror_framebuffer;
    core->retired.retire(last_serial, [device, fb] { vkDestroyFramebuffer(device, fb, nullptr); });
    mirror_framebuffer = VK_NULL_HANDLE;
    mirror_colour.reset();
    mirror_depth.reset();
  }
  return createMirrorTarget(extent);
}

// The glass disc's bounding rectangle on a `target`-sized frame, a pixel wider on every side (the
// rim's edge pixels), clipped to the target; the whole target when a rim point lies behind the eye
// (its projection would flip). Empty: the glass is off the frame.
PixelRect SceneRenderer::State::glassRect(const FrameState& frame, VkExtent2D target) const {
  const int w = int(target.width), h = int(target.height);
  const glm::mat4 to_clip = frame.projection * frame.view * toGlm(frame.mirror);
  float lo_x = 1e30f, lo_y = 1e30f, hi_x = -1e30f, hi_y = -1e30f;
  for (const glm::vec3& corner : glass_corners) {
    const glm::vec4 c = to_clip * glm::vec4(corner, 1.0f);
    if (!(c.w > 1e-6f)) return PixelRect{0, 0, w, h};
    const float x = (c.x / c.w + 1.0f) * 0.5f * float(w), y = (c.y / c.w + 1.0f) * 0.5f * float(h);
    lo_x = std::min(lo_x, x);
    hi_x = std::max(hi_x, x);
    lo_y = std::min(lo_y, y);
    hi_y = std::max(hi_y, y);
  }
  const auto clampTo = [](float v, int hi) { return int(std::clamp(v, 0.0f, float(hi))); };
  const int x0 = clampTo(std::floor(lo_x) - 1.0f, w), x1 = clampTo(std::ceil(hi_x) + 1.0f, w);
  const int y0 = clampTo(std::floor(lo_y) - 1.0f, h), y1 = clampTo(std::ceil(hi_y) + 1.0f, h);
  return PixelRect{x0, y0, x1 - x0, y1 - y0};
}

Result<SceneRenderer> SceneRenderer::create(gpu::Context& ctx, VkFormat colour_format, VkImageLayout final_layout,
                                            const SceneRendererOptions& options) {
  auto s = std::make_unique<State>();
  s->ctx = &ctx;
  s->core = ctx.sharedCore();
  s->options = options;
  s->colour_format = colour_format;
  s->final_layout = final_layout;

  // The first depth format the device can attach.
  for (VkFormat f : {VK_FORMAT_D32_SFLOAT, VK_FORMAT_X8_D24_UNORM_PACK32, VK_FORMAT_D16_UNORM}) {
    VkFormatProperties props{};
    vkGetPhysicalDeviceFormatProperties(s->core->physical, f, &props);
    if (props.optimalTilingFeatures & VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT) {
      s->depth_format = f;
      break;
    }
  }
  if (s->depth_format == VK_FORMAT_UNDEFINED) return makeError(kWhere, "the device has no depth attachment format");
  VkFormatProperties colour_props{};
  vkGetPhysicalDeviceFormatProperties(s->core->physical, colour_format, &colour_props);
  const VkFormatFeatureFlags need = VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT | VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BLEND_BIT |
                                    VK_FORMAT_FEATURE_SAMPLED_IMAGE_BIT;
  if ((colour_props.optimalTilingFeatures & need) != need)
    return makeError(kWhere, "colour format " + std::to_string(int(colour_format)) +
                                 " cannot be a blended colour attachment and sampled on this device");

  DS_TRY_STATUS(s->createPasses());
  DS_TRY_STATUS(s->createLayouts());
  DS_TRY_STATUS(s->createPipelines());
  DS_TRY_STATUS(s->createTools());
  // A fixed-size mirror image is made now; one drawn at the size it is shown at, at its first pass.
  if (options.mirror_resolution > 0)
    DS_TRY_STATUS(s->createMirrorTarget({options.mirror_resolution, options.mirror_resolution}));
  for (const ToolVertex& v : discVertices(kMirrorGlassRadiusMm, kGlassLiftMm, kGlassSegments))
    if (v.px != 0.0f || v.py != 0.0f) s->glass_corners.emplace_back(v.px, v.py, v.pz);
  return SceneRenderer(std::move(s));
}

SceneRenderer::SceneRenderer(std::unique_ptr<State> state) : state_(std::move(state)) {}
SceneRenderer::SceneRenderer(SceneRenderer&&) noexcept = default;
SceneRenderer& SceneRenderer::operator=(SceneRenderer&&) noexcept = default;
SceneRenderer::~SceneRenderer() = default;

VkRenderPass SceneRenderer::renderPass() const { return state_->main_pass; }
VkFormat SceneRenderer::colourFormat() const { return state_->colour_format; }
VkImageLayout SceneRenderer::finalLayout() const { return state_->final_layout; }
bool SceneRenderer::mirrorDrawn() const { return state_->mirror_drawn; }
void SceneRenderer::markSubmitted(uint64_t serial) { state_->last_serial = std::max(state_->last_serial, serial); }

RenderImage SceneRenderer::mirrorImage() const {
  if (!state_->mirror_colour) return {};
  const GpuImage& m = *state_->mirror_colour;
  return {m.image(), m.view(), m.format(), m.extent()};
}

PixelRect SceneRenderer::mirrorRect() const { return state_->mirror_rect; }

glm::mat4 cropProjection(const glm::mat4& projection, const PixelRect& rect, VkExtent2D target) {
  assert(!rect.empty());
  // NDC x of the frame maps to x' = x * W / w + (W - 2 x0 - w) / w, so that pixel x0 lands on -1 and
  // x0 + w on +1; the same for y (Vulkan's y runs down, as pixel rows do). In clip space the offset
  // is scaled by w_clip, so the crop is one matrix before the division.
  const float W = float(target.width), H = float(target.height);
  const float w = float(rect.width), h = float(rect.height);
  glm::mat4 crop(1.0f);
  crop[0][0] = W / w;
  crop[1][1] = H / h;
  crop[3][0] = (W - 2.0f * float(rect.x) - w) / w;
  crop[3][1] = (H - 2.0f * float(rect.y) - h) / h;
  return crop * projection;
}

Status SceneRenderer::setOverlayImage(const RgbImage& image) {
  if (image.width <= 0 || image.height <= 0 || image.rgb.size() != size_t(image.width) * size_t(image.height) * 3)
    return makeError(kWhere, "overlay image is empty or its pixels do not match its size");
  State& s = *state_;
  DS_TRY_STATUS(s.ctx->waitIdle());
  const VkExtent2D extent{uint32_t(image.width), uint32_t(image.height)};
  auto img = GpuImage::create(*s.ctx, extent, VK_FORMAT_R8G8B8A8_UNORM,
                              VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT, VK_IMAGE_ASPECT_COLOR_BIT,
                              "overlay image");
  if (!img) return img.error();
  std::vector<uint8_t> rgba(size_t(image.width) * size_t(image.height) * 4);
  for (size_t p = 0; p < rgba.size() / 4; ++p) {
    std::memcpy(&rgba[4 * p], &image.rgb[3 * p], 3);
    rgba[4 * p + 3] = 255;
  }
  auto staging = gpu::Buffer::create(*s.ctx, rgba.size(), gpu::MemoryKind::HostVisible, gpu::BufferUse::Transfer,
                                     "overlay staging");
  if (!staging) return staging.error();
  std::memcpy(staging->mapped(), rgba.data(), rgba.size());
  DS_TRY_STATUS(gpu::submitAndWait(*s.ctx, "overlay upload", [&](gpu::Commands& cmds) -> Status {
    VkImageMemoryBarrier b{};
    b.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER;
    b.srcAccessMask = 0;
    b.dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    b.oldLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    b.newLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    b.srcQueueFamilyIndex = b.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
    b.image = img->image();
    b.subresourceRange = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 1, 0, 1};
    vkCmdPipelineBarrier(cmds.cmd(), VK_PIPELINE_STAGE_TOP_OF_PIPE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 0, nullptr, 0,
                         nullptr, 1, &b);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
    region.imageExtent = {extent.width, extent.height, 1};
    vkCmdCopyBufferToImage(cmds.cmd(), staging->handle(), img->image(), VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &region);
    b.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
    b.dstAccessMask = VK_ACCESS_SHADER_READ_BIT;
    b.oldLayout = VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL;
    b.newLayout = VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL;
    vkCmdPipelineBarrier(cmds.cmd(), VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT, 0, 0, nullptr,
                         0, nullptr, 1, &b);
    cmds.use(*staging);
    img->markUsed(cmds.serial());
    return Ok{};
  }));
  s.overlay.emplace(std::move(*img));
  VkDescriptorImageInfo info{s.sampler, s.overlay->view(), VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL};
  VkWriteDescriptorSet w{};
  w.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET;
  w.dstSet = s.overlay_texture_set;
  w.descriptorCount = 1;
  w.descriptorType = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
  w.pImageInfo = &info;
  vkUpdateDescriptorSets(s.core->device, 1, &w, 0, nullptr);
  return Ok{};
}

// ==== 4. targets =====================================================================================

Result<Target*> SceneRenderer::State::target(const RenderImage& image) {
  auto it = targets.find(image.view);
  if (it != targets.end() && it->second.image == image.image && it->second.extent.width == image.extent.width &&
      it->second.extent.height == image.extent.height)
    return &it->second;
  if (it != targets.end()) {
    retireTarget(it->second);
    targets.erase(it);
  }
  Target t;
  t.extent = image.extent;
  t.image = image.image;
  auto depth = GpuImage::create(*ctx, image.extent, depth_format, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT,
                                VK_IMAGE_ASPECT_DEPTH_BIT, "scene depth");
  if (!depth) return depth.error();
  t.depth.emplace(std::move(*depth));
  const VkImageView views[2] = {image.view, t.depth->view()};
  VkFramebufferCreateInfo fci{};
  fci.sType = VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO;
  fci.renderPass = main_pass;
  fci.attachmentCount = 2;
  fci.pAttachments = views;
  fci.width = image.extent.width;
  fci.height = image.extent.height;
  fci.layers = 1;
  DS_VK_TRY(vkCreateFramebuffer(core->device, &fci, nullptr, &t.framebuffer), "scene framebuffer");
  core->name(VK_OBJECT_TYPE_FRAMEBUFFER, t.framebuffer, "scene framebuffer");
  return &targets.emplace(image.view, std::move(t)).first->second;
}

ToothDrawStats SceneRenderer::toothDrawStats() const { return state_->tooth_stats; }

void SceneRenderer::forgetTarget(VkImageView view) {
  auto it = state_->targets.find(view);
  if (it == state_->targets.end()) return;
  state_->retireTarget(it->second);
  state_->targets.erase(it);
}

void SceneRenderer::forgetTargets() {
  for (auto& [view, t] : state_->targets) state_->retireTarget(t);
  state_->targets.clear();
}

// ==== 5. recording ===================================================================================

void SceneRenderer::State::drawTooth(VkCommandBuffer cmd, const ToothSurfaces& tooth, const FrameState& frame,
                                     bool translucent, bool flip, const LodChoice* choice, uint64_t& triangles) {
  const VolumeFrame& vf = frame.tooth_frame;
  const uint32_t copies = choice ? tooth.copies() : 1u;
  // Records one tissue's draws of every copy with `pipe`; counts them when `count`.
  const auto draw_tissue = [&](size_t i, const TissueLook& look, bool count) {
    for (uint32_t k = 0; k < copies; ++k) {
      // Copy k's vertices are in its own voxels, 2^k full ones each.
      const float s = float(vf.voxel_mm * double(1u << k));
      const glm::mat4 model = glm::scale(
          glm::translate(glm::mat4(1.0f), glm::vec3(float(vf.origin_mm[0]), float(vf.origin_mm[1]), float(vf.origin_mm[2]))),
          glm::vec3(s, s, s));
      layout::DrawConstants dc{};
      putMatrix(dc.model, model);
      putLook(dc, look);
      vkCmdPushConstants(cmd, pipeline_layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof dc, &dc);
      gpu::GpuSurface& surface = tooth.surface(i, k);
      for (uint32_t page = 0; page < surface.pageCount(); ++page) {
        const uint32_t n = surface.drawCount(page);
        const auto* records = static_cast<const gpu::SurfaceDraw*>(surface.draws(page).mapped());
        if (n == 0 || !records) continue;
        const VkBuffer slots = surface.pool(page).handle();
        const VkDeviceSize zero = 0;
        vkCmdBindVertexBuffers(cmd, 0, 1, &slots, &zero);
        vkCmdBindIndexBuffer(cmd, slots, 0, VK_INDEX_TYPE_UINT32);
        // The records are host-visible: one direct draw per live block, so neither multiDrawIndirect
        // nor drawIndirectFirstInstance (the block id in firstInstance) is needed, and the choice of
        // copy can skip blocks here.
        for (uint32_t d = 0; d < n; ++d) {
          const gpu::SurfaceDraw& r = records[d];
          if (!r.index_count) continue;
          if (choice && !choice->drawsBlock(k, MeshBlock::unpack(r.first_instance))) continue;
          vkCmdDrawIndexed(cmd, r.index_count, 1, r.first_index, r.vertex_offset, 0);
          if (count) triangles += r.index_count / 3u;
        }
      }
    }
  };
  // Translucent layers go in falling draw order (inside out: caries, pulp, dentin, enamel), so outer
  // ones blend over inner ones. Each translucent tissue writes its depth first and then blends its
  // nearest layer only: where two copies overlap at a border, or a fold puts two layers in one
  // pixel, the tissue is blended once.
  for (size_t n = 0; n < kDrawnTissues.size(); ++n) {
    const size_t i = translucent ? kDrawnTissues.size() - 1 - n : n;
    const TissueLook& look = frame.looks[size_t(kDrawnTissues[i])];
    if (look.alpha <= 0.0 || (look.alpha < 1.0) != translucent) continue;
    if (translucent) {
      vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipes.tooth_blend_depth[flip ? 1 : 0]);
      draw_tissue(i, look, false);
    }
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS,
                      translucent ? pipes.tooth_blend[flip ? 1 : 0] : pipes.tooth_opaque[flip ? 1 : 0]);
    draw_tissue(i, look, true);
  }
}

void SceneRenderer::State::drawTool(VkCommandBuffer cmd, const ToolMesh& mesh, VkPipeline pipe, const glm::mat4& model,
                                    const TissueLook& look) {
  if (!mesh.vertices || mesh.count == 0) return;
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, pipe);
  layout::DrawConstants dc{};
  putMatrix(dc.model, model);
  putLook(dc, look);
  vkCmdPushConstants(cmd, pipeline_layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof dc, &dc);
  const VkBuffer buf = mesh.vertices->handle();
  const VkDeviceSize zero = 0;
  vkCmdBindVertexBuffers(cmd, 0, 1, &buf, &zero);
  vkCmdDraw(cmd, mesh.count, 1, 0, 0);
}

void SceneRenderer::State::drawTools(VkCommandBuffer cmd, const FrameState& frame, bool with_mirror, bool flip) {
  const VkPipeline pipe = pipes.tool[flip ? 1 : 0];
  if (frame.drill_shown) {
    const glm::mat4 model = toGlm(frame.drill);
    drawTool(cmd, tools.at(frame.bur), pipe, model, burLook(options, frame.drill_force_n, frame.max_force_n));
    if (frame.handpiece_shown) drawTool(cmd, tools.at(kHandpieceName), pipe, model, options.steel);
  }
  if (with_mirror && frame.mirror_shown) drawTool(cmd, tools.at(kMirrorName), pipe, toGlm(frame.mirror), options.mirror_rim);
}

void SceneRenderer::State::drawGhost(VkCommandBuffer cmd, const FrameState& frame, bool with_mirror, bool flip) {
  const bool mirror = with_mirror && frame.ghost_mirror_shown;
  if ((!frame.ghost_drill_shown && !mirror) || !(frame.ghost_opacity > 0.0f)) return;
  TissueLook look = options.ghost;
  look.alpha = std::clamp(double(frame.ghost_opacity), 0.0, 1.0);
  // The colour pass keeps the fragments at the depth its depth pass wrote (less or equal): both run
  // the same vertex shader on the same vertices, so they compute the same positions. (`invariant
  // gl_Position` would say so in GLSL, but glslang puts it on a struct member, which the
  // validation layers warn about.)
  for (const VkPipeline pipe : {pipes.ghost_depth[flip ? 1 : 0], pipes.ghost[flip ? 1 : 0]}) {
    if (frame.ghost_drill_shown) {
      const glm::mat4 model = toGlm(frame.ghost_drill);
      drawTool(cmd, tools.at(frame.ghost_bur), pipe, model, look);
      if (frame.ghost_handpiece_shown) drawTool(cmd, tools.at(kHandpieceName), pipe, model, look);
    }
    if (mirror) drawTool(cmd, tools.at(kMirrorName), pipe, toGlm(frame.ghost_mirror), look);
  }
}

Status SceneRenderer::recordFrame(VkCommandBuffer cmd, const RenderImage& target, const ToothSurfaces& tooth,
                                  const FrameState& frame, const std::function<void(VkCommandBuffer)>& in_pass) {
  State& s = *state_;
  if (target.format != s.colour_format)
    return makeError(kWhere, "target format " + std::to_string(int(target.format)) + " differs from the renderer's " +
                                 std::to_string(int(s.colour_format)));
  if (frame.drill_shown && !s.tools.contains(frame.bur)) return makeError(kWhere, "unknown bur '" + frame.bur + "'");
  if (frame.ghost_drill_shown && !s.tools.contains(frame.ghost_bur))
    return makeError(kWhere, "unknown ghost bur '" + frame.ghost_bur + "'");
  if (target.extent.width == 0 || target.extent.height == 0) return makeError(kWhere, "target has no pixels");
  auto tgt = s.target(target);
  if (!tgt) return tgt.error();

  // The mirror: its plane, and whether the eye sees its face at all.
  const glm::vec3 light = glm::normalize(frame.light_dir);
  glm::vec3 mirror_point{0.0f}, mirror_normal{0.0f, 0.0f, 1.0f};
  if (frame.mirror_shown) {
    mirror_point = toGlm(frame.mirror.position);
    mirror_normal = glm::normalize(toGlm(frame.mirror.applyDirection(Vec3{0.0, 0.0, 1.0})));
  }
  bool mirror_pass = frame.mirror_shown && glm::dot(frame.eye - mirror_point, mirror_normal) > 0.0f;
  const glm::mat4 reflect = reflectionMatrix(mirror_point, mirror_normal);
  const glm::mat4 mirror_view = frame.view * reflect;
  // Where the mirror pass draws: the glass's rectangle on the target, pixel for pixel (none when it is
  // off the frame), or with a fixed resolution the whole view into its own square.
  const bool shown_size = s.options.mirror_resolution == 0;
  PixelRect rect{0, 0, int(target.extent.width), int(target.extent.height)};
  if (mirror_pass && shown_size) {
    rect = s.glassRect(frame, target.extent);
    mirror_pass = !rect.empty();
    if (mirror_pass) DS_TRY_STATUS(s.growMirrorTarget(target.extent));
  }
  const glm::mat4 mirror_projection = mirror_pass && shown_size ? cropProjection(frame.projection, rect, target.extent)
                                                                : frame.projection;
  const VkExtent2D mirror_extent = shown_size ? VkExtent2D{uint32_t(rect.width), uint32_t(rect.height)}
                                              : VkExtent2D{s.options.mirror_resolution, s.options.mirror_resolution};

  // Frame uniforms of both passes, written in the command stream so that frames in flight keep theirs.
  layout::FrameUniforms main_u{};
  putMatrix(main_u.viewProj, frame.projection * frame.view);
  putMatrix(main_u.mirrorViewProj, frame.projection * mirror_view);
  main_u.eye = {frame.eye.x, frame.eye.y, frame.eye.z, 1.0f};
  main_u.lightDir = {light.x, light.y, light.z, 0.0f};
  main_u.clipPlane = toVec4(frame.clip_plane);
  main_u.mirrorTint = {s.options.mirror_tint[0], s.options.mirror_tint[1], s.options.mirror_tint[2], 1.0f};
  main_u.mirrorRect = shown_size ? layout::vec4{float(rect.x), float(rect.y), float(rect.width), float(rect.height)}
                                 : layout::vec4{0.0f, 0.0f, 0.0f, 0.0f};
  layout::FrameUniforms mirror_u = main_u;
  putMatrix(mirror_u.viewProj, mirror_projection * mirror_view);
  const glm::vec3 virtual_eye = glm::vec3(reflect * glm::vec4(frame.eye, 1.0f));
  mirror_u.eye = {virtual_eye.x, virtual_eye.y, virtual_eye.z, 1.0f};
  mirror_u.clipPlane = toVec4(planeEquation(mirror_point, mirror_normal));

  // Earlier compute (the mesher) and transfers, and last frame's reads of the uniforms, come first.
  VkMemoryBarrier before{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                         VK_ACCESS_TRANSFER_WRITE_BIT};
  vkCmdPipelineBarrier(cmd,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                           VK_PIPELINE_STAGE_VERTEX_SHADER_BIT | VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                       VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1, &before, 0, nullptr, 0, nullptr);
  vkCmdUpdateBuffer(cmd, s.uniforms->handle(), 0, sizeof main_u, &main_u);
  vkCmdUpdateBuffer(cmd, s.uniforms->handle(), s.mirror_offset, sizeof mirror_u, &mirror_u);
  VkMemoryBarrier after{VK_STRUCTURE_TYPE_MEMORY_BARRIER, nullptr, VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_VERTEX_ATTRIBUTE_READ_BIT | VK_ACCESS_INDEX_READ_BIT};
  vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                       VK_PIPELINE_STAGE_VERTEX_INPUT_BIT | VK_PIPELINE_STAGE_VERTEX_SHADER_BIT |
                           VK_PIPELINE_STAGE_FRAGMENT_SHADER_BIT,
                       0, 1, &after, 0, nullptr, 0, nullptr);

  const VkClearValue clears[2] = {
      {.color = {{frame.background[0], frame.background[1], frame.background[2], 1.0f}}},
      {.depthStencil = {1.0f, 0}}};
  const auto begin = [&](VkRenderPass pass, VkFramebuffer fb, VkExtent2D extent, VkDescriptorSet frame_set) {
    VkRenderPassBeginInfo rbi{};
    rbi.sType = VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO;
    rbi.renderPass = pass;
    rbi.framebuffer = fb;
    rbi.renderArea = {{0, 0}, extent};
    rbi.clearValueCount = 2;
    rbi.pClearValues = clears;
    vkCmdBeginRenderPass(cmd, &rbi, VK_SUBPASS_CONTENTS_INLINE);
    const VkViewport viewport{0.0f, 0.0f, float(extent.width), float(extent.height), 0.0f, 1.0f};
    const VkRect2D scissor{{0, 0}, extent};
    vkCmdSetViewport(cmd, 0, 1, &viewport);
    vkCmdSetScissor(cmd, 0, 1, &scissor);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, s.pipeline_layout, DS_RENDER_SET_FRAME, 1, &frame_set,
                            0, nullptr);
  };
  const bool draw_tooth = frame.tooth_shown && tooth.built();
  // Each pass chooses its own copies: the mirror pass draws a small part of the view and sees the tooth from elsewhere.
  const bool lod = draw_tooth && frame.lod.pixel_error > 0.0f;
  std::optional<glm::vec3> bur_tip;
  if (frame.drill_shown) bur_tip = toGlm(frame.drill.position);
  const auto choose = [&](const glm::mat4& view, const glm::mat4& projection, VkExtent2D extent) {
    return chooseLod(frame.tooth_frame, tooth.copies() - 1u,
                     LodView{view, projection, extent.width, extent.height, bur_tip}, frame.lod,
                     LodRegions{tooth.readyRegions(), tooth.laggingRegions(), tooth.copyErrors()});
  };
  s.tooth_stats = ToothDrawStats{};

  // 1. The mirror pass: everything but the mirror itself, seen in the mirror's plane.
  if (mirror_pass) {
    const bool flip = mirrored(mirror_view);
    begin(s.mirror_pass, s.mirror_framebuffer, mirror_extent, s.mirror_frame_set);
    std::optional<LodChoice> choice;
    if (lod) choice = choose(mirror_view, mirror_projection, mirror_extent);
    const LodChoice* c = choice ? &*choice : nullptr;
    if (draw_tooth) s.drawTooth(cmd, tooth, frame, false, flip, c, s.tooth_stats.mirror_triangles);
    s.drawTools(cmd, frame, false, flip);
    if (draw_tooth) s.drawTooth(cmd, tooth, frame, true, flip, c, s.tooth_stats.mirror_triangles);
    s.drawGhost(cmd, frame, false, flip);
    vkCmdEndRenderPass(cmd);
  }
  s.mirror_drawn = mirror_pass;
  s.mirror_rect = mirror_pass ? rect : PixelRect{};

  // 2. The main pass.
  const bool flip = mirrored(frame.view);
  begin(s.main_pass, (*tgt)->framebuffer, target.extent, s.main_frame_set);
  std::optional<LodChoice> choice;
  if (lod) {
    choice = choose(frame.view, frame.projection, target.extent);
    for (uint8_t k : choice->copy)
      if (k < s.tooth_stats.main_regions.size()) ++s.tooth_stats.main_regions[k];
  }
  const LodChoice* main_choice = choice ? &*choice : nullptr;
  if (draw_tooth)
    s.drawTooth(cmd, tooth, frame, false, flip, main_choice, s.tooth_stats.main_triangles);
  s.drawTools(cmd, frame, true, flip);
  if (mirror_pass) {
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, s.pipeline_layout, DS_RENDER_SET_TEXTURE, 1,
                            &s.mirror_texture_set, 0, nullptr);
    s.drawTool(cmd, s.glass, s.pipes.glass[flip ? 1 : 0], toGlm(frame.mirror), s.options.mirror_rim);
  }
  if (draw_tooth)
    s.drawTooth(cmd, tooth, frame, true, flip, main_choice, s.tooth_stats.main_triangles);
  s.drawGhost(cmd, frame, true, flip);
  if (frame.overlay_shown && s.overlay && frame.overlay_rect.width > 0 && frame.overlay_rect.height > 0) {
    const float w = float(target.extent.width), h = float(target.extent.height);
    const PixelRect& r = frame.overlay_rect;
    layout::DrawConstants dc{};
    dc.rect = {2.0f * float(r.x) / w - 1.0f, 2.0f * float(r.y) / h - 1.0f, 2.0f * float(r.x + r.width) / w - 1.0f,
               2.0f * float(r.y + r.height) / h - 1.0f};
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, s.pipes.overlay);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, s.pipeline_layout, DS_RENDER_SET_TEXTURE, 1,
                            &s.overlay_texture_set, 0, nullptr);
    vkCmdPushConstants(cmd, s.pipeline_layout, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0, sizeof dc, &dc);
    vkCmdDraw(cmd, 6, 1, 0, 0);
  }
  if (in_pass) in_pass(cmd);
  vkCmdEndRenderPass(cmd);
  return Ok{};
}

}  // namespace dentsim::render
