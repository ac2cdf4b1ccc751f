// The device handler: pen and pedal names to backends, and the list of what is connected.
#include "devices/device_registry.h"

#include <cctype>
#include <charconv>

#include "devices/hid_pedal.h"
#include "devices/software_pen.h"
#include "devices/virtual_pen.h"
#include "io/parse_guard.h"
#include "io/pen_playback.h"
#include "io/session_file.h"

namespace dentsim::devices {
namespace {

constexpr const char* kPenChoices = "virtual, script:FILE, replay:FILE, falcon[:N], openhaptics[:NAME]";

}  // namespace

Result<PenName> parsePenName(const std::string& text) {
  PenName n;
  n.text = text;
  const size_t colon = text.find(':');
  n.backend = text.substr(0, colon);
  if (colon != std::string::npos) n.arg = text.substr(colon + 1);
  // The name is the user's text: echoed escaped, so a stray line break cannot split the message.
  const auto bad = [&](const std::string& why) { return makeError("pen '" + escapeControl(text) + "'", why); };
  if (n.backend == "virtual") {
    if (colon != std::string::npos) return bad("the virtual pen takes no argument");
  } else if (n.backend == "script" || n.backend == "replay") {
    if (n.arg.empty()) return bad(n.backend + " needs a file: " + n.backend + ":FILE");
  } else if (n.backend == "falcon") {
    if (n.arg.empty()) n.arg = "0";
    int index = -1;
    const auto [end, ec] = std::from_chars(n.arg.data(), n.arg.data() + n.arg.size(), index);
    if (!std::isdigit(static_cast<unsigned char>(n.arg[0])) || ec != std::errc{} || end != n.arg.data() + n.arg.size() ||
        index < 0 || index > 63)
      return bad("the Falcon's index must be a number 0..63 (falcon:0 is the first on the bus)");
  } else if (n.backend == "openhaptics") {
    if (n.arg.empty()) n.arg = "Default";
  } else {
    return bad(std::string("unknown pen; choose one of ") + kPenChoices);
  }
  return n;
}

Result<std::unique_ptr<HapticDevice>> makePen(const PenName& name, const PenContext& context) {
  const auto software = [&](std::unique_ptr<PenSource> source, const std::string& model,
                            std::shared_ptr<const void> keep) -> std::unique_ptr<HapticDevice> {
    return std::make_unique<SoftwarePen>(name.text, std::move(source),
                                         softwarePenSpec(model, context.max_force_n, context.max_torque_n_mm),
                                         std::move(keep));
  };
  if (name.backend == "virtual")
    return software(std::make_unique<VirtualPen>(context.start_grip), "virtual pen (mouse and keys)", {});
  if (name.backend == "script") {
    auto path = loadPenPath(name.arg);
    if (!path) return path.error();
    if (!hasPen(*path, context.role))
      return makeError(name.arg, "the pen path has no samples for the " + std::string(penRoleName(context.role)));
    auto kept = std::make_shared<const PenPath>(std::move(*path));
    return software(std::make_unique<ScriptedPen>(*kept, context.role), "pen script", kept);
  }
  if (name.backend == "replay") {
    auto rec = readSessionFile(name.arg);
    if (!rec) return rec.error();
    auto kept = std::make_shared<const SessionRecording>(std::move(*rec));
    return software(std::make_unique<ReplayPen>(kept->steps, context.role), "session replay", kept);
  }
  if (name.backend == "falcon") return makeFalcon(std::stoi(name.arg), context.options.falcon);
  if (name.backend == "openhaptics") return makeOpenHapticsPen(name.arg, context.options.openhaptics);
  return makeError("pen '" + escapeControl(name.text) + "'", std::string("unknown pen; choose one of ") + kPenChoices);
}

Status checkPedalName(const std::string& name) {
  if (name.empty() || name == "none" || name == "hid" || name.rfind("hid:", 0) == 0) return Ok{};
  return makeError("pedal '" + escapeControl(name) + "'", "unknown pedal; choose none, hid[:N], hid:VVVV:PPPP[,...] or hid:/dev/hidrawN");
}

Result<std::unique_ptr<FootPedal>> makePedal(const std::string& name) {
  if (Status st = checkPedalName(name); !st) return st.error();
  if (name.empty() || name == "none") return std::unique_ptr<FootPedal>{};
  return makeHidPedal(name == "hid" ? "0" : name.substr(4));
}

std::vector<DeviceEntry> listDevices(const PenContext& context) {
  std::vector<DeviceEntry> all;
  DeviceEntry v;
  v.name = "virtual";
  v.kind = "pen";
  v.model = "virtual pen (mouse and keys)";
  v.location = "this window";
  v.state = DeviceState::Ready;
  all.push_back(v);
  for (auto& e : enumerateFalcons()) all.push_back(std::move(e));
  for (auto& e : enumerateOpenHaptics(context.options.openhaptics)) all.push_back(std::move(e));
  for (auto& e : enumerateHidPedals()) all.push_back(std::move(e));
  return all;
}

}  // namespace dentsim::devices
