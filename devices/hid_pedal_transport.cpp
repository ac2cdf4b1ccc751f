// The hidapi transport for HID pedals: enumerate, open and read hidraw nodes, and read report descriptors from sysfs.
//
// Kept apart from the pedal so that the pedal's logic is tested against a fake transport and
// only this file links hidapi.
#include "devices/hid_pedal_transport.h"

#include <hidapi.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

namespace dentsim::devices {

namespace {

// hidapi speaks wchar_t (UTF-32 on Linux); the rest of dentsim speaks UTF-8.
std::string toUtf8(const wchar_t* text) {
  std::string out;
  if (text == nullptr) return out;
  for (; *text != 0; ++text) {
    const auto c = static_cast<uint32_t>(*text);
    if (c < 0x80) {
      out += static_cast<char>(c);
    } else if (c < 0x800) {
      out += static_cast<char>(0xC0 | (c >> 6));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else if (c < 0x10000) {
      out += static_cast<char>(0xE0 | (c >> 12));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    } else if (c < 0x110000) {
      out += static_cast<char>(0xF0 | (c >> 18));
      out += static_cast<char>(0x80 | ((c >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (c & 0x3F));
    }
  }
  return out;
}

class HidapiConnection final : public HidConnection {
 public:
  explicit HidapiConnection(hid_device* device) : device_(device) {}
  ~HidapiConnection() override { hid_close(device_); }
  HidapiConnection(const HidapiConnection&) = delete;
  HidapiConnection& operator=(const HidapiConnection&) = delete;

  int read(uint8_t* buffer, size_t capacity, int timeout_ms) override {
    return hid_read_timeout(device_, buffer, capacity, timeout_ms);
  }
  std::string error() const override {
    const std::string text = toUtf8(hid_error(device_));
    return text.empty() ? "read failed" : text;
  }

 private:
  hid_device* device_;
};

class HidapiTransport final : public HidTransport {
 public:
  HidapiTransport() { hid_init(); }

  std::vector<HidDeviceInfo> enumerate() override {
    std::vector<HidDeviceInfo> list;
    hid_device_info* all = hid_enumerate(0, 0);
    for (const hid_device_info* d = all; d != nullptr; d = d->next) {
      HidDeviceInfo info;
      info.path = d->path != nullptr ? d->path : "";
      info.vendor_id = d->vendor_id;
      info.product_id = d->product_id;
      info.serial = toUtf8(d->serial_number);
      info.manufacturer = toUtf8(d->manufacturer_string);
      info.product = toUtf8(d->product_string);
      info.usage_page = d->usage_page;
      info.usage = d->usage;
      info.interface_number = d->interface_number;
      info.permitted = ::access(info.path.c_str(), R_OK | W_OK) == 0;
      list.push_back(std::move(info));
    }
    hid_free_enumeration(all);
    return list;
  }

  HidOpenResult open(const std::string& path) override {
    HidOpenResult result;
    // Ask the file system first: hidapi's own message does not say which way the open failed.
    if (::access(path.c_str(), F_OK) != 0) {
      result.error = HidOpenError::NotFound;
      result.message = path + ": " + std::strerror(errno);
      return result;
    }
    if (::access(path.c_str(), R_OK | W_OK) != 0 && errno == EACCES) {
      result.error = HidOpenError::PermissionDenied;
      result.message = path + ": " + std::strerror(EACCES);
      return result;
    }
    hid_device* device = hid_open_path(path.c_str());
    if (device == nullptr) {
      const int saved = errno;
      result.error = saved == EACCES ? HidOpenError::PermissionDenied
                     : saved == ENOENT || saved == ENODEV ? HidOpenError::NotFound
                                                          : HidOpenError::Failed;
      result.message = toUtf8(hid_error(nullptr));
      if (result.message.empty()) result.message = path + ": " + std::strerror(saved);
      return result;
    }
    result.connection = std::make_unique<HidapiConnection>(device);
    return result;
  }

  std::vector<uint8_t> reportDescriptor(const std::string& path) override {
    // hidapi 0.13 has no call for it; the kernel exposes it beside the hidraw node.
    const size_t slash = path.rfind('/');
    const std::string node = slash == std::string::npos ? path : path.substr(slash + 1);
    if (node.rfind("hidraw", 0) != 0) return {};
    std::ifstream file("/sys/class/hidraw/" + node + "/device/report_descriptor", std::ios::binary);
    if (!file) return {};
    constexpr size_t kMaxDescriptorBytes = 4096;  // the kernel's HID_MAX_DESCRIPTOR_SIZE
    std::vector<uint8_t> bytes(kMaxDescriptorBytes);
    file.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    bytes.resize(static_cast<size_t>(file.gcount()));
    return bytes;
  }
};

}  // namespace

std::shared_ptr<HidTransport> makeHidapiTransport() { return std::make_shared<HidapiTransport>(); }

}  // namespace dentsim::devices
