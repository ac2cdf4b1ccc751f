// Tests for the HID foot pedal: report decoding, descriptors, spec parsing, and the reader thread against a fake HID device.
#include "devices/hid_pedal.h"

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <future>
#include <mutex>
#include <thread>

namespace dentsim::devices {
namespace {

using namespace std::chrono_literals;

// ---- a fake HID device: scripted reports, unplug and replug, reads that can be held ----

class FakeHid {
 public:
  explicit FakeHid(HidDeviceInfo info) : info_(std::move(info)) {}

  HidDeviceInfo info() const {
    std::lock_guard lock(mutex_);
    return info_;
  }
  bool plugged() const {
    std::lock_guard lock(mutex_);
    return plugged_;
  }
  uint64_t generation() const {
    std::lock_guard lock(mutex_);
    return generation_;
  }
  void setPermitted(bool permitted) {
    std::lock_guard lock(mutex_);
    info_.permitted = permitted;
  }

  void push(std::vector<uint8_t> report) {
    {
      std::lock_guard lock(mutex_);
      queue_.push_back(std::move(report));
      idle_ = false;
    }
    cv_.notify_all();
  }
  void unplug() {
    {
      std::lock_guard lock(mutex_);
      plugged_ = false;
      queue_.clear();
    }
    cv_.notify_all();
  }
  // Back, perhaps under another hidraw node; connections from before stay dead.
  void replug(const std::string& path) {
    {
      std::lock_guard lock(mutex_);
      plugged_ = true;
      info_.path = path;
      ++generation_;
    }
    cv_.notify_all();
  }
  // While held, a read that starts blocks past its timeout until released.
  void hold(bool on) {
    {
      std::lock_guard lock(mutex_);
      hold_ = on;
    }
    cv_.notify_all();
  }
  bool readerHeld() const {
    std::lock_guard lock(mutex_);
    return held_;
  }
  // Every report pushed has been read and decoded: the reader came back for more and found none.
  bool readerIdle() const {
    std::lock_guard lock(mutex_);
    return idle_ && queue_.empty();
  }

  int read(uint64_t generation, uint8_t* buffer, size_t capacity, int timeout_ms) {
    std::unique_lock lock(mutex_);
    const auto dead = [&] { return !plugged_ || generation_ != generation; };
    if (hold_) {
      held_ = true;
      cv_.wait(lock, [&] { return !hold_ || dead(); });
      held_ = false;
    }
    if (queue_.empty()) idle_ = true;
    cv_.wait_for(lock, std::chrono::milliseconds(timeout_ms), [&] { return !queue_.empty() || dead(); });
    if (dead()) return -1;
    if (queue_.empty()) return 0;
    std::vector<uint8_t> report = std::move(queue_.front());
    queue_.pop_front();
    idle_ = false;
    std::copy_n(report.begin(), std::min(report.size(), capacity), buffer);
    return static_cast<int>(report.size());
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  HidDeviceInfo info_;
  std::deque<std::vector<uint8_t>> queue_;
  bool plugged_ = true;
  uint64_t generation_ = 0;
  bool hold_ = false;
  bool held_ = false;
  bool idle_ = false;
};

class FakeConnection final : public HidConnection {
 public:
  FakeConnection(std::shared_ptr<FakeHid> device, uint64_t generation)
      : device_(std::move(device)), generation_(generation) {}
  int read(uint8_t* buffer, size_t capacity, int timeout_ms) override {
    return device_->read(generation_, buffer, capacity, timeout_ms);
  }
  std::string error() const override { return "No such device"; }

 private:
  std::shared_ptr<FakeHid> device_;
  uint64_t generation_;
};

class FakeTransport final : public HidTransport {
 public:
  std::shared_ptr<FakeHid> add(HidDeviceInfo info, std::vector<uint8_t> descriptor = {}) {
    auto device = std::make_shared<FakeHid>(std::move(info));
    std::lock_guard lock(mutex_);
    devices_.push_back({device, std::move(descriptor)});
    return device;
  }

  std::vector<HidDeviceInfo> enumerate() override {
    std::lock_guard lock(mutex_);
    std::vector<HidDeviceInfo> list;
    for (const Entry& e : devices_) {
      if (e.device->plugged()) list.push_back(e.device->info());
    }
    return list;
  }
  HidOpenResult open(const std::string& path) override {
    std::lock_guard lock(mutex_);
    HidOpenResult result;
    for (const Entry& e : devices_) {
      const HidDeviceInfo info = e.device->info();
      if (!e.device->plugged() || info.path != path) continue;
      if (!info.permitted) {
        result.error = HidOpenError::PermissionDenied;
        result.message = path + ": Permission denied";
        return result;
      }
      result.connection = std::make_unique<FakeConnection>(e.device, e.device->generation());
      return result;
    }
    result.error = HidOpenError::NotFound;
    result.message = path + ": No such file or directory";
    return result;
  }
  std::vector<uint8_t> reportDescriptor(const std::string& path) override {
    std::lock_guard lock(mutex_);
    for (const Entry& e : devices_) {
      if (e.device->info().path == path) return e.descriptor;
    }
    return {};
  }

 private:
  struct Entry {
    std::shared_ptr<FakeHid> device;
    std::vector<uint8_t> descriptor;
  };
  std::mutex mutex_;
  std::vector<Entry> devices_;
};

HidDeviceInfo deviceInfo(const std::string& path, uint16_t vid, uint16_t pid, const std::string& product,
                         uint16_t usage_page = 0x01, uint16_t usage = 0x04, int interface_number = 0) {
  HidDeviceInfo info;
  info.path = path;
  info.vendor_id = vid;
  info.product_id = pid;
  info.manufacturer = "Acme";
  info.product = product;
  info.serial = "SN1";
  info.usage_page = usage_page;
  info.usage = usage;
  info.interface_number = interface_number;
  return info;
}

// Polls until pred() holds or the deadline passes; the reader thread needs no fixed sleeps. The
// deadline only bounds how long a failure takes to show: a loaded machine may leave the reader
// unscheduled for a long while, so it is far longer than any read here takes.
template <class Pred>
bool eventually(Pred pred, std::chrono::milliseconds deadline = 10s) {
  const auto end = std::chrono::steady_clock::now() + deadline;
  while (!pred()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(200us);
  }
  return true;
}

std::unique_ptr<FootPedal> makePedal(const std::string& spec, std::shared_ptr<FakeTransport> transport,
                                     HidPedalOptions options = {0, 0}) {
  if (options.read_timeout_ms == 0) options.read_timeout_ms = 10;
  auto pedal = makeHidPedal(spec, std::move(transport), options);
  EXPECT_TRUE(pedal.ok()) << (pedal.ok() ? "" : pedal.message());
  return std::move(pedal).value();
}

PedalLayout axisLayout(int byte, int bit, int bits, int64_t raw_min, int64_t raw_max) {
  PedalLayout l;
  l.input = PedalInput::Axis;
  l.byte = byte;
  l.bit = bit;
  l.bits = bits;
  l.raw_min = raw_min;
  l.raw_max = raw_max;
  return l;
}

std::optional<double> decode(const PedalLayout& l, std::vector<uint8_t> report) { return decodePedalReport(l, report); }

// ---- decoding ----

TEST(HidPedalDecode, SwitchBitIsExactlyOneOrZero) {
  PedalLayout l;
  l.input = PedalInput::Button;
  l.byte = 1;
  l.button_mask = 1u << 3;
  EXPECT_EQ(decode(l, {0x00, 0x08}), 1.0);
  EXPECT_EQ(decode(l, {0xFF, 0xF7}), 0.0);  // every other bit set, ours clear
  EXPECT_EQ(decode(l, {0x00, 0xFF}), 1.0);
}

TEST(HidPedalDecode, EightBitAxisMinMidMax) {
  const PedalLayout l = axisLayout(1, 0, 8, 0, 255);
  EXPECT_EQ(decode(l, {0x00, 0}), 0.0);
  EXPECT_EQ(decode(l, {0x00, 255}), 1.0);
  // 128/255 is the nearest raw value to half way: within one raw step of 0.5.
  EXPECT_NEAR(*decode(l, {0x00, 128}), 0.5, 1.0 / 255.0);
  EXPECT_DOUBLE_EQ(*decode(l, {0x00, 128}), 128.0 / 255.0);
}

TEST(HidPedalDecode, TwelveBitAxisAtABitOffsetIsLittleEndian) {
  // 12 bits from bit 4 of byte 1: raw bits 0-3 in byte 1's high nibble, bits 4-11 in byte 2.
  const PedalLayout l = axisLayout(1, 4, 12, 0, 4095);
  EXPECT_EQ(decode(l, {0x00, 0xF0, 0xFF}), 1.0);
  EXPECT_EQ(decode(l, {0xAA, 0x0F, 0x00}), 0.0);  // the low nibble belongs to someone else
  // raw 0x801 = 2049: nibble 1 in byte 1's high half, 0x80 in byte 2.
  EXPECT_DOUBLE_EQ(*decode(l, {0x00, 0x10, 0x80}), 2049.0 / 4095.0);
}

TEST(HidPedalDecode, SignedAxisAndReversedRange) {
  const PedalLayout s = axisLayout(0, 0, 16, -32768, 32767);
  EXPECT_EQ(decode(s, {0x00, 0x80}), 0.0);  // -32768
  EXPECT_EQ(decode(s, {0xFF, 0x7F}), 1.0);  // 32767
  EXPECT_DOUBLE_EQ(*decode(s, {0x00, 0x00}), 32768.0 / 65535.0);
  // A pedal whose raw value falls as it is pressed: MIN above MAX.
  const PedalLayout r = axisLayout(0, 0, 8, 200, 0);
  EXPECT_EQ(decode(r, {200}), 0.0);
  EXPECT_EQ(decode(r, {0}), 1.0);
  EXPECT_EQ(decode(r, {255}), 0.0);  // outside the range: clamped
}

TEST(HidPedalDecode, InvertedAxisAndDeadBand) {
  PedalLayout l = axisLayout(0, 0, 8, 0, 255);
  l.invert = true;
  EXPECT_EQ(decode(l, {0}), 1.0);
  EXPECT_EQ(decode(l, {255}), 0.0);
  EXPECT_DOUBLE_EQ(*decode(l, {55}), 200.0 / 255.0);

  PedalLayout d = axisLayout(0, 0, 8, 0, 255);
  d.dead_band = 0.02;                 // 0.02 * 255 = 5.1 raw steps
  EXPECT_EQ(decode(d, {5}), 0.0);     // 5/255 = 0.0196: resting
  EXPECT_DOUBLE_EQ(*decode(d, {6}), 6.0 / 255.0);  // 0.0235: pressed
  // The dead band sits at rest after inversion too.
  d.invert = true;
  EXPECT_EQ(decode(d, {250}), 0.0);
  EXPECT_NEAR(*decode(d, {249}), 6.0 / 255.0, 1e-12);  // 1 - 249/255
}

TEST(HidPedalDecode, KeyboardFootSwitch) {
  PedalLayout any;
  any.input = PedalInput::Key;
  EXPECT_EQ(decode(any, {0, 0, 0x05, 0, 0, 0, 0, 0}), 1.0);  // B down
  EXPECT_EQ(decode(any, {0, 0, 0, 0, 0, 0, 0, 0}), 0.0);
  EXPECT_EQ(decode(any, {0x02, 0, 0, 0, 0, 0, 0, 0}), 1.0);  // left shift only
  EXPECT_EQ(decode(any, {0, 0, 0x01, 0x01, 0x01, 0x01, 0x01, 0x01}), 0.0);  // rollover error, no key
  PedalLayout b = any;
  b.key_code = 0x05;
  EXPECT_EQ(decode(b, {0, 0, 0x06, 0x05, 0, 0, 0, 0}), 1.0);
  EXPECT_EQ(decode(b, {0x02, 0, 0x06, 0, 0, 0, 0, 0}), 0.0);
}

TEST(HidPedalDecode, ShortOrForeignReportsAreIgnored) {
  const PedalLayout axis = axisLayout(1, 4, 12, 0, 4095);
  EXPECT_FALSE(decode(axis, {}));
  EXPECT_FALSE(decode(axis, {0x00}));
  EXPECT_FALSE(decode(axis, {0x00, 0xF0}));  // needs bits 12..23: three bytes
  PedalLayout button;
  button.byte = 4;
  EXPECT_FALSE(decode(button, {1, 2, 3, 4}));
  PedalLayout key;
  key.input = PedalInput::Key;
  EXPECT_FALSE(decode(key, {0, 0, 5}));
  PedalLayout numbered = axisLayout(1, 0, 8, 0, 255);
  numbered.report_id = 2;
  EXPECT_FALSE(decode(numbered, {1, 255}));
  EXPECT_EQ(decode(numbered, {2, 255}), 1.0);
}

// ---- report descriptors ----

TEST(HidPedalDescriptor, AcceleratorAfterButtonsInANumberedReport) {
  const std::vector<uint8_t> d = {
      0x05, 0x01, 0x09, 0x04, 0xA1, 0x01,  // Generic Desktop, Joystick, Collection (Application)
      0x85, 0x03,                          // Report ID 3
      0x05, 0x09, 0x19, 0x01, 0x29, 0x02,  // Buttons 1..2
      0x15, 0x00, 0x25, 0x01, 0x75, 0x01, 0x95, 0x02, 0x81, 0x02,  // 2 x 1 bit, Input (Var)
      0x75, 0x06, 0x95, 0x01, 0x81, 0x03,  // 6 bits padding, Input (Const)
      0x05, 0x02, 0x09, 0xC4,              // Simulation Controls, Accelerator
      0x15, 0x00, 0x26, 0xFF, 0x03,        // logical 0..1023
      0x75, 0x0A, 0x95, 0x01, 0x81, 0x02,  // 1 x 10 bits, Input (Var)
      0xC0,
  };
  const std::optional<PedalLayout> l = layoutFromReportDescriptor(d);
  ASSERT_TRUE(l);
  EXPECT_EQ(l->input, PedalInput::Axis);
  EXPECT_EQ(l->report_id, 3);
  // Report id byte, then 8 bits of buttons and padding: the accelerator starts at byte 2, bit 0.
  EXPECT_EQ(l->byte, 2);
  EXPECT_EQ(l->bit, 0);
  EXPECT_EQ(l->bits, 10);
  EXPECT_EQ(l->raw_min, 0);
  EXPECT_EQ(l->raw_max, 1023);
  EXPECT_EQ(decodePedalReport(*l, std::vector<uint8_t>{3, 0x01, 0xFF, 0x03}), 1.0);
  EXPECT_DOUBLE_EQ(*decodePedalReport(*l, std::vector<uint8_t>{3, 0x00, 0x00, 0x02}), 512.0 / 1023.0);
}

TEST(HidPedalDescriptor, OneByteMaximumMeantUnsignedAndButtonOnly) {
  // Z axis, logical max written as the one-byte 0xFF with minimum 0: meant as 255.
  const std::vector<uint8_t> axis = {0x05, 0x01, 0x09, 0x04, 0xA1, 0x01, 0x09, 0x32, 0x15, 0x00, 0x25, 0xFF,
                                     0x75, 0x08, 0x95, 0x01, 0x81, 0x02, 0xC0};
  const std::optional<PedalLayout> a = layoutFromReportDescriptor(axis);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->input, PedalInput::Axis);
  EXPECT_EQ(a->report_id, -1);
  EXPECT_EQ(a->byte, 0);
  EXPECT_EQ(a->raw_max, 255);

  // Five bits of padding, then three buttons: the first is bit 5 of byte 0.
  const std::vector<uint8_t> buttons = {0x05, 0x01, 0x09, 0x04, 0xA1, 0x01, 0x75, 0x05, 0x95, 0x01, 0x81, 0x03,
                                        0x05, 0x09, 0x19, 0x01, 0x29, 0x03, 0x75, 0x01, 0x95, 0x03, 0x81, 0x02, 0xC0};
  const std::optional<PedalLayout> b = layoutFromReportDescriptor(buttons);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->input, PedalInput::Button);
  EXPECT_EQ(b->byte, 0);
  EXPECT_EQ(b->button_mask, 1u << 5);
}

TEST(HidPedalDescriptor, MalformedOrEmpty) {
  EXPECT_FALSE(layoutFromReportDescriptor({}));
  const std::vector<uint8_t> truncated = {0x05, 0x01, 0x26, 0xFF};  // a two-byte item with one byte left
  EXPECT_FALSE(layoutFromReportDescriptor(truncated));
  // A long item whose data runs past the end, after an axis that was complete.
  const std::vector<uint8_t> long_cut = {0x05, 0x01, 0x09, 0x30, 0x15, 0x00, 0x26, 0xFF, 0x00, 0x75,
                                         0x08, 0x95, 0x01, 0x81, 0x02, 0xFE, 0xFF, 0x00};
  EXPECT_FALSE(layoutFromReportDescriptor(long_cut));
  const std::vector<uint8_t> pop_empty = {0xB4};  // Pop with nothing pushed
  EXPECT_FALSE(layoutFromReportDescriptor(pop_empty));
  const std::vector<uint8_t> keyboard_only = {0x05, 0x07, 0x19, 0xE0, 0x29, 0xE7, 0x75, 0x01, 0x95, 0x08, 0x81, 0x02};
  EXPECT_FALSE(layoutFromReportDescriptor(keyboard_only));
}

// ---- spec parsing ----

TEST(HidPedalSpec, GoodSpecs) {
  auto index = parseHidPedalSpec("0");
  ASSERT_TRUE(index.ok()) << index.message();
  EXPECT_EQ(index->target, HidPedalSpec::Target::Index);
  EXPECT_EQ(index->index, 0);
  EXPECT_EQ(index->text, "hid:0");
  EXPECT_FALSE(index->layout);

  auto vp = parseHidPedalSpec("hid:0c45:7403,button=0:0");
  ASSERT_TRUE(vp.ok()) << vp.message();
  EXPECT_EQ(vp->text, "hid:0c45:7403,button=0:0");
  EXPECT_EQ(vp->target, HidPedalSpec::Target::VendorProduct);
  EXPECT_EQ(vp->vendor_id, 0x0c45);
  EXPECT_EQ(vp->product_id, 0x7403);
  ASSERT_TRUE(vp->layout);
  EXPECT_EQ(vp->layout->input, PedalInput::Button);
  EXPECT_EQ(vp->layout->byte, 0);
  EXPECT_EQ(vp->layout->button_mask, 1);

  auto path = parseHidPedalSpec("/dev/hidraw3,axis=1:8:0:255");
  ASSERT_TRUE(path.ok()) << path.message();
  EXPECT_EQ(path->target, HidPedalSpec::Target::Path);
  EXPECT_EQ(path->path, "/dev/hidraw3");
  ASSERT_TRUE(path->layout);
  EXPECT_EQ(path->layout->input, PedalInput::Axis);
  EXPECT_EQ(path->layout->byte, 1);
  EXPECT_EQ(path->layout->bits, 8);
  EXPECT_EQ(path->layout->raw_max, 255);

  auto full = parseHidPedalSpec("2,axis=2.4:12:0x10:4095,invert,deadband=0.05,report=3,serial=AB12");
  ASSERT_TRUE(full.ok()) << full.message();
  EXPECT_EQ(full->index, 2);
  EXPECT_EQ(full->layout->bit, 4);
  EXPECT_EQ(full->layout->bits, 12);
  EXPECT_EQ(full->layout->raw_min, 16);
  EXPECT_EQ(full->invert, true);
  EXPECT_DOUBLE_EQ(*full->dead_band, 0.05);
  EXPECT_EQ(full->report_id, 3);
  EXPECT_EQ(full->serial, "AB12");

  auto key = parseHidPedalSpec("413d:2107,key=0x05");
  ASSERT_TRUE(key.ok()) << key.message();
  EXPECT_EQ(key->layout->input, PedalInput::Key);
  EXPECT_EQ(key->layout->key_code, 5);

  auto is_signed = parseHidPedalSpec("0,axis=0:16:-32768:32767");
  ASSERT_TRUE(is_signed.ok()) << is_signed.message();
  EXPECT_EQ(is_signed->layout->raw_min, -32768);
}

TEST(HidPedalSpec, BadSpecsNameTheSpecOnOneLine) {
  struct Bad {
    std::string spec;
    std::string says;  // a word the message must contain
  };
  const std::vector<Bad> bad = {
      {"", "no pedal named"},
      {"hid:", "no pedal named"},
      {"0c45:74zz", "bad target"},
      {"0c45", "bad target"},
      {"0c45:7403:1", "bad target"},
      {"12345", "out of range"},
      {"0,button=9", "bad button"},
      {"0,button=0:8", "bad button"},
      {"0,button=-1:0", "bad button"},
      {"0,axis=1:8:5:5", "equal"},
      {"0,axis=1:40:0:255", "bits"},
      {"0,axis=1:8:0:256", "fit 8 bits"},
      {"0,axis=1.9:8:0:255", "bit in [0, 7]"},
      {"0,axis=1:8:0", "bad axis"},
      {"0,frobnicate", "unknown option"},
      {"0,invert=yes", "unknown option"},
      {"0,deadband=0.7", "bad deadband"},
      {"0,deadband=abc", "bad deadband"},
      {"0,button=0:0,axis=1:8:0:255", "more than one"},
      {"0,key=2", "bad key"},
      {"0,report=300", "bad report"},
      {"0,serial=", "empty serial"},
      {"0,axis=0:8:0x-5:100", "bad axis"},  // a sign after 0x is no hex number
  };
  for (const Bad& b : bad) {
    auto parsed = parseHidPedalSpec(b.spec);
    ASSERT_FALSE(parsed.ok()) << "accepted: " << b.spec;
    const std::string& message = parsed.message();
    const std::string body = b.spec.rfind("hid:", 0) == 0 ? b.spec.substr(4) : b.spec;
    EXPECT_EQ(message.rfind("hid:" + body + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(b.says), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    // makeHidPedal refuses the same spec with the same words.
    auto pedal = makeHidPedal(b.spec, std::make_shared<FakeTransport>());
    ASSERT_FALSE(pedal.ok());
    EXPECT_EQ(pedal.message(), message);
  }
  // A line break typed into the spec is echoed escaped: the error stays one line.
  auto broken = parseHidPedalSpec("0\n");
  ASSERT_FALSE(broken.ok());
  EXPECT_EQ(broken.message().find('\n'), std::string::npos) << broken.message();
  EXPECT_EQ(broken.message().rfind("hid:0\\x0a: ", 0), 0u) << broken.message();
}

// ---- the pedal against a fake device ----

TEST(HidPedal, SwitchPressedAndReleased) {
  auto transport = std::make_shared<FakeTransport>();
  auto hid = transport->add(deviceInfo("/dev/hidraw2", 0x1234, 0x0001, "Pedal"));
  auto pedal = makePedal("1234:0001,button=0:2", transport);
  EXPECT_EQ(pedal->value(), 0.0);
  ASSERT_TRUE(pedal->open().ok()) << pedal->reason();
  EXPECT_EQ(pedal->state(), DeviceState::Ready);
  EXPECT_EQ(pedal->name(), "hid:1234:0001,button=0:2");

  hid->push({0x04});
  ASSERT_TRUE(eventually([&] { return hid->readerIdle(); }));
  EXPECT_EQ(pedal->value(), 1.0);
  hid->push({0xFB});
  ASSERT_TRUE(eventually([&] { return hid->readerIdle(); }));
  EXPECT_EQ(pedal->value(), 0.0);
}

TEST(HidPedal, ProportionalAxisInvertedThroughThePedal) {
  auto transport = std::make_shared<FakeTransport>();
  auto hid = transport->add(deviceInfo("/dev/hidraw5", 0x1234, 0x0002, "Pedal"));
  auto pedal = makePedal("/dev/hidraw5,axis=1:8:0:255,invert", transport);
  ASSERT_TRUE(pedal->open().ok()) << pedal->reason();
  const std::vector<std::pair<uint8_t, double>> expected = {{255, 0.0}, {0, 1.0}, {128, 127.0 / 255.0}};
  for (const auto& [raw, position] : expected) {
    hid->push({0x00, raw});
    ASSERT_TRUE(eventually([&] { return hid->readerIdle(); }));
    EXPECT_DOUBLE_EQ(pedal->value(), position) << "raw " << int(raw);
  }
}

TEST(HidPedal, ShortSplitAndOversizedReportsAreIgnored) {
  auto transport = std::make_shared<FakeTransport>();
  auto hid = transport->add(deviceInfo("/dev/hidraw5", 0x1234, 0x0002, "Pedal"));
  auto pedal = makePedal("/dev/hidraw5,axis=1:16:0:65535,report=7", transport);
  ASSERT_TRUE(pedal->open().ok()) << pedal->reason();
  hid->push({7, 0xFF, 0xFF});
  ASSERT_TRUE(eventually([&] { return hid->readerIdle(); }));
  ASSERT_EQ(pedal->value(), 1.0);
  // A report cut in two: the head is too short, the tail carries no report id 7.
  hid->push({7, 0x00});
  hid->push({0x00});
  hid->push({});
  std::vector<uint8_t> huge(1000, 0x00);  // larger than any read buffer: truncated, not overrun
  huge[0] = 3;
  hid->push(huge);
  ASSERT_TRUE(eventually([&] { return hid->readerIdle(); }));
  EXPECT_EQ(pedal->value(), 1.0);
  EXPECT_EQ(pedal->state(), DeviceState::Ready);
}

TEST(HidPedal, UnplugStopsAtOnceAndReplugRecovers) {
  auto transport = std::make_shared<FakeTransport>();
  auto hid = transport->add(deviceInfo("/dev/hidraw4", 0x1234, 0x0003, "Foot Pedal"));
  auto pedal = makePedal("1234:0003,axis=1:8:0:255", transport);
  ASSERT_TRUE(pedal->open().ok()) << pedal->reason();
  hid->push({0, 255});
  ASSERT_TRUE(eventually([&] { return hid->readerIdle(); }));
  ASSERT_EQ(pedal->value(), 1.0);

  // The fake wakes a waiting read on unplug, as poll() does on a hidraw node that goes away. The
  // reader is held inside a read that never times out, so the unplug can only be seen through that
  // read waking: judged by the event, not by a stopwatch that a loaded machine would break.
  hid->hold(true);
  ASSERT_TRUE(eventually([&] { return hid->readerHeld(); }));
  hid->unplug();
  ASSERT_TRUE(eventually([&] { return pedal->state() == DeviceState::Disconnected; }));
  hid->hold(false);
  EXPECT_EQ(pedal->value(), 0.0);
  EXPECT_NE(pedal->reason().find("/dev/hidraw4"), std::string::npos) << pedal->reason();
  EXPECT_NE(pedal->reason().find("unplugged"), std::string::npos) << pedal->reason();

  // Still gone: service() keeps it Disconnected.
  pedal->service();
  EXPECT_EQ(pedal->state(), DeviceState::Disconnected);
  EXPECT_EQ(pedal->value(), 0.0);

  // Back under another node number: found again by VID:PID and serial.
  hid->replug("/dev/hidraw9");
  pedal->service();
  ASSERT_EQ(pedal->state(), DeviceState::Ready) << pedal->reason();
  EXPECT_EQ(pedal->value(), 0.0);  // nothing read yet since the replug
  hid->push({0, 51});
  ASSERT_TRUE(eventually([&] { return hid->readerIdle(); }));
  EXPECT_DOUBLE_EQ(pedal->value(), 51.0 / 255.0);
}

TEST(HidPedal, ReconnectAttemptsAreRateLimited) {
  auto transport = std::make_shared<FakeTransport>();
  auto hid = transport->add(deviceInfo("/dev/hidraw4", 0x1234, 0x0003, "Foot Pedal"));
  auto pedal = makePedal("1234:0003,button=0:0", transport, {10, 60'000});
  ASSERT_TRUE(pedal->open().ok());
  hid->unplug();
  ASSERT_TRUE(eventually([&] { return pedal->state() == DeviceState::Disconnected; }));
  hid->replug("/dev/hidraw4");
  pedal->service();  // within the minute after open(): not yet
  EXPECT_EQ(pedal->state(), DeviceState::Disconnected);
}

TEST(HidPedal, IndexUsesTheTableAndPermissionDeniedNamesTheRules) {
  auto transport = std::make_shared<FakeTransport>();
  // A PCsensor switch: the programming interface is skipped, the keyboard interface is the pedal.
  transport->add(deviceInfo("/dev/hidraw0", 0x0c45, 0x7403, "FootSwitch", 0xFF00, 0x01, 1));
  auto keys = transport->add(deviceInfo("/dev/hidraw1", 0x0c45, 0x7403, "FootSwitch", 0x01, 0x06, 0));
  auto pedal = makePedal("0", transport);
  ASSERT_TRUE(pedal->open().ok()) << pedal->reason();
  keys->push({0, 0, 0x05, 0, 0, 0, 0, 0});
  ASSERT_TRUE(eventually([&] { return keys->readerIdle(); }));
  EXPECT_EQ(pedal->value(), 1.0);
  pedal->close();

  keys->setPermitted(false);
  auto denied = makePedal("0", transport);
  const Status status = denied->open();
  ASSERT_FALSE(status.ok());
  EXPECT_NE(status.message().find("hid:0"), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("permission denied on /dev/hidraw1"), std::string::npos) << status.message();
  EXPECT_NE(status.message().find("devices/70-dentsim.rules"), std::string::npos) << status.message();
  EXPECT_EQ(denied->state(), DeviceState::Disconnected);
  EXPECT_EQ(denied->reason(), status.message());
  EXPECT_EQ(denied->value(), 0.0);
}

TEST(HidPedal, MissingDeviceAndUnknownLayoutAreErrors) {
  auto transport = std::make_shared<FakeTransport>();
  transport->add(deviceInfo("/dev/hidraw0", 0x1234, 0x0005, "Foot Pedal"));  // no descriptor, not in the table
  auto missing = makePedal("abcd:0001,button=0:0", transport);
  const Status a = missing->open();
  ASSERT_FALSE(a.ok());
  EXPECT_EQ(a.message().rfind("hid:abcd:0001,button=0:0: not found", 0), 0u) << a.message();
  auto beyond = makePedal("3", transport);
  const Status b = beyond->open();
  ASSERT_FALSE(b.ok());
  EXPECT_NE(b.message().find("1 found"), std::string::npos) << b.message();
  auto unknown = makePedal("0", transport);
  const Status c = unknown->open();
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.message().find("cannot tell the report layout of /dev/hidraw0 (1234:0005)"), std::string::npos)
      << c.message();
  EXPECT_EQ(unknown->state(), DeviceState::Disconnected);
}

TEST(HidPedal, CloseIsIdempotent) {
  auto transport = std::make_shared<FakeTransport>();
  auto hid = transport->add(deviceInfo("/dev/hidraw2", 0x1234, 0x0001, "Pedal"));
  auto pedal = makePedal("/dev/hidraw2,button=0:0", transport);
  pedal->close();  // never opened
  EXPECT_EQ(pedal->state(), DeviceState::Disconnected);
  ASSERT_TRUE(pedal->open().ok());
  hid->push({1});
  ASSERT_TRUE(eventually([&] { return hid->readerIdle(); }));
  ASSERT_EQ(pedal->value(), 1.0);
  pedal->close();
  EXPECT_EQ(pedal->state(), DeviceState::Disconnected);
  EXPECT_EQ(pedal->value(), 0.0);
  pedal->close();
  EXPECT_EQ(pedal->state(), DeviceState::Disconnected);
  pedal->service();  // closed: no reconnect
  EXPECT_EQ(pedal->state(), DeviceState::Disconnected);
  // Open again after close, then let the destructor close.
  ASSERT_TRUE(pedal->open().ok());
  EXPECT_EQ(pedal->state(), DeviceState::Ready);
}

TEST(HidPedal, ValueNeverBlocksWhileTheReaderIsInARead) {
  auto transport = std::make_shared<FakeTransport>();
  auto hid = transport->add(deviceInfo("/dev/hidraw2", 0x1234, 0x0001, "Pedal"));
  auto pedal = makePedal("/dev/hidraw2,axis=0:8:0:255", transport);
  ASSERT_TRUE(pedal->open().ok());
  hid->push({102});
  ASSERT_TRUE(eventually([&] { return hid->readerIdle(); }));
  hid->hold(true);
  ASSERT_TRUE(eventually([&] { return hid->readerHeld(); }));
  // Asked from another thread so that a blocking value() fails the test instead of hanging it.
  auto reads = std::async(std::launch::async, [&] {
    int other = 0;  // readings that were not the last decoded position
    for (int i = 0; i < 10'000; ++i) other += pedal->value() != 102.0 / 255.0;
    return other;
  });
  // 10 000 lock-free loads take microseconds; a blocking value() never ends while the read is held,
  // so the generous wait tells the two apart even on a loaded machine.
  const bool finished = reads.wait_for(10s) == std::future_status::ready;
  EXPECT_TRUE(hid->readerHeld());  // the reader was inside its read all along
  hid->hold(false);                // lets a blocked value() go, so a failure ends rather than hangs
  ASSERT_TRUE(finished) << "value() blocked behind the reader";
  EXPECT_EQ(reads.get(), 0);
  pedal->close();
}

// ---- enumeration ----

TEST(HidPedalEnumerate, ListsPedalsOnly) {
  auto transport = std::make_shared<FakeTransport>();
  const std::vector<uint8_t> accelerator = {0x05, 0x02, 0x09, 0xC4, 0x15, 0x00, 0x26, 0xFF, 0x00,
                                            0x75, 0x08, 0x95, 0x01, 0x81, 0x02};
  transport->add(deviceInfo("/dev/hidraw0", 0x046d, 0xc31c, "USB Keyboard", 0x01, 0x06));   // a keyboard: no
  transport->add(deviceInfo("/dev/hidraw1", 0x0c45, 0x7403, "FootSwitch", 0x01, 0x06, 0));  // table
  transport->add(deviceInfo("/dev/hidraw2", 0x0c45, 0x7403, "FootSwitch", 0xFF00, 0x01, 1));  // its other interface: no
  transport->add(deviceInfo("/dev/hidraw3", 0x1111, 0x2222, "Racing Pedals", 0x01, 0x04), accelerator);  // by name
  auto locked = transport->add(deviceInfo("/dev/hidraw4", 0x3333, 0x4444, "Gizmo", 0x02, 0x02));  // Simulation Controls
  locked->setPermitted(false);
  transport->add(deviceInfo("/dev/hidraw5", 0x5555, 0x6666, "Gamepad", 0x01, 0x05), accelerator);  // a gamepad: no

  const std::vector<DeviceEntry> entries = enumerateHidPedals(*transport);
  ASSERT_EQ(entries.size(), 3u);
  EXPECT_EQ(entries[0].name, "hid:0");
  EXPECT_EQ(entries[0].kind, "pedal");
  EXPECT_EQ(entries[0].model, "PCsensor FootSwitch (switch)");
  EXPECT_EQ(entries[0].location, "/dev/hidraw1 (0c45:7403)");
  EXPECT_EQ(entries[0].state, DeviceState::Ready);
  EXPECT_EQ(entries[0].reason, "");
  EXPECT_EQ(entries[1].name, "hid:1");
  EXPECT_EQ(entries[1].model, "Acme Racing Pedals (proportional)");
  EXPECT_EQ(entries[1].location, "/dev/hidraw3 (1111:2222)");
  EXPECT_EQ(entries[2].name, "hid:2");
  EXPECT_EQ(entries[2].state, DeviceState::Disconnected);
  EXPECT_NE(entries[2].reason.find("permission denied on /dev/hidraw4"), std::string::npos) << entries[2].reason;
  EXPECT_NE(entries[2].reason.find("70-dentsim.rules"), std::string::npos) << entries[2].reason;
}

TEST(HidPedalEnumerate, KnownTableIsWellFormed) {
  for (const KnownPedal& k : knownPedals()) {
    EXPECT_NE(k.vendor_id, 0);
    EXPECT_NE(std::string(k.model), "");
    if (k.layout.input == PedalInput::Button) {
      EXPECT_NE(k.layout.button_mask, 0);
    }
  }
  EXPECT_GE(knownPedals().size(), 4u);
}

// ---- the real hidapi transport, with no pedal needed ----

TEST(HidPedalHidapi, MissingNodeIsAClearError) {
  auto pedal = makeHidPedal("hid:/dev/hidraw-dentsim-absent,button=0:0");
  ASSERT_TRUE(pedal.ok()) << pedal.message();
  const Status status = (*pedal)->open();
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.message().rfind("hid:/dev/hidraw-dentsim-absent,button=0:0: not found", 0), 0u) << status.message();
  EXPECT_EQ((*pedal)->state(), DeviceState::Disconnected);
  EXPECT_EQ((*pedal)->value(), 0.0);
  // Whatever this machine has plugged in, the listing is well formed.
  for (const DeviceEntry& e : enumerateHidPedals()) {
    EXPECT_EQ(e.name.rfind("hid:", 0), 0u);
    EXPECT_EQ(e.kind, "pedal");
    EXPECT_NE(e.location.find("/dev/"), std::string::npos);
  }
}

}  // namespace
}  // namespace dentsim::devices
