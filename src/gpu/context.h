// Vulkan context for compute: instance, chosen device, one compute queue, command pool, validation and deferred deletion.
//
// Contents
//   1. Options, device description and limits
//   2. Context: creation and accessors (the API)
//   3. Details: RetireList and ContextCore, shared by every object made from a context
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <vulkan/vulkan.h>

#include "core/result.h"

namespace dentsim::gpu {

// ---- 1. options, devices, limits ---------------------------------------------------------------

struct ContextOptions {
  bool enable_validation = false;   // Khronos validation layer + debug messenger; also DENTSIM_VALIDATION=1
  std::string device_override;      // device index ("0") or case-insensitive name substring; also DENTSIM_DEVICE
  uint64_t submit_timeout_ns = 20'000'000'000;  // longest wait for one submission before it is an error [ns]
  // Rendering: the queue must also do graphics (one queue then runs the mesher and the draws, in
  // order), and a device without such a family is unusable.
  bool graphics = false;
  // Instance extensions a window system needs (glfwGetRequiredInstanceExtensions); with any given,
  // the device must also offer VK_KHR_swapchain, which is enabled.
  std::vector<std::string> instance_extensions;
};

// Context::create errors start with "gpu: no Vulkan device" when the machine has no Vulkan driver or
// device at all (tests skip then); any other error is a real failure.
inline constexpr const char* kNoDeviceMessage = "no Vulkan device";
bool isNoDeviceError(const Error& e);

// Applies DENTSIM_VALIDATION=1 and DENTSIM_DEVICE to options that do not already set them.
ContextOptions withEnvironment(ContextOptions options);

// One physical device as the loader reports it.
struct DeviceInfo {
  uint32_t index = 0;                  // position in vkEnumeratePhysicalDevices
  std::string name;                    // deviceName
  VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
  uint32_t vendor_id = 0;
  uint32_t device_id = 0;
  uint32_t api_version = 0;            // VK_MAKE_API_VERSION encoded
  uint32_t driver_version = 0;         // vendor-specific encoding
  std::string driver_name;             // VkPhysicalDeviceDriverProperties (Vulkan 1.2), else empty
  std::string driver_info;             // driver build string, else empty
  bool usable = false;                 // Vulkan 1.2 and a compute queue (with graphics, when asked)
  std::string unusable_reason;         // why not, when !usable
};

// "discrete", "integrated", "virtual", "cpu" or "other".
const char* deviceTypeName(VkPhysicalDeviceType type);
// "1.3.230" from a VK_MAKE_API_VERSION value.
std::string apiVersionString(uint32_t version);

struct MemoryHeapInfo {
  uint64_t size = 0;        // [B]
  bool device_local = false;
};

// The limits dentsim depends on, queried from the chosen device; nothing is assumed.
struct DeviceLimits {
  uint64_t max_storage_buffer_range = 0;         // largest storage-buffer binding [B] (128 MiB on lavapipe)
  uint64_t max_memory_allocation_size = 0;       // largest single allocation [B] (Vulkan 1.1)
  std::array<uint32_t, 3> max_group_count{};     // maxComputeWorkGroupCount [groups]
  std::array<uint32_t, 3> max_group_size{};      // maxComputeWorkGroupSize [invocations]
  uint32_t max_group_invocations = 0;            // maxComputeWorkGroupInvocations
  uint32_t max_push_constants_size = 0;          // [B]
  uint32_t max_bound_descriptor_sets = 0;
  uint32_t max_per_stage_storage_buffers = 0;
  uint64_t min_storage_buffer_offset_alignment = 0;  // [B]
  uint32_t subgroup_size = 0;                    // VkPhysicalDeviceSubgroupProperties [invocations]
  bool subgroup_arithmetic_in_compute = false;   // subgroup add/scan in compute shaders
  uint32_t max_compute_shared_memory = 0;        // maxComputeSharedMemorySize [B]
  float timestamp_period = 0.0f;                 // [ns per tick]
  bool timestamp_compute_and_graphics = false;
  uint32_t timestamp_valid_bits = 0;             // of the compute queue family; 0 = no timestamps
  std::vector<MemoryHeapInfo> heaps;
};

// Optional Vulkan 1.2 features found on the device; each is enabled only when supported.
struct DeviceFeatures {
  bool host_query_reset = false;     // enabled when supported: TimestampPool resets on the host
  bool timeline_semaphore = false;   // reported only
  bool storage_buffer_8bit = false;  // reported only: the kernels read voxels as packed words
};

class RetireList;
struct ContextCore;

// ---- 2. context --------------------------------------------------------------------------------

// Owns the Vulkan instance and device. Move-only. Objects made from it (buffers, pipelines) keep the
// device alive, so they may outlive the Context object itself.
class Context {
 public:
  // Creates instance, device and queue. Errors name the cause in one line: no loader or driver,
  // no device, an override matching nothing (listing the devices), a missing validation layer.
  static Result<Context> create(const ContextOptions& options);

  Context(Context&&) noexcept = default;
  Context& operator=(Context&&) noexcept = default;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;
  ~Context() = default;

  const DeviceInfo& device() const;                 // the chosen device
  const std::vector<DeviceInfo>& allDevices() const;  // every device the loader listed
  const DeviceLimits& limits() const;
  const DeviceFeatures& features() const;
  bool validationEnabled() const;

  // Validation messages seen so far (errors, warnings) and the text of the last one.
  uint32_t validationErrorCount() const;
  uint32_t validationWarningCount() const;
  std::string lastValidationMessage() const;
  // An error naming how many validation errors were seen and the last one; Ok when none was (or
  // validation is off). What a run under DENTSIM_VALIDATION=1 ends on.
  Status validationStatus() const;

  // Frees retired handles whose submissions have finished; returns how many entries remain queued.
  size_t collectRetired();
  // Waits until the device is idle, then frees everything retired.
  Status waitIdle();

  ContextCore& core() const { return *core_; }
  const std::shared_ptr<ContextCore>& sharedCore() const { return core_; }

 private:
  explicit Context(std::shared_ptr<ContextCore> core) : core_(std::move(core)) {}
  std::shared_ptr<ContextCore> core_;
};

// ---- 3. details ----------------------------------------------------------------------------------

// Handles waiting for the submission that last used them. Submissions are numbered by serial; an
// entry is destroyed once every submission up to its serial has signalled its fence.
class RetireList {
 public:
  using Destroy = std::function<void()>;

  // Queues `destroy` to run once submission `serial` (0 = never submitted) has finished.
  void retire(uint64_t serial, Destroy destroy);
  // Runs the destroy functions of every entry at or below `safe_serial`; returns entries left.
  size_t collect(uint64_t safe_serial);
  // Runs every destroy function; only after the device is idle.
  void flushAll();
  size_t size() const;

 private:
  struct Entry {
    uint64_t serial;
    Destroy destroy;
  };
  mutable std::mutex mutex_;
  std::vector<Entry> entries_;
};

// The messenger's view: counts and the last text. Lives in the core so its address is stable.
struct ValidationState {
  std::atomic<uint32_t> errors{0};
  std::atomic<uint32_t> warnings{0};
  mutable std::mutex mutex;
  std::string last_message;
  std::set<std::string> printed;  // each distinct message goes to stderr once
};

// Everything a device-owning object needs, shared by the Context and the objects made from it.
struct ContextCore {
  ContextCore() = default;
  ContextCore(const ContextCore&) = delete;
  ContextCore& operator=(const ContextCore&) = delete;
  ~ContextCore();

  VkInstance instance = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
  VkPhysicalDevice physical = VK_NULL_HANDLE;
  VkDevice device = VK_NULL_HANDLE;
  VkQueue queue = VK_NULL_HANDLE;
  uint32_t queue_family = 0;
  VkCommandPool command_pool = VK_NULL_HANDLE;
  VkPhysicalDeviceMemoryProperties memory{};

  DeviceInfo info;
  std::vector<DeviceInfo> all_devices;
  DeviceLimits limits;
  DeviceFeatures features;
  ContextOptions options;
  bool validation = false;
  ValidationState validation_state;
  RetireList retired;

  PFN_vkSetDebugUtilsObjectNameEXT set_object_name = nullptr;
  PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger = nullptr;

  // Submission serials: issued counts every submission, pending holds those whose fence has not
  // been seen to signal (a timed-out one stays here until its fence is found signalled).
  uint64_t issued_serial = 0;
  std::set<uint64_t> pending;
  struct PendingFence {
    uint64_t serial;
    VkFence fence;
  };
  std::vector<PendingFence> timed_out;  // fences of submissions that passed their timeout

  // Gives a handle a debug name when VK_EXT_debug_utils is enabled.
  void setName(VkObjectType type, uint64_t handle, std::string_view name) const;
  template <class H>
  void name(VkObjectType type, H handle, std::string_view n) const {
    setName(type, reinterpret_cast<uint64_t>(handle), n);
  }
  // Index of a memory type allowed by `type_bits` with all of `required` (preferring `preferred`
  // too and none of `avoided`), or -1.
  int findMemoryType(uint32_t type_bits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred,
                     VkMemoryPropertyFlags avoided) const;
  // Highest serial below which every submission has finished.
  uint64_t safeSerial();
  // Polls timed-out fences, then frees what is safe.
  size_t collect();
};

}  // namespace dentsim::gpu
