// The HID transport a pedal reads through: enumerate, open by path, read with a timeout, close (the destructor); hidapi or a fake.
//
// An interface, so that the pedal's reader thread, unplug and replug are tested against a fake
// transport without hardware; makeHidapiTransport() is the real one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace dentsim::devices {

struct HidDeviceInfo {
  std::string path;              // "/dev/hidraw3"
  uint16_t vendor_id = 0;
  uint16_t product_id = 0;
  std::string serial;
  std::string manufacturer;
  std::string product;
  uint16_t usage_page = 0;       // of the top-level collection
  uint16_t usage = 0;
  int interface_number = -1;
  bool permitted = true;         // the node may be opened for reading and writing by this user
};

// One open device. read() and the destructor are called from one thread at a time.
class HidConnection {
 public:
  virtual ~HidConnection() = default;
  // Waits at most timeout_ms for one input report: its size (> 0; only `capacity` bytes are stored),
  // 0 when none came, < 0 when the device failed or is gone (error() says why).
  virtual int read(uint8_t* buffer, size_t capacity, int timeout_ms) = 0;
  virtual std::string error() const = 0;
};

enum class HidOpenError : uint8_t { None, NotFound, PermissionDenied, Failed };

struct HidOpenResult {
  std::unique_ptr<HidConnection> connection;  // set when error is None
  HidOpenError error = HidOpenError::None;
  std::string message;                        // the system's words for the error
};

class HidTransport {
 public:
  virtual ~HidTransport() = default;
  virtual std::vector<HidDeviceInfo> enumerate() = 0;
  virtual HidOpenResult open(const std::string& path) = 0;
  // The node's HID report descriptor; empty where it cannot be read.
  virtual std::vector<uint8_t> reportDescriptor(const std::string& path) = 0;
};

// hidapi over hidraw, reading report descriptors from sysfs.
std::shared_ptr<HidTransport> makeHidapiTransport();

}  // namespace dentsim::devices
