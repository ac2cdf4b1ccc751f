// The Touch's serial nodes: a walk of sysfs from each tty up to its USB device, and an access check of its node.
#include "devices/touch_serial.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "core/permission_advice.h"

namespace dentsim::devices {
namespace {

namespace fs = std::filesystem;

// The USB vendor id of the device `tty_dir` (a resolved sysfs device folder) hangs under: the
// nearest ancestor with an idVendor file (the USB device; its interface, the tty's parent, has
// none). -1 when there is none below `root` (or, for a folder outside it, below "/"), or it is not hex.
int usbVendorOf(const fs::path& tty_dir, const fs::path& root) {
  for (fs::path dir = tty_dir; dir != root && dir.has_relative_path(); dir = dir.parent_path()) {
    std::ifstream in(dir / "idVendor");
    if (!in) continue;
    std::string text;
    in >> text;
    char* end = nullptr;
    const long id = std::strtol(text.c_str(), &end, 16);
    if (text.empty() || end == text.c_str() || *end != '\0' || id < 0 || id > 0xffff) return -1;
    return int(id);
  }
  return -1;
}

// ttyACM2 before ttyACM10: the name without its trailing digits, then the number.
bool naturalLess(const std::string& a, const std::string& b) {
  auto split = [](const std::string& s) {
    size_t digits = s.size();
    while (digits > 0 && s[digits - 1] >= '0' && s[digits - 1] <= '9') --digits;
    const std::string number = s.substr(digits);
    return std::make_pair(s.substr(0, digits), number.size() > 9 ? ~0UL : number.empty() ? 0UL : std::stoul(number));
  };
  const auto sa = split(a), sb = split(b);
  return sa != sb ? sa < sb : a < b;
}

}  // namespace

std::vector<std::string> touchSerialNodes(const std::string& sysfs_root, const std::string& dev_root) {
  std::error_code ec;
  const fs::path root = fs::weakly_canonical(sysfs_root, ec);
  if (ec) return {};
  std::vector<std::string> names;
  for (const fs::directory_entry& entry : fs::directory_iterator(root / "class" / "tty", ec)) {
    // Each entry is a link to the tty's folder among the devices; a tty with no USB ancestor
    // (a virtual console, a UART) is not a Touch.
    std::error_code resolved;
    const fs::path dir = fs::canonical(entry.path(), resolved);
    if (resolved) continue;
    if (usbVendorOf(dir, root) == kTouchUsbVendorId) names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end(), naturalLess);
  std::vector<std::string> nodes;
  for (const std::string& name : names) nodes.push_back((fs::path(dev_root) / name).string());
  return nodes;
}

std::string touchSerialPermissionProblem(const std::string& sysfs_root, const std::string& dev_root) {
  for (const std::string& node : touchSerialNodes(sysfs_root, dev_root)) {
    // The effective ids decide an open, so they decide here too (AT_EACCESS), as for the pedal.
    if (::faccessat(AT_FDCWD, node.c_str(), R_OK | W_OK, AT_EACCESS) == 0) continue;
    if (errno == EACCES) return permissionAdvice(node);
  }
  return {};
}

}  // namespace dentsim::devices
