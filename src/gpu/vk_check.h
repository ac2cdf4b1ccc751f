// Turns a failed Vulkan call into a readable dentsim::Error (never an abort): for the Vulkan sources of src/gpu and src/render, never in public headers.
#pragma once

#include <string>
#include <string_view>

#include <vulkan/vulkan.h>

#include "core/result.h"

namespace dentsim::gpu::detail {

// "VK_ERROR_OUT_OF_DEVICE_MEMORY" for a VkResult, or "VkResult(-13)" for one it does not know.
std::string vkResultName(VkResult r);

// "gpu: <what> failed: <VkResult name>", with a hint for the results a user can act on.
Error vkError(std::string_view what, VkResult r);

}  // namespace dentsim::gpu::detail

// Evaluates a Vulkan call; on any result other than VK_SUCCESS returns the Error from the enclosing
// function, whose return type must be a Result<T> or Status.
#define DS_VK_TRY(call, what)                                              \
  do {                                                                     \
    const VkResult ds_vk_result_ = (call);                                 \
    if (ds_vk_result_ != VK_SUCCESS) return ::dentsim::gpu::detail::vkError((what), ds_vk_result_); \
  } while (0)

// Propagates the error of a Status or Result expression.
#define DS_TRY_STATUS(expr)                                \
  do {                                                     \
    auto ds_status_ = (expr);                              \
    if (!ds_status_.ok()) return ds_status_.error();       \
  } while (0)
