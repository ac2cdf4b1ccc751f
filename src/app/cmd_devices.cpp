// `dentsim devices [--json]`: every pen and pedal found, its state, and why it cannot be used.
#include <cstdio>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "devices/device_registry.h"

namespace dentsim::app {

void addDevicesCommand(CLI::App& root, Action& action) {
  auto json = std::make_shared<bool>(false);
  auto firmware = std::make_shared<std::string>();
  CLI::App* cmd = root.add_subcommand("devices", "List the haptic pens and foot pedals found, with their state and what stops them");
  cmd->add_flag("--json", *json, "Machine-readable output");
  cmd->add_option("--falcon-firmware", *firmware, "The Novint Falcon's firmware file, to tell whether it can be loaded");
  cmd->callback([json, firmware, &action] {
    action = [json, firmware] {
      devices::PenContext context;
      context.options.falcon.firmware_path = *firmware;
      const std::vector<devices::DeviceEntry> all = devices::listDevices(context);
      if (*json) {
        nlohmann::json j = nlohmann::json::array();
        for (const devices::DeviceEntry& e : all)
          j.push_back({{"name", e.name}, {"kind", e.kind}, {"model", e.model}, {"location", e.location},
                       {"state", devices::stateName(e.state)}, {"usable", e.reason.empty()}, {"reason", e.reason}});
        std::printf("%s\n", j.dump(2).c_str());
        return 0;
      }
      std::printf("%-22s %-6s %-36s %-15s %s\n", "NAME", "KIND", "MODEL", "STATE", "WHERE / WHY NOT USABLE");
      for (const devices::DeviceEntry& e : all) {
        std::printf("%-22s %-6s %-36s %-15s %s\n", e.name.c_str(), e.kind.c_str(), e.model.c_str(),
                    devices::stateName(e.state), e.location.c_str());
        if (!e.reason.empty()) std::printf("%-22s %-6s %-36s %-15s   %s\n", "", "", "", "", e.reason.c_str());
      }
      std::printf("Use a NAME with `dentsim run --drill NAME --mirror NAME --pedal NAME` (docs/DEVICES.md).\n");
      return 0;
    };
  });
}

}  // namespace dentsim::app
