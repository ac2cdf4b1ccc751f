// The 3D Systems Touch's serial nodes: finds the /dev/ttyACM* nodes a Touch or Touch X owns, and says which one this user may not open.
//
// On Linux, OpenHaptics' Touch device driver talks to the pen over a USB serial (CDC ACM) node,
// /dev/ttyACMn. When that node is not open to the user, hdInitDevice only fails, without saying
// why; the plug-in asks touchSerialPermissionProblem() for the reason then. The tty's USB parent
// in sysfs carries the vendor id, so a Touch is told from any other ACM device (a modem, a board).
// Both roots are parameters so that the tests can point them at a fake tree.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace dentsim::devices {

// 3D Systems' USB vendor id, which its Touch pens report (2988:0302 and 2988:0304 have been seen:
// the product differs by model, so only the vendor is matched).
inline constexpr uint16_t kTouchUsbVendorId = 0x2988;

// The device nodes (dev_root + "/" + NAME) of every tty in sysfs_root/class/tty whose nearest USB
// ancestor has idVendor kTouchUsbVendorId, in natural order (ttyACM2 before ttyACM10), whether or
// not the node exists. Empty when there is no such tty or no sysfs_root/class/tty.
std::vector<std::string> touchSerialNodes(const std::string& sysfs_root = "/sys", const std::string& dev_root = "/dev");

// For a pen that HDAPI could not open: the permission line (core/permission_advice.h) for the
// first Touch node that exists but that this process may not read and write; empty when every
// Touch node that exists opens, or none is plugged in. It only checks access, and opens nothing.
std::string touchSerialPermissionProblem(const std::string& sysfs_root = "/sys", const std::string& dev_root = "/dev");

}  // namespace dentsim::devices
