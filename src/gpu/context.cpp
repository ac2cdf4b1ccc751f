// Vulkan context: picks a device, creates the compute queue, counts validation messages, retires handles.
//
// Contents
//   1. VkResult names and errors (vk_check.h)
//   2. Options from the environment, device names
//   3. Validation messenger
//   4. Device listing and choice
//   5. Context::create
//   6. ContextCore, RetireList
#include "gpu/context.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>

#include "gpu/vk_check.h"

namespace dentsim::gpu {

// ---- 1. VkResult names ---------------------------------------------------------------------------
namespace detail {

std::string vkResultName(VkResult r) {
  switch (r) {
#define DS_CASE(x) \
  case x:          \
    return #x;
    DS_CASE(VK_SUCCESS)
    DS_CASE(VK_NOT_READY)
    DS_CASE(VK_TIMEOUT)
    DS_CASE(VK_EVENT_SET)
    DS_CASE(VK_EVENT_RESET)
    DS_CASE(VK_INCOMPLETE)
    DS_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    DS_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    DS_CASE(VK_ERROR_INITIALIZATION_FAILED)
    DS_CASE(VK_ERROR_DEVICE_LOST)
    DS_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    DS_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    DS_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    DS_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    DS_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    DS_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    DS_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    DS_CASE(VK_ERROR_FRAGMENTED_POOL)
    DS_CASE(VK_ERROR_UNKNOWN)
    DS_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    DS_CASE(VK_ERROR_INVALID_EXTERNAL_HANDLE)
    DS_CASE(VK_ERROR_FRAGMENTATION)
    DS_CASE(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
    DS_CASE(VK_ERROR_INVALID_SHADER_NV)
#undef DS_CASE
    default:
      return "VkResult(" + std::to_string(static_cast<int>(r)) + ")";
  }
}

Error vkError(std::string_view what, VkResult r) {
  std::string msg = std::string(what) + " failed: " + vkResultName(r);
  if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
    msg += " (no Vulkan driver found; install mesa-vulkan-drivers for lavapipe)";
  else if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY)
    msg += " (not enough memory)";
  else if (r == VK_ERROR_DEVICE_LOST)
    msg += " (the GPU driver reset the device)";
  return makeError("gpu", msg);
}

}  // namespace detail

using detail::vkError;

// ---- 2. options, names -----------------------------------------------------------------------------

ContextOptions withEnvironment(ContextOptions options) {
  if (const char* v = std::getenv("DENTSIM_VALIDATION"); v && std::strcmp(v, "1") == 0)
    options.enable_validation = true;
  if (const char* d = std::getenv("DENTSIM_DEVICE"); d && *d && options.device_override.empty())
    options.device_override = d;
  return options;
}

bool isNoDeviceError(const Error& e) {
  return e.message.rfind(std::string("gpu: ") + kNoDeviceMessage, 0) == 0;
}

const char* deviceTypeName(VkPhysicalDeviceType type) {
  switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
  }
}

std::string apiVersionString(uint32_t v) {
  return std::to_string(VK_API_VERSION_MAJOR(v)) + "." + std::to_string(VK_API_VERSION_MINOR(v)) + "." +
         std::to_string(VK_API_VERSION_PATCH(v));
}

namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";
constexpr uint32_t kRequiredApi = VK_API_VERSION_1_2;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// ---- 3. validation messenger ---------------------------------------------------------------------

VKAPI_ATTR VkBool32 VKAPI_CALL onDebugMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                              VkDebugUtilsMessageTypeFlagsEXT /*types*/,
                                              const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* state = static_cast<ValidationState*>(user);
  const bool is_error = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) != 0;
  const bool is_warning = (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) != 0;
  if (!is_error && !is_warning) return VK_FALSE;
  (is_error ? state->errors : state->warnings).fetch_add(1);
  const std::string text = std::string(is_error ? "error" : "warning") + ": " +
                           (data && data->pMessage ? data->pMessage : "(no message)");
  std::lock_guard lock(state->mutex);
  state->last_message = text;
  if (state->printed.insert(text).second) std::cerr << "dentsim: vulkan validation " << text << "\n";
  return VK_FALSE;  // the call that triggered the message goes on; the count makes tests fail
}

VkDebugUtilsMessengerCreateInfoEXT messengerInfo(ValidationState* state) {
  VkDebugUtilsMessengerCreateInfoEXT info{};
  info.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
  info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                     VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  info.pfnUserCallback = onDebugMessage;
  info.pUserData = state;
  return info;
}

// ---- 4. devices --------------------------------------------------------------------------------

int typeRank(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 3;
    default: return 4;
  }
}

// A queue family with compute; a compute-only family (no graphics) first, as it is the dedicated one.
// With `graphics`, the first family that does both.
int pickQueueFamily(VkPhysicalDevice pd, bool graphics) {
  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
  int any = -1;
  for (uint32_t i = 0; i < n; ++i) {
    const VkQueueFlags f = families[i].queueFlags;
    if (!(f & VK_QUEUE_COMPUTE_BIT) || families[i].queueCount == 0) continue;
    if (graphics) {
      if (f & VK_QUEUE_GRAPHICS_BIT) return static_cast<int>(i);
      continue;
    }
    if (!(f & VK_QUEUE_GRAPHICS_BIT)) return static_cast<int>(i);
    if (any < 0) any = static_cast<int>(i);
  }
  return any;
}

bool hasDeviceExtension(VkPhysicalDevice pd, const char* name) {
  uint32_t n = 0;
  if (vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, nullptr) != VK_SUCCESS) return false;
  std::vector<VkExtensionProperties> exts(n);
  if (vkEnumerateDeviceExtensionProperties(pd, nullptr, &n, exts.data()) != VK_SUCCESS) return false;
  return std::any_of(exts.begin(), exts.end(), [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

DeviceInfo describe(VkPhysicalDevice pd, uint32_t index, bool graphics, bool swapchain) {
  VkPhysicalDeviceProperties props{};
  vkGetPhysicalDeviceProperties(pd, &props);
  DeviceInfo d;
  d.index = index;
  d.name = props.deviceName;
  d.type = props.deviceType;
  d.vendor_id = props.vendorID;
  d.device_id = props.deviceID;
  d.api_version = props.apiVersion;
  d.driver_version = props.driverVersion;
  if (props.apiVersion >= VK_API_VERSION_1_2) {
    VkPhysicalDeviceDriverProperties driver{};
    driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
    VkPhysicalDeviceProperties2 p2{};
    p2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
    p2.pNext = &driver;
    vkGetPhysicalDeviceProperties2(pd, &p2);
    d.driver_name = driver.driverName;
    d.driver_info = driver.driverInfo;
  }
  if (props.apiVersion < kRequiredApi) {
    d.unusable_reason = "supports Vulkan " + apiVersionString(props.apiVersion) + ", dentsim needs 1.2";
  } else if (pickQueueFamily(pd, graphics) < 0) {
    d.unusable_reason = graphics ? "has no queue that does both graphics and compute" : "has no compute queue";
  } else if (swapchain && !hasDeviceExtension(pd, VK_KHR_SWAPCHAIN_EXTENSION_NAME)) {
    d.unusable_reason = "cannot present to a window (no VK_KHR_swapchain)";
  } else {
    d.usable = true;
  }
  return d;
}

std::string listDevicesText(const std::vector<DeviceInfo>& devices) {
  std::ostringstream s;
  for (size_t i = 0; i < devices.size(); ++i) {
    const DeviceInfo& d = devices[i];
    s << (i ? "; " : "") << d.index << ": " << d.name << " [" << deviceTypeName(d.type) << "]";
    if (!d.usable) s << " (unusable: " << d.unusable_reason << ")";
  }
  return s.str();
}

// Picks a device: the override if given (index or name substring), else the best usable type.
Result<uint32_t> chooseDevice(const std::vector<DeviceInfo>& devices, const std::string& override_text) {
  const std::string where = "gpu";
  if (!override_text.empty()) {
    const bool numeric = std::all_of(override_text.begin(), override_text.end(),
                                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; });
    int found = -1;
    if (numeric) {
      const unsigned long idx = std::strtoul(override_text.c_str(), nullptr, 10);
      if (idx < devices.size()) found = static_cast<int>(idx);
    } else {
      const std::string needle = lower(override_text);
      for (size_t i = 0; i < devices.size() && found < 0; ++i)
        if (lower(devices[i].name).find(needle) != std::string::npos) found = static_cast<int>(i);
    }
    if (found < 0)
      return makeError(where, "device override '" + override_text + "' matches no Vulkan device; devices: " + listDevicesText(devices));
    if (!devices[size_t(found)].usable)
      return makeError(where, "device '" + devices[size_t(found)].name + "' " + devices[size_t(found)].unusable_reason);
    return static_cast<uint32_t>(found);
  }
  int best = -1;
  for (size_t i = 0; i < devices.size(); ++i) {
    if (!devices[i].usable) continue;
    if (best < 0 || typeRank(devices[i].type) < typeRank(devices[size_t(best)].type)) best = static_cast<int>(i);
  }
  if (best < 0) return makeError(where, "no usable Vulkan 1.2 device with compute; devices: " + listDevicesText(devices));
  return static_cast<uint32_t>(best);
}

DeviceLimits queryLimits(VkPhysicalDevice pd, uint32_t queue_family) {
  VkPhysicalDeviceSubgroupProperties subgroup{};
  subgroup.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES;
  VkPhysicalDeviceMaintenance3Properties maint3{};
  maint3.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES;
  maint3.pNext = &subgroup;
  VkPhysicalDeviceProperties2 p2{};
  p2.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
  p2.pNext = &maint3;
  vkGetPhysicalDeviceProperties2(pd, &p2);
  const VkPhysicalDeviceLimits& l = p2.properties.limits;

  DeviceLimits out;
  out.max_storage_buffer_range = l.maxStorageBufferRange;
  out.max_memory_allocation_size = maint3.maxMemoryAllocationSize;
  for (int i = 0; i < 3; ++i) {
    out.max_group_count[size_t(i)] = l.maxComputeWorkGroupCount[i];
    out.max_group_size[size_t(i)] = l.maxComputeWorkGroupSize[i];
  }
  out.max_group_invocations = l.maxComputeWorkGroupInvocations;
  out.max_push_constants_size = l.maxPushConstantsSize;
  out.max_bound_descriptor_sets = l.maxBoundDescriptorSets;
  out.max_per_stage_storage_buffers = l.maxPerStageDescriptorStorageBuffers;
  out.min_storage_buffer_offset_alignment = l.minStorageBufferOffsetAlignment;
  out.subgroup_size = subgroup.subgroupSize;
  out.subgroup_arithmetic_in_compute = (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) != 0 &&
                                       (subgroup.supportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT) != 0;
  out.max_compute_shared_memory = l.maxComputeSharedMemorySize;
  out.timestamp_period = l.timestampPeriod;
  out.timestamp_compute_and_graphics = l.timestampComputeAndGraphics == VK_TRUE;

  uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, nullptr);
  std::vector<VkQueueFamilyProperties> families(n);
  vkGetPhysicalDeviceQueueFamilyProperties(pd, &n, families.data());
  out.timestamp_valid_bits = queue_family < n ? families[queue_family].timestampValidBits : 0;

  VkPhysicalDeviceMemoryProperties mem{};
  vkGetPhysicalDeviceMemoryProperties(pd, &mem);
  for (uint32_t i = 0; i < mem.memoryHeapCount; ++i)
    out.heaps.push_back({mem.memoryHeaps[i].size, (mem.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) != 0});
  return out;
}

bool hasLayer(const char* name) {
  uint32_t n = 0;
  if (vkEnumerateInstanceLayerProperties(&n, nullptr) != VK_SUCCESS) return false;
  std::vector<VkLayerProperties> layers(n);
  if (vkEnumerateInstanceLayerProperties(&n, layers.data()) != VK_SUCCESS) return false;
  return std::any_of(layers.begin(), layers.end(), [&](const VkLayerProperties& p) { return std::strcmp(p.layerName, name) == 0; });
}

bool hasInstanceExtension(const char* name, const char* layer) {
  uint32_t n = 0;
  if (vkEnumerateInstanceExtensionProperties(layer, &n, nullptr) != VK_SUCCESS) return false;
  std::vector<VkExtensionProperties> exts(n);
  if (vkEnumerateInstanceExtensionProperties(layer, &n, exts.data()) != VK_SUCCESS) return false;
  return std::any_of(exts.begin(), exts.end(), [&](const VkExtensionProperties& e) { return std::strcmp(e.extensionName, name) == 0; });
}

}  // namespace

// ---- 5. Context::create ------------------------------------------------------------------------------

Result<Context> Context::create(const ContextOptions& requested) {
  auto core = std::make_shared<ContextCore>();
  core->options = withEnvironment(requested);
  const std::string where = "gpu";

  // Instance: the loader must offer 1.1+ for properties2/subgroup queries; devices must be 1.2.
  uint32_t loader_version = VK_API_VERSION_1_0;
  DS_VK_TRY(vkEnumerateInstanceVersion(&loader_version), "vkEnumerateInstanceVersion (Vulkan loader)");
  if (loader_version < kRequiredApi)
    return makeError(where, "the Vulkan loader supports " + apiVersionString(loader_version) + ", dentsim needs 1.2");

  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  core->validation = core->options.enable_validation;
  if (core->validation) {
    if (!hasLayer(kValidationLayer))
      return makeError(where, std::string("validation requested but ") + kValidationLayer +
                                  " is not installed (Debian: apt install vulkan-validationlayers)");
    layers.push_back(kValidationLayer);
  }
  const bool debug_utils = hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME, nullptr) ||
                           (core->validation && hasInstanceExtension(VK_EXT_DEBUG_UTILS_EXTENSION_NAME, kValidationLayer));
  if (core->validation && !debug_utils)
    return makeError(where, "validation requested but VK_EXT_debug_utils is missing, so errors could not be counted");
  if (debug_utils) extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  for (const std::string& e : core->options.instance_extensions) {
    if (!hasInstanceExtension(e.c_str(), nullptr))
      return makeError(where, "the window needs the instance extension " + e + ", which the Vulkan loader does not offer");
    extensions.push_back(e.c_str());
  }
  const bool swapchain = !core->options.instance_extensions.empty();

  VkApplicationInfo app{};
  app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
  app.pApplicationName = "dentsim";
  app.applicationVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
  app.pEngineName = "dentsim";
  app.apiVersion = kRequiredApi;

  // The messenger chained here also reports problems in vkCreateInstance/vkDestroyInstance.
  VkDebugUtilsMessengerCreateInfoEXT messenger_info = messengerInfo(&core->validation_state);
  VkInstanceCreateInfo ici{};
  ici.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
  ici.pNext = core->validation ? &messenger_info : nullptr;
  ici.pApplicationInfo = &app;
  ici.enabledLayerCount = static_cast<uint32_t>(layers.size());
  ici.ppEnabledLayerNames = layers.data();
  ici.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  ici.ppEnabledExtensionNames = extensions.data();
  if (const VkResult r = vkCreateInstance(&ici, nullptr, &core->instance); r != VK_SUCCESS) {
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
      return makeError(where, std::string(kNoDeviceMessage) + ": no Vulkan driver (ICD) is installed; for a CPU device install mesa-vulkan-drivers");
    return vkError("vkCreateInstance", r);
  }

  if (debug_utils) {
    core->set_object_name = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(
        vkGetInstanceProcAddr(core->instance, "vkSetDebugUtilsObjectNameEXT"));
  }
  if (core->validation) {
    auto create_messenger = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(core->instance, "vkCreateDebugUtilsMessengerEXT"));
    core->destroy_messenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
        vkGetInstanceProcAddr(core->instance, "vkDestroyDebugUtilsMessengerEXT"));
    if (!create_messenger || !core->destroy_messenger)
      return makeError(where, "validation requested but vkCreateDebugUtilsMessengerEXT is unavailable");
    DS_VK_TRY(create_messenger(core->instance, &messenger_info, nullptr, &core->messenger),
              "vkCreateDebugUtilsMessengerEXT");
  }

  // Devices.
  uint32_t count = 0;
  DS_VK_TRY(vkEnumeratePhysicalDevices(core->instance, &count, nullptr), "vkEnumeratePhysicalDevices");
  if (count == 0)
    return makeError(where, std::string(kNoDeviceMessage) + ": the installed drivers report none; for a CPU device install mesa-vulkan-drivers");
  std::vector<VkPhysicalDevice> physicals(count);
  DS_VK_TRY(vkEnumeratePhysicalDevices(core->instance, &count, physicals.data()), "vkEnumeratePhysicalDevices");
  physicals.resize(count);
  for (uint32_t i = 0; i < count; ++i) core->all_devices.push_back(describe(physicals[i], i, core->options.graphics, swapchain));
  auto chosen = chooseDevice(core->all_devices, core->options.device_override);
  if (!chosen) return chosen.error();
  core->physical = physicals[*chosen];
  core->info = core->all_devices[*chosen];
  core->queue_family = static_cast<uint32_t>(pickQueueFamily(core->physical, core->options.graphics));
  core->limits = queryLimits(core->physical, core->queue_family);
  vkGetPhysicalDeviceMemoryProperties(core->physical, &core->memory);

  // Vulkan 1.2 features: query, and enable only the ones we use that the device has.
  VkPhysicalDeviceVulkan12Features supported12{};
  supported12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
  VkPhysicalDeviceFeatures2 supported{};
  supported.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
  supported.pNext = &supported12;
  vkGetPhysicalDeviceFeatures2(core->physical, &supported);
  core->features.host_query_reset = supported12.hostQueryReset == VK_TRUE;
  core->features.timeline_semaphore = supported12.timelineSemaphore == VK_TRUE;
  core->features.storage_buffer_8bit = supported12.storageBuffer8BitAccess == VK_TRUE;

  VkPhysicalDeviceVulkan12Features enable12{};
  enable12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
  enable12.hostQueryReset = core->features.host_query_reset ? VK_TRUE : VK_FALSE;
  VkPhysicalDeviceFeatures2 enable{};
  enable.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
  enable.pNext = &enable12;

  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{};
  qci.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
  qci.queueFamilyIndex = core->queue_family;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  VkDeviceCreateInfo dci{};
  dci.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
  dci.pNext = &enable;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  const char* swapchain_extension = VK_KHR_SWAPCHAIN_EXTENSION_NAME;
  if (swapchain) {
    dci.enabledExtensionCount = 1;
    dci.ppEnabledExtensionNames = &swapchain_extension;
  }
  DS_VK_TRY(vkCreateDevice(core->physical, &dci, nullptr, &core->device), "vkCreateDevice");
  vkGetDeviceQueue(core->device, core->queue_family, 0, &core->queue);

  VkCommandPoolCreateInfo pci{};
  pci.sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO;
  pci.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT | VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pci.queueFamilyIndex = core->queue_family;
  DS_VK_TRY(vkCreateCommandPool(core->device, &pci, nullptr, &core->command_pool), "vkCreateCommandPool");

  // The instance-level handles (instance, physical device, messenger) stay unnamed: the loader hands
  // the driver its own wrapped handles for them, and naming one through the device writes into memory the driver does not own
  // (lavapipe crashed in vkDestroyInstance when we did).
  core->name(VK_OBJECT_TYPE_DEVICE, core->device, "dentsim device");
  core->name(VK_OBJECT_TYPE_QUEUE, core->queue, "dentsim compute queue");
  core->name(VK_OBJECT_TYPE_COMMAND_POOL, core->command_pool, "dentsim one-shot command pool");
  return Context(std::move(core));
}

const DeviceInfo& Context::device() const { return core_->info; }
const std::vector<DeviceInfo>& Context::allDevices() const { return core_->all_devices; }
const DeviceLimits& Context::limits() const { return core_->limits; }
const DeviceFeatures& Context::features() const { return core_->features; }
bool Context::validationEnabled() const { return core_->validation; }
uint32_t Context::validationErrorCount() const { return core_->validation_state.errors.load(); }
uint32_t Context::validationWarningCount() const { return core_->validation_state.warnings.load(); }
std::string Context::lastValidationMessage() const {
  std::lock_guard lock(core_->validation_state.mutex);
  return core_->validation_state.last_message;
}
Status Context::validationStatus() const {
  const uint32_t errors = validationErrorCount();
  if (errors == 0) return Ok{};
  return makeError("gpu", std::to_string(errors) + " Vulkan validation errors; the last: " + lastValidationMessage());
}
size_t Context::collectRetired() { return core_->collect(); }

Status Context::waitIdle() {
  DS_VK_TRY(vkDeviceWaitIdle(core_->device), "vkDeviceWaitIdle");
  for (const auto& t : core_->timed_out) core_->pending.erase(t.serial);
  core_->collect();
  return Ok{};
}

// ---- 6. ContextCore, RetireList --------------------------------------------------------------------

ContextCore::~ContextCore() {
  if (device) {
    // Every object holding this core is gone; the wait makes freeing their retired handles safe.
    vkDeviceWaitIdle(device);
    retired.flushAll();
    for (const auto& t : timed_out) vkDestroyFence(device, t.fence, nullptr);
    if (command_pool) vkDestroyCommandPool(device, command_pool, nullptr);
    vkDestroyDevice(device, nullptr);
  }
  if (messenger && destroy_messenger) destroy_messenger(instance, messenger, nullptr);
  if (instance) vkDestroyInstance(instance, nullptr);
}

void ContextCore::setName(VkObjectType type, uint64_t handle, std::string_view n) const {
  if (!set_object_name || !device || handle == 0) return;
  const std::string text(n);
  VkDebugUtilsObjectNameInfoEXT name_info{};
  name_info.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT;
  name_info.objectType = type;
  name_info.objectHandle = handle;
  name_info.pObjectName = text.c_str();
  set_object_name(device, &name_info);  // a failed name costs only readability, so its result is not checked
}

int ContextCore::findMemoryType(uint32_t type_bits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred,
                                VkMemoryPropertyFlags avoided) const {
  int fallback = -1;
  for (uint32_t i = 0; i < memory.memoryTypeCount; ++i) {
    if (!(type_bits & (1u << i))) continue;
    const VkMemoryPropertyFlags f = memory.memoryTypes[i].propertyFlags;
    if ((f & required) != required) continue;
    if ((f & preferred) == preferred && (f & avoided) == 0) return static_cast<int>(i);
    if (fallback < 0) fallback = static_cast<int>(i);
  }
  return fallback;
}

uint64_t ContextCore::safeSerial() { return pending.empty() ? issued_serial : *pending.begin() - 1; }

size_t ContextCore::collect() {
  // A submission that timed out may have finished since; its fence says so.
  for (auto it = timed_out.begin(); it != timed_out.end();) {
    if (vkGetFenceStatus(device, it->fence) == VK_SUCCESS) {
      pending.erase(it->serial);
      vkDestroyFence(device, it->fence, nullptr);
      it = timed_out.erase(it);
    } else {
      ++it;
    }
  }
  return retired.collect(safeSerial());
}

void RetireList::retire(uint64_t serial, Destroy destroy) {
  std::lock_guard lock(mutex_);
  entries_.push_back({serial, std::move(destroy)});
}

size_t RetireList::collect(uint64_t safe_serial) {
  std::vector<Entry> ready;
  {
    std::lock_guard lock(mutex_);
    auto split = std::stable_partition(entries_.begin(), entries_.end(),
                                       [&](const Entry& e) { return e.serial > safe_serial; });
    ready.assign(std::make_move_iterator(split), std::make_move_iterator(entries_.end()));
    entries_.erase(split, entries_.end());
  }
  for (Entry& e : ready) e.destroy();
  std::lock_guard lock(mutex_);
  return entries_.size();
}

void RetireList::flushAll() {
  std::vector<Entry> all;
  {
    std::lock_guard lock(mutex_);
    all.swap(entries_);
  }
  for (Entry& e : all) e.destroy();
}

size_t RetireList::size() const {
  std::lock_guard lock(mutex_);
  return entries_.size();
}

}  // namespace dentsim::gpu
