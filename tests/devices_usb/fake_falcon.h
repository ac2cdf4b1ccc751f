// FakeFalcon: a Falcon's FTDI at the usbdevfs level inside a umockdev testbed, checking the bytes the driver sends.
//
// The test process is the device: umockdev hands every ioctl on /dev/bus/usb/BBB/DDD to
// onIoctl() (on umockdev's worker thread). Control URBs are recorded; bulk OUT data drives a small
// model of the boot loader and of the Novint firmware, whose answers go back through bulk IN URBs
// with the FTDI's two modem status bytes in front. Everything the driver sent is kept for the test
// to compare with bytes written out by hand. Behaviours: stall (no answers), hold_out (OUT never
// completes), gone (unplugged: in-flight URBs end with -ESHUTDOWN, every ioctl fails with ENODEV).
#pragma once

#include <umockdev.h>

#include <cstdint>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

namespace dentsim::devices::testing {

struct ControlSetup {
  uint8_t request_type, request;
  uint16_t value, index;
  bool operator==(const ControlSetup&) const = default;
};

class FakeFalcon {
 public:
  // Adds the device at sysfs name "1-<port>", node /dev/bus/usb/001/<devnum>.
  FakeFalcon(UMockdevTestbed* testbed, int port, int devnum);
  ~FakeFalcon();
  FakeFalcon(const FakeFalcon&) = delete;
  FakeFalcon& operator=(const FakeFalcon&) = delete;

  // ---- the device's state (any thread) ----
  void setFirmwareRunning(bool on);
  void setExpectedImage(std::vector<uint8_t> image);  // what a load must deliver
  void setEncoders(int16_t a, int16_t b, int16_t c);
  void setHomed(uint8_t bits);
  void setStall(bool on);
  void setHoldOut(bool on);
  void setGone(bool on);

  // ---- what the driver did ----
  std::vector<ControlSetup> controls() const;
  std::vector<std::string> commands() const;  // the 16-byte packets the running firmware received
  std::vector<uint8_t> image() const;          // bytes the boot loader received
  bool firmwareRunning() const;
  int claims() const;
  size_t commandCount() const;
  std::string lastCommand() const;
  void clearRecords();

  const std::string& node() const { return node_; }

 private:
  static gboolean onIoctlThunk(UMockdevIoctlBase* base, UMockdevIoctlClient* client, gpointer self);
  gboolean onIoctl(UMockdevIoctlClient* client);
  void submit(UMockdevIoctlClient* client);
  void reap(UMockdevIoctlClient* client);
  void discard(UMockdevIoctlClient* client);
  void onBulkOut(const uint8_t* data, size_t size);
  void queueIn(const std::string& bytes);
  void completeReadyIn();
  std::string replyPacket() const;

  struct Urb {
    UMockdevIoctlData* urb = nullptr;     // our reference to the client's struct usbdevfs_urb
    UMockdevIoctlData* buffer = nullptr;  // its data buffer
    int status = 0;
    int actual = 0;
  };

  UMockdevTestbed* testbed_;
  UMockdevIoctlBase* handler_;
  std::string node_;
  mutable std::mutex mutex_;
  std::deque<Urb> pending_in_;  // IN URBs waiting for data
  std::deque<Urb> pending_out_; // OUT URBs held (hold_out)
  std::deque<Urb> done_;        // ready to be reaped
  std::string in_data_;         // bytes the device has to send
  std::vector<ControlSetup> controls_;
  std::vector<std::string> commands_;
  std::string partial_command_;
  std::vector<uint8_t> image_;
  std::vector<uint8_t> expected_image_;
  uint16_t baud_ = 0;
  bool firmware_ = false;
  bool greeted_ = false;
  bool loading_ = false;
  bool stall_ = false;
  bool hold_out_ = false;
  bool gone_ = false;
  int claims_ = 0;
  int16_t encoders_[3] = {0, 0, 0};
  uint8_t homed_ = 0;
};

}  // namespace dentsim::devices::testing
