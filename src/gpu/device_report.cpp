// Device report for `dentsim gpu`: devices, limits, and the material-count self-test, as text or JSON.
#include "gpu/device_report.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include <nlohmann/json.hpp>

#include "gpu/buffer.h"
#include "gpu/material_counts.h"

namespace dentsim::gpu {
namespace {

std::string hex(uint32_t v) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%04x", v);
  return text;
}

nlohmann::json deviceJson(const DeviceInfo& d) {
  nlohmann::json j = {{"index", d.index},
                      {"name", d.name},
                      {"type", deviceTypeName(d.type)},
                      {"vendor_id", hex(d.vendor_id)},
                      {"device_id", hex(d.device_id)},
                      {"api_version", apiVersionString(d.api_version)},
                      {"driver_version", d.driver_version},
                      {"driver_name", d.driver_name},
                      {"driver_info", d.driver_info},
                      {"usable", d.usable}};
  if (!d.usable) j["unusable_reason"] = d.unusable_reason;
  return j;
}

nlohmann::json limitsJson(const DeviceLimits& l) {
  nlohmann::json heaps = nlohmann::json::array();
  for (const MemoryHeapInfo& h : l.heaps) heaps.push_back({{"size_bytes", h.size}, {"device_local", h.device_local}});
  return {{"max_storage_buffer_range_bytes", l.max_storage_buffer_range},
          {"max_memory_allocation_size_bytes", l.max_memory_allocation_size},
          {"max_compute_work_group_count", l.max_group_count},
          {"max_compute_work_group_size", l.max_group_size},
          {"max_compute_work_group_invocations", l.max_group_invocations},
          {"max_push_constants_size_bytes", l.max_push_constants_size},
          {"max_per_stage_storage_buffers", l.max_per_stage_storage_buffers},
          {"subgroup_size", l.subgroup_size},
          {"timestamp_period_ns", l.timestamp_period},
          {"timestamp_compute_and_graphics", l.timestamp_compute_and_graphics},
          {"timestamp_valid_bits", l.timestamp_valid_bits},
          {"memory_heaps", heaps}};
}

std::string triple(const std::array<uint32_t, 3>& a) {
  return std::to_string(a[0]) + " x " + std::to_string(a[1]) + " x " + std::to_string(a[2]);
}

}  // namespace

BrickVolume selfTestVolume() {
  BrickVolume v(5);
  const double c = 15.5, r = 11.0;  // sphere centre and radius [voxels]
  for (uint32_t z = 0; z < v.dim(); ++z)
    for (uint32_t y = 0; y < v.dim(); ++y)
      for (uint32_t x = 0; x < v.dim(); ++x) {
        const double d = std::sqrt((x - c) * (x - c) + (y - c) * (y - c) + (z - c) * (z - c));
        if (d > r) continue;
        // The outer two voxels of the sphere are partly filled, like a smooth cut surface.
        const double inside = std::min(1.0, (r - d) / 2.0);
        const uint32_t fill = std::max(1u, static_cast<uint32_t>(std::lround(inside * DS_FILL_FULL)));
        v.setVoxel(x, y, z, makeVoxel(Material::Enamel, fill));
      }
  for (uint32_t z = 20; z < 30; ++z)
    for (uint32_t y = 2; y < 12; ++y)
      for (uint32_t x = 16; x < 32; ++x) v.setVoxel(x, y, z, makeVoxel(Material::Dentin));
  v.compact();
  return v;
}

Status printDeviceReport(std::ostream& out, const ContextOptions& options, bool json) {
  auto ctx = Context::create(options);
  if (!ctx) return ctx.error();
  const DeviceInfo& dev = ctx->device();
  const DeviceLimits& lim = ctx->limits();

  // Self-test: the count kernel against the CPU reference on the built-in volume.
  const BrickVolume volume = selfTestVolume();
  const MaterialTotals cpu = volume.materialTotals();
  TimingOut timing;
  auto gpu = countMaterialsGpu(*ctx, volume, &timing);
  if (!gpu) return gpu.error();
  const bool equal = gpu->voxels == cpu.voxels && gpu->fill_sum == cpu.fill_sum;
  if (auto idle = ctx->waitIdle(); !idle) return idle.error();

  if (json) {
    nlohmann::json devices = nlohmann::json::array();
    for (const DeviceInfo& d : ctx->allDevices()) devices.push_back(deviceJson(d));
    nlohmann::json test = {{"volume_level", volume.level()},
                           {"gpu_equals_cpu", equal},
                           {"dispatches", timing.dispatches},
                           {"workgroups", timing.workgroups},
                           {"enamel_voxels", gpu->voxels[DS_MAT_ENAMEL]},
                           {"dentin_voxels", gpu->voxels[DS_MAT_DENTIN]}};
    if (timing.timestamps)
      test["kernel_ns"] = timing.kernel_ns;
    else
      test["kernel_ns"] = nullptr, test["timestamp_note"] = timing.timestamp_note;
    nlohmann::json j = {{"devices", devices},
                        {"chosen", deviceJson(dev)},
                        {"limits", limitsJson(lim)},
                        {"self_test", test},
                        {"validation",
                         {{"enabled", ctx->validationEnabled()},
                          {"errors", ctx->validationErrorCount()},
                          {"warnings", ctx->validationWarningCount()}}}};
    out << j.dump(2) << "\n";
  } else {
    out << "Vulkan devices:\n";
    for (const DeviceInfo& d : ctx->allDevices()) {
      out << "  [" << d.index << "] " << d.name << " (" << deviceTypeName(d.type) << ", Vulkan "
          << apiVersionString(d.api_version) << ")" << (d.index == dev.index ? "  <- chosen" : "");
      if (!d.usable) out << "  unusable: " << d.unusable_reason;
      out << "\n";
    }
    out << "Chosen device: " << dev.name << "\n"
        << "  type               " << deviceTypeName(dev.type) << "\n"
        << "  vendor / device id " << hex(dev.vendor_id) << " / " << hex(dev.device_id) << "\n"
        << "  driver             " << (dev.driver_name.empty() ? "?" : dev.driver_name)
        << (dev.driver_info.empty() ? "" : " (" + dev.driver_info + ")") << ", version " << dev.driver_version << "\n"
        << "  API version        " << apiVersionString(dev.api_version) << "\n"
        << "Limits:\n"
        << "  maxStorageBufferRange          " << formatBytes(lim.max_storage_buffer_range) << "\n"
        << "  maxMemoryAllocationSize        " << formatBytes(lim.max_memory_allocation_size) << "\n"
        << "  maxComputeWorkGroupCount       " << triple(lim.max_group_count) << "\n"
        << "  maxComputeWorkGroupSize        " << triple(lim.max_group_size) << "\n"
        << "  maxComputeWorkGroupInvocations " << lim.max_group_invocations << "\n"
        << "  maxPushConstantsSize           " << lim.max_push_constants_size << " B\n"
        << "  subgroup size                  " << lim.subgroup_size << "\n"
        << "  timestampPeriod                " << lim.timestamp_period << " ns\n"
        << "  timestampComputeAndGraphics    " << (lim.timestamp_compute_and_graphics ? "yes" : "no") << "\n"
        << "  queue timestampValidBits       " << lim.timestamp_valid_bits << "\n";
    for (size_t i = 0; i < lim.heaps.size(); ++i)
      out << "  memory heap " << i << "                  " << formatBytes(lim.heaps[i].size)
          << (lim.heaps[i].device_local ? " (device-local)" : "") << "\n";
    out << "Self-test: material counts on a " << volume.dim() << "^3 grid: GPU " << (equal ? "==" : "!=") << " CPU ("
        << gpu->voxels[DS_MAT_ENAMEL] << " enamel, " << gpu->voxels[DS_MAT_DENTIN] << " dentin voxels; "
        << timing.dispatches << " dispatch, " << timing.workgroups << " workgroups)\n";
    if (timing.timestamps) {
      std::ostringstream t;
      t.precision(1);
      t << std::fixed << timing.kernel_ns / 1000.0;
      out << "  kernel time " << t.str() << " us (timestamps)\n";
    } else {
      out << "  kernel time unavailable: " << timing.timestamp_note << "\n";
    }
    out << "Validation: " << (ctx->validationEnabled() ? "on" : "off (--validation or DENTSIM_VALIDATION=1)");
    if (ctx->validationEnabled())
      out << ", " << ctx->validationErrorCount() << " errors, " << ctx->validationWarningCount() << " warnings";
    out << "\n";
  }
  if (!equal) return makeError("gpu", "self-test failed: GPU material counts differ from the CPU reference");
  return ctx->validationStatus();
}

}  // namespace dentsim::gpu
