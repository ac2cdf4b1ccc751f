// render-internal: error propagation for the renderer's sources (Vulkan results and Status), never in public headers.
#pragma once

#include <string>

#include <vulkan/vulkan.h>

#include "core/result.h"

namespace dentsim::render::detail {

// "render: <what> failed: VkResult <n>".
inline Error vkFailure(const std::string& what, VkResult r) {
  return makeError("render", what + " failed: VkResult " + std::to_string(int(r)));
}

}  // namespace dentsim::render::detail

// Returns the Error of a failed Vulkan call from the enclosing function (a Result<T> or Status).
#define DS_RENDER_VK(call, what)                                                               \
  do {                                                                                         \
    const VkResult ds_render_r_ = (call);                                                      \
    if (ds_render_r_ != VK_SUCCESS) return ::dentsim::render::detail::vkFailure((what), ds_render_r_); \
  } while (0)

// Propagates the Error of a Status or Result expression.
#define DS_RENDER_TRY(expr)                        \
  do {                                             \
    auto ds_render_s_ = (expr);                    \
    if (!ds_render_s_.ok()) return ds_render_s_.error(); \
  } while (0)
