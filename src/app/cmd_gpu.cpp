// `dentsim gpu`: lists the Vulkan devices and limits and checks the compute path with a GPU-versus-CPU self-test.
#include <iostream>
#include <memory>
#include <string>

#include "app/commands.h"
#include "gpu/device_report.h"

namespace dentsim::app {

void addGpuCommand(CLI::App& root, Action& action) {
  struct Options {
    std::string device;
    bool validation = false;
    bool json = false;
  };
  auto opts = std::make_shared<Options>();
  CLI::App* cmd = root.add_subcommand("gpu", "List Vulkan devices and limits, and self-test the compute kernels");
  cmd->add_option("--device", opts->device, "Device index or name substring (default: best GPU; also DENTSIM_DEVICE)");
  cmd->add_flag("--validation", opts->validation, "Enable the Khronos validation layer (also DENTSIM_VALIDATION=1)");
  cmd->add_flag("--json", opts->json, "Print one JSON object");
  cmd->callback([&action, opts] {
    action = [opts]() -> int {
      gpu::ContextOptions options;
      options.device_override = opts->device;
      options.enable_validation = opts->validation;
      const Status s = gpu::printDeviceReport(std::cout, options, opts->json);
      return s.ok() ? 0 : fail(s.message());
    };
  });
}

}  // namespace dentsim::app
