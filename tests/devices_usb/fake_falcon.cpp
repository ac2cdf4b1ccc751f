// FakeFalcon: the usbdevfs ioctls of a Falcon's FTDI answered inside the test process (see fake_falcon.h).
#include "fake_falcon.h"

#include <linux/ioctl.h>
#include <linux/usbdevice_fs.h>

#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstring>

namespace dentsim::devices::testing {

namespace {

// Device descriptor (FTDI 0403:cb48, bcdDevice 6.00), one configuration with one vendor interface
// and the two bulk endpoints 0x81 and 0x02 of 64 bytes.
constexpr const char* kDescriptors =
    "120100020000000803" "0448cb0006010203" "01"  // device
    "09022000010100802d"                        // configuration
    "09040000" "02" "ffffff" "02"               // interface 0: two endpoints, vendor class
    "07058102400000"                            // bulk IN 0x81, 64 bytes
    "07050202400000";                           // bulk OUT 0x02, 64 bytes

// The FTDI's modem status: CTS/DSR set, transmitter empty.
constexpr uint8_t kModem0 = 0x31, kModem1 = 0x60;

}  // namespace

FakeFalcon::FakeFalcon(UMockdevTestbed* testbed, int port, int devnum) : testbed_(testbed) {
  char node[64];
  std::snprintf(node, sizeof node, "/dev/bus/usb/001/%03d", devnum);
  node_ = node;
  handler_ = umockdev_ioctl_base_new();
  g_signal_connect_after(handler_, "handle-ioctl", G_CALLBACK(&FakeFalcon::onIoctlThunk), this);
  umockdev_testbed_attach_ioctl(testbed_, node, handler_, nullptr);
  char description[1024];
  std::snprintf(description, sizeof description,
                "P: /devices/pci0000:00/0000:00:14.0/usb1/1-%d\n"
                "N: bus/usb/001/%03d\n"
                "E: SUBSYSTEM=usb\n"
                "E: DEVTYPE=usb_device\n"
                "E: DRIVER=usb\n"
                "E: BUSNUM=001\n"
                "E: DEVNUM=%03d\n"
                "E: DEVNAME=/dev/bus/usb/001/%03d\n"
                "A: busnum=1\\n\n"
                "A: devnum=%d\\n\n"
                "A: bConfigurationValue=1\\n\n"
                "A: speed=12\\n\n"
                "A: idVendor=0403\\n\n"
                "A: idProduct=cb48\\n\n"
                "H: descriptors=%s\n",
                port, devnum, devnum, devnum, devnum, kDescriptors);
  umockdev_testbed_add_from_string(testbed_, description, nullptr);
}

FakeFalcon::~FakeFalcon() {
  umockdev_testbed_detach_ioctl(testbed_, node_.c_str(), nullptr);
  std::lock_guard lock(mutex_);
  for (auto* list : {&pending_in_, &pending_out_, &done_})
    for (Urb& u : *list) {
      g_object_unref(u.buffer);
      g_object_unref(u.urb);
    }
  g_object_unref(handler_);
}

// ---- state ----
void FakeFalcon::setFirmwareRunning(bool on) { std::lock_guard l(mutex_); firmware_ = on; }
void FakeFalcon::setExpectedImage(std::vector<uint8_t> image) { std::lock_guard l(mutex_); expected_image_ = std::move(image); }
void FakeFalcon::setEncoders(int16_t a, int16_t b, int16_t c) {
  std::lock_guard l(mutex_);
  encoders_[0] = a; encoders_[1] = b; encoders_[2] = c;
}
void FakeFalcon::setHomed(uint8_t bits) { std::lock_guard l(mutex_); homed_ = bits; }
void FakeFalcon::setStall(bool on) { std::lock_guard l(mutex_); stall_ = on; }
void FakeFalcon::setHoldOut(bool on) { std::lock_guard l(mutex_); hold_out_ = on; }
void FakeFalcon::setGone(bool on) {
  std::lock_guard l(mutex_);
  gone_ = on;
  if (!on) return;
  // Unplugged: everything in flight ends as the kernel ends it, with -ESHUTDOWN.
  for (auto* list : {&pending_in_, &pending_out_})
    while (!list->empty()) {
      Urb u = list->front();
      list->pop_front();
      u.status = -ESHUTDOWN;
      u.actual = 0;
      done_.push_back(u);
    }
  // A replugged Falcon comes back without firmware.
  firmware_ = greeted_ = loading_ = false;
  in_data_.clear();
}

std::vector<ControlSetup> FakeFalcon::controls() const { std::lock_guard l(mutex_); return controls_; }
std::vector<std::string> FakeFalcon::commands() const { std::lock_guard l(mutex_); return commands_; }
std::vector<uint8_t> FakeFalcon::image() const { std::lock_guard l(mutex_); return image_; }
bool FakeFalcon::firmwareRunning() const { std::lock_guard l(mutex_); return firmware_; }
int FakeFalcon::claims() const { std::lock_guard l(mutex_); return claims_; }
size_t FakeFalcon::commandCount() const { std::lock_guard l(mutex_); return commands_.size(); }
std::string FakeFalcon::lastCommand() const {
  std::lock_guard l(mutex_);
  return commands_.empty() ? std::string() : commands_.back();
}
void FakeFalcon::clearRecords() {
  std::lock_guard l(mutex_);
  controls_.clear();
  commands_.clear();
}

// ---- the firmware's side of the protocol ----
// '<', encoders as nibbles least significant first, 'A' + (homed << 4 | grip), 'A', '>'.
std::string FakeFalcon::replyPacket() const {
  std::string p = "<";
  for (int16_t e : encoders_) {
    const auto bits = static_cast<uint16_t>(e);
    for (int k = 0; k < 4; ++k) p += static_cast<char>('A' + ((bits >> (4 * k)) & 0xF));
  }
  p += static_cast<char>('A' + (homed_ << 4));
  p += "A>";
  return p;
}

void FakeFalcon::queueIn(const std::string& bytes) { in_data_ += bytes; }

void FakeFalcon::onBulkOut(const uint8_t* data, size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  if (firmware_) {
    if (baud_ != 0x0002) return;  // the firmware talks at 1.5 Mbaud only
    partial_command_ += bytes;
    while (partial_command_.size() >= 16) {
      commands_.push_back(partial_command_.substr(0, 16));
      partial_command_.erase(0, 16);
      if (!stall_) queueIn(replyPacket());
    }
    return;
  }
  if (loading_) {  // the boot loader echoes the image
    image_.insert(image_.end(), data, data + size);
    queueIn(bytes);
    if (!expected_image_.empty() && image_.size() >= expected_image_.size()) {
      loading_ = false;
      firmware_ = image_ == expected_image_;
    }
    return;
  }
  if (baud_ == 0x4138 && bytes == std::string("\x0a\x43\x0d", 3)) {
    greeted_ = true;
    queueIn(std::string("\x0a\x44\x2c\x0d", 4));
  } else if (greeted_ && baud_ == 0x0015 && bytes == "A") {
    loading_ = true;
    image_.clear();
    queueIn("A");
  }
}

void FakeFalcon::completeReadyIn() {
  while (!in_data_.empty() && !pending_in_.empty()) {
    Urb u = pending_in_.front();
    pending_in_.pop_front();
    auto* urb = static_cast<usbdevfs_urb*>(static_cast<void*>(u.urb->data));
    auto* buf = static_cast<uint8_t*>(u.buffer->data);
    const size_t room = urb->buffer_length > 2 ? static_cast<size_t>(urb->buffer_length) - 2 : 0;
    const size_t n = in_data_.size() < room ? in_data_.size() : room;
    buf[0] = kModem0;
    buf[1] = kModem1;
    std::memcpy(buf + 2, in_data_.data(), n);
    in_data_.erase(0, n);
    u.actual = static_cast<int>(n + 2);
    u.status = 0;
    done_.push_back(u);
  }
}

// ---- usbdevfs ----
gboolean FakeFalcon::onIoctlThunk(UMockdevIoctlBase*, UMockdevIoctlClient* client, gpointer self) {
  return static_cast<FakeFalcon*>(self)->onIoctl(client);
}

gboolean FakeFalcon::onIoctl(UMockdevIoctlClient* client) {
  const gulong request = umockdev_ioctl_client_get_request(client);
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
  std::lock_guard lock(mutex_);
  if (gone_ && !(request == USBDEVFS_REAPURB || request == USBDEVFS_REAPURBNDELAY)) {
    umockdev_ioctl_client_complete(client, -1, ENODEV);
    return TRUE;
  }
  switch (request) {
    case USBDEVFS_GET_CAPABILITIES: {
      UMockdevIoctlData* d = umockdev_ioctl_data_resolve(arg, 0, sizeof(guint32), nullptr);
      *static_cast<guint32*>(static_cast<void*>(d->data)) = USBDEVFS_CAP_NO_PACKET_SIZE_LIM | USBDEVFS_CAP_REAP_AFTER_DISCONNECT;
      g_object_unref(d);
      umockdev_ioctl_client_complete(client, 0, 0);
      return TRUE;
    }
    case USBDEVFS_CLAIMINTERFACE:
      ++claims_;
      umockdev_ioctl_client_complete(client, 0, 0);
      return TRUE;
    case USBDEVFS_RELEASEINTERFACE:
    case USBDEVFS_CLEAR_HALT:
      umockdev_ioctl_client_complete(client, 0, 0);
      return TRUE;
    case USBDEVFS_GETDRIVER:  // no kernel driver bound
      umockdev_ioctl_client_complete(client, -1, ENODATA);
      return TRUE;
    case USBDEVFS_SUBMITURB: submit(client); return TRUE;
    case USBDEVFS_REAPURB:
    case USBDEVFS_REAPURBNDELAY: reap(client); return TRUE;
    case USBDEVFS_DISCARDURB: discard(client); return TRUE;
    default:
      umockdev_ioctl_client_complete(client, -1, ENOTTY);
      return TRUE;
  }
}

void FakeFalcon::submit(UMockdevIoctlClient* client) {
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
  Urb u;
  u.urb = umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_urb), nullptr);
  auto* urb = static_cast<usbdevfs_urb*>(static_cast<void*>(u.urb->data));
  u.buffer = umockdev_ioctl_data_resolve(u.urb, offsetof(usbdevfs_urb, buffer), static_cast<gsize>(urb->buffer_length), nullptr);
  const auto* buf = static_cast<const uint8_t*>(u.buffer->data);
  if (urb->type == USBDEVFS_URB_TYPE_CONTROL) {
    ControlSetup s{buf[0], buf[1], static_cast<uint16_t>(buf[2] | buf[3] << 8), static_cast<uint16_t>(buf[4] | buf[5] << 8)};
    controls_.push_back(s);
    if (s.request_type == 0x40 && s.request == 0x03) baud_ = s.value;
    u.actual = 0;
    done_.push_back(u);
  } else if (urb->endpoint == 0x02) {
    if (hold_out_) {
      pending_out_.push_back(u);
    } else {
      onBulkOut(buf, static_cast<size_t>(urb->buffer_length));
      u.actual = urb->buffer_length;
      done_.push_back(u);
      completeReadyIn();
    }
  } else if (urb->endpoint == 0x81) {
    pending_in_.push_back(u);
    completeReadyIn();
  } else {
    g_object_unref(u.buffer);
    g_object_unref(u.urb);
    umockdev_ioctl_client_complete(client, -1, EINVAL);
    return;
  }
  umockdev_ioctl_client_complete(client, 0, 0);
}

void FakeFalcon::reap(UMockdevIoctlClient* client) {
  if (done_.empty()) {
    umockdev_ioctl_client_complete(client, -1, gone_ ? ENODEV : EAGAIN);
    return;
  }
  Urb u = done_.front();
  done_.pop_front();
  auto* urb = static_cast<usbdevfs_urb*>(static_cast<void*>(u.urb->data));
  urb->status = u.status;
  urb->actual_length = u.actual;
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
  UMockdevIoctlData* slot = umockdev_ioctl_data_resolve(arg, 0, sizeof(gpointer), nullptr);
  umockdev_ioctl_data_set_ptr(slot, 0, u.urb);
  umockdev_ioctl_client_complete(client, 0, 0);
  g_object_unref(slot);
  g_object_unref(u.buffer);
  g_object_unref(u.urb);
}

void FakeFalcon::discard(UMockdevIoctlClient* client) {
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
  const auto address = reinterpret_cast<gulong>(*static_cast<void**>(static_cast<void*>(arg->data)));
  for (auto* list : {&pending_in_, &pending_out_})
    for (auto it = list->begin(); it != list->end(); ++it)
      if (it->urb->client_addr == address) {
        Urb u = *it;
        list->erase(it);
        u.status = -ENOENT;
        u.actual = 0;
        done_.push_back(u);
        umockdev_ioctl_client_complete(client, 0, 0);
        return;
      }
  umockdev_ioctl_client_complete(client, -1, EINVAL);
}

}  // namespace dentsim::devices::testing
