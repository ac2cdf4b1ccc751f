// The Falcon backend: libusb transport (enumeration, firmware load, asynchronous 1 kHz exchange) behind HapticDevice.
//
// Contents
//   1. Helpers: firmware path, libusb names
//   2. Transport: finding the index-th Falcon, synchronous control and bulk calls with timeouts
//   3. Bring-up: firmware mode, probe, firmware load
//   4. FalconDevice: open/close/service/read and the event thread's exchange
//   5. enumerateFalcons, makeFalcon
//
// Threads. The control thread opens, services and closes. While open, one event thread runs
// libusb's event loop; the transfer callbacks run on it and keep one IN and one OUT in flight: each
// status packet that arrives publishes a reading (a triple buffer, read() never waits) and sends
// the next command built from output(). Faults found there become atomics that service() turns into
// a state and a reason; the event thread itself only ever sends zero force after a fault.
#include "devices/falcon_device.h"

#include <libusb-1.0/libusb.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <thread>

#include "core/permission_advice.h"
#include "core/steady_clock.h"
#include "core/triple_buffer.h"
#include "devices/falcon_kinematics.h"
#include "devices/falcon_protocol.h"

namespace dentsim::devices {

namespace {

using namespace falcon;

// ---- 1. Helpers ---------------------------------------------------------------------------------
constexpr unsigned kControlTimeoutMs = 200;    // one vendor request
constexpr unsigned kBulkTimeoutMs = 200;       // one synchronous bulk call during bring-up
constexpr unsigned kOutTimeoutMs = 20;         // one command in the running loop
constexpr unsigned kInTimeoutMs = 200;         // one IN transfer in the running loop (the stall check comes first)
constexpr int64_t kStallNs = 50'000'000;       // no status packet for this long: Fault
constexpr int64_t kProbeNs = 100'000'000;      // how long a running firmware has to answer a command
constexpr int64_t kReconnectNs = 200'000'000;  // service() retries a lost Falcon this often
constexpr int kInBufferSize = 64;              // one full-speed USB packet: a status packet plus modem bytes
constexpr double kVelocityCutoffHz = 50.0;     // low-pass on the differenced velocity

// Where the user's firmware image is: the option, else $DENTSIM_FALCON_FIRMWARE, else the config dir.
std::string firmwarePath(const FalconOptions& options) {
  if (!options.firmware_path.empty()) return options.firmware_path;
  if (const char* env = std::getenv("DENTSIM_FALCON_FIRMWARE"); env && *env) return env;
  if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg) return std::string(xdg) + "/dentsim/falcon_firmware.bin";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.config/dentsim/falcon_firmware.bin";
  return "falcon_firmware.bin";
}

std::string firmwareMissingReason(const std::string& path) {
  return "firmware file " + path + ": not found; dentsim does not ship the Falcon's firmware: copy the file from "
         "the Novint driver to that path, or set DENTSIM_FALCON_FIRMWARE or --falcon-firmware";
}

bool fileExists(const std::string& path) { return std::ifstream(path, std::ios::binary).good(); }

struct UsbLocation {
  uint8_t bus = 0;
  uint8_t address = 0;
  std::array<uint8_t, 8> ports{};
  int port_count = 0;
  std::string node() const {
    char s[40];
    std::snprintf(s, sizeof s, "/dev/bus/usb/%03u/%03u", bus, address);
    return s;
  }
  // "usb 1-4.2 (/dev/bus/usb/001/005)"
  std::string text() const {
    std::string t = "usb " + std::to_string(bus);
    for (int i = 0; i < port_count; ++i) t += (i == 0 ? "-" : ".") + std::to_string(ports[i]);
    if (port_count == 0) t += ":" + std::to_string(address);
    return t + " (" + node() + ")";
  }
  bool operator<(const UsbLocation& o) const {
    if (bus != o.bus) return bus < o.bus;
    if (!std::equal(ports.begin(), ports.begin() + port_count, o.ports.begin(), o.ports.begin() + o.port_count))
      return std::lexicographical_compare(ports.begin(), ports.begin() + port_count, o.ports.begin(),
                                          o.ports.begin() + o.port_count);
    return address < o.address;
  }
};

UsbLocation locationOf(libusb_device* d) {
  UsbLocation l;
  l.bus = libusb_get_bus_number(d);
  l.address = libusb_get_device_address(d);
  const int n = libusb_get_port_numbers(d, l.ports.data(), static_cast<int>(l.ports.size()));
  l.port_count = n > 0 ? n : 0;
  return l;
}

// ---- 2. Transport -----------------------------------------------------------------------------
struct Found {
  libusb_device* device = nullptr;  // referenced; the caller unrefs
  UsbLocation location;
};

// Every Falcon on the bus, in bus order. The devices are referenced; unref each.
std::vector<Found> listFalcons(libusb_context* ctx) {
  std::vector<Found> found;
  libusb_device** list = nullptr;
  const ssize_t n = libusb_get_device_list(ctx, &list);
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor desc{};
    if (libusb_get_device_descriptor(list[i], &desc) != 0) continue;
    if (desc.idVendor != kVendorId || desc.idProduct != kProductId) continue;
    found.push_back({libusb_ref_device(list[i]), locationOf(list[i])});
  }
  if (n >= 0) libusb_free_device_list(list, 1);
  std::sort(found.begin(), found.end(), [](const Found& a, const Found& b) { return a.location < b.location; });
  return found;
}

Status control(libusb_device_handle* h, const ControlRequest& r, const std::string& where) {
  const int rc = libusb_control_transfer(h, r.request_type, r.request, r.value, r.index, nullptr, 0, kControlTimeoutMs);
  if (rc < 0) {
    char what[96];
    std::snprintf(what, sizeof what, "FTDI request 0x%02x (value 0x%04x): %s", r.request, r.value, libusb_error_name(rc));
    return makeError(where, what);
  }
  return Ok{};
}

Status writeAll(libusb_device_handle* h, const uint8_t* data, int size, unsigned timeout_ms, const std::string& where) {
  int done = 0;
  const int rc = libusb_bulk_transfer(h, kEndpointOut, const_cast<uint8_t*>(data), size, &done, timeout_ms);
  if (rc < 0) return makeError(where, std::string("USB write: ") + libusb_error_name(rc));
  if (done != size) return makeError(where, "USB write: short write (" + std::to_string(done) + " of " + std::to_string(size) + " bytes)");
  return Ok{};
}

// Reads until `want` payload bytes have arrived (modem status stripped) or the deadline passes.
// Returns the payload bytes read; a USB error gives -1 and *error.
int readPayload(libusb_device_handle* h, uint8_t* out, int want, int64_t deadline_ns, int* error) {
  int got = 0;
  *error = 0;
  while (got < want && steadyNowNs() < deadline_ns) {
    uint8_t raw[kInBufferSize];
    int n = 0;
    const int rc = libusb_bulk_transfer(h, kEndpointIn, raw, kInBufferSize, &n, kBulkTimeoutMs);
    if (rc == LIBUSB_ERROR_TIMEOUT) continue;
    if (rc < 0) {
      *error = rc;
      return -1;
    }
    uint8_t payload[kInBufferSize];
    const size_t p = stripModemStatus(raw, static_cast<size_t>(n), payload);
    const size_t take = std::min(p, static_cast<size_t>(want - got));
    std::memcpy(out + got, payload, take);
    got += static_cast<int>(take);
  }
  return got;
}

// ---- 3. Bring-up ----------------------------------------------------------------------------------
Status firmwareMode(libusb_device_handle* h, const std::string& where) {
  for (const ControlRequest& r : kFirmwareModeRequests)
    if (Status s = control(h, r, where); !s) return s;
  return Ok{};
}

// True when a running firmware answers a zero command with a status packet within kProbeNs.
Result<bool> probeFirmware(libusb_device_handle* h, const std::string& where) {
  const Packet zero = encodeCommand({});
  if (Status s = writeAll(h, zero.data(), static_cast<int>(zero.size()), kBulkTimeoutMs, where); !s) return s.error();
  PacketAssembler assembler;
  falcon::Reply status;
  const int64_t deadline = steadyNowNs() + kProbeNs;
  while (steadyNowNs() < deadline) {
    uint8_t raw[kInBufferSize];
    int n = 0;
    const int rc = libusb_bulk_transfer(h, kEndpointIn, raw, kInBufferSize, &n, kBulkTimeoutMs);
    if (rc == LIBUSB_ERROR_TIMEOUT) continue;
    if (rc < 0) return makeError(where, std::string("USB read: ") + libusb_error_name(rc));
    uint8_t payload[kInBufferSize];
    const size_t p = stripModemStatus(raw, static_cast<size_t>(n), payload);
    if (assembler.feed(payload, p, &status) > 0) return true;
  }
  return false;
}

Status loadFirmware(libusb_device_handle* h, const std::string& path, const std::string& where) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return makeError(where, firmwareMissingReason(path));
  const std::vector<uint8_t> image((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (image.empty()) return makeError(where, "firmware file " + path + ": empty");

  for (const ControlRequest& r : kLoaderModeRequests)
    if (Status s = control(h, r, where); !s) return s;
  // The boot loader greets after its reset; a few tries cover a slow start.
  bool greeted = false;
  for (int attempt = 0; attempt < 10 && !greeted; ++attempt) {
    if (Status s = writeAll(h, kLoaderHello.data(), static_cast<int>(kLoaderHello.size()), kBulkTimeoutMs, where); !s) return s;
    uint8_t reply[kLoaderHelloReply.size() + 1];
    int err = 0;
    const int n = readPayload(h, reply, static_cast<int>(sizeof reply), steadyNowNs() + 20'000'000, &err);
    if (n < 0) return makeError(where, std::string("firmware load: USB read: ") + libusb_error_name(err));
    greeted = isLoaderHelloReply(reply, static_cast<size_t>(n)) ||
              (n == static_cast<int>(sizeof reply) && isLoaderHelloReply(reply + 1, kLoaderHelloReply.size()));
  }
  if (!greeted) return makeError(where, "firmware load: the boot loader does not answer (is the power supply plugged in?)");
  for (const ControlRequest& r : kLoaderUploadRequests)
    if (Status s = control(h, r, where); !s) return s;
  if (Status s = writeAll(h, &kLoaderStart, 1, kBulkTimeoutMs, where); !s) return s;
  uint8_t echo[kFirmwareChunk];
  int err = 0;
  if (readPayload(h, echo, 1, steadyNowNs() + 200'000'000, &err) != 1 || echo[0] != kLoaderStart)
    return makeError(where, "firmware load: the boot loader did not accept the upload");

  for (size_t at = 0; at < image.size(); at += kFirmwareChunk) {
    const int n = static_cast<int>(std::min(kFirmwareChunk, image.size() - at));
    if (Status s = writeAll(h, image.data() + at, n, kBulkTimeoutMs, where); !s) return s;
    const int got = readPayload(h, echo, n, steadyNowNs() + 500'000'000, &err);
    if (got < 0) return makeError(where, std::string("firmware load: USB read: ") + libusb_error_name(err));
    if (got != n || std::memcmp(echo, image.data() + at, static_cast<size_t>(n)) != 0)
      return makeError(where, "firmware load: echo mismatch at byte " + std::to_string(at) + " of " + path);
  }
  return firmwareMode(h, where);
}

// ---- 4. FalconDevice ------------------------------------------------------------------------------
enum class Fault : uint8_t { None, Stall, Timeout, Gone, UsbError };

class FalconDevice final : public HapticDevice {
 public:
  FalconDevice(int index, const FalconOptions& options)
      : HapticDevice(options.safety), index_(index), options_(options), name_("falcon:" + std::to_string(index)) {
    // Novint rates the Falcon at over 2 lbf (8.9 N) of force; stiffness and damping are the usual
    // stable figures for a 1 kHz impedance pen of its size, not vendor numbers. The workspace is the
    // box the kinematics reach everywhere (falcon_kinematics.h).
    spec_.model = "Novint Falcon";
    spec_.max_force_n = 8.9;
    spec_.max_torque_n_mm = 0.0;
    spec_.max_stiffness_n_per_mm = 2.0;
    spec_.max_damping_n_s_per_mm = 0.004;
    spec_.workspace_min_mm = kinematics_.geometry().workspace_min_mm;
    spec_.workspace_max_mm = kinematics_.geometry().workspace_max_mm;
    spec_.rate_hz = 1000.0;
    setState(DeviceState::Disconnected, "not opened");
  }
  ~FalconDevice() override { close(); }

  std::string name() const override { return name_; }
  const DeviceSpec& spec() const override { return spec_; }

  Status open() override {
    if (handle_) return Ok{};
    want_open_ = true;
    Status s = connect();
    if (!s) return s;
    return Ok{};
  }

  void close() override {
    want_open_ = false;
    stopIo(/*send_zero=*/true);
    setState(DeviceState::Disconnected, "closed");
  }

  void service() override {
    const Fault f = fault_.load(std::memory_order_acquire);
    if (f != Fault::None && handle_) {
      const bool gone = f == Fault::Gone;
      stopIo(/*send_zero=*/!gone);
      switch (f) {
        case Fault::Gone: setState(DeviceState::Disconnected, "unplugged: zero force; waiting for the Falcon to come back"); break;
        case Fault::Stall: setState(DeviceState::Fault, "no data from the Falcon for 50 ms: zero force; check its power and USB cable"); break;
        case Fault::Timeout: setState(DeviceState::Fault, "USB write timed out: zero force; check the Falcon's power and USB cable"); break;
        default: setState(DeviceState::Fault, "USB error: " + std::string(libusb_error_name(usb_error_.load())) + ": zero force"); break;
      }
      last_attempt_ns_ = steadyNowNs();
      return;
    }
    if (!handle_) {
      // A lost Falcon is looked for again; a replugged one needs its firmware and homing anew.
      if (want_open_ && steadyNowNs() - last_attempt_ns_ >= kReconnectNs) {
        last_attempt_ns_ = steadyNowNs();
        const DeviceState before = state();
        const std::string why = reason();
        if (!connect()) {
          if (before == DeviceState::Fault || before == DeviceState::Disconnected) setState(before, why);
        }
      }
      return;
    }
    const bool homed = homed_.load(std::memory_order_acquire);
    const DeviceState s = state();
    if (homed && s == DeviceState::NeedsHoming) setState(DeviceState::Ready);
    if (!homed && tracking(s)) setState(DeviceState::NeedsHoming, homingReason());
  }

  bool read(double /*t_s*/, DeviceReading* out) override {
    if (!tracking(state()) || fault_.load(std::memory_order_acquire) != Fault::None) return false;
    const std::optional<DeviceReading>& r = readings_.read();
    if (!r) return false;
    *out = *r;
    return true;
  }

  // ---- event thread ----
  static void LIBUSB_CALL onOut(libusb_transfer* t) { static_cast<FalconDevice*>(t->user_data)->outDone(t); }
  static void LIBUSB_CALL onIn(libusb_transfer* t) { static_cast<FalconDevice*>(t->user_data)->inDone(t); }

 private:
  static std::string homingReason() {
    return "not homed: move the grip slowly through its whole range until the LED turns green";
  }

  Status connect() {
    const std::string where_name = name_;
    if (libusb_init(&ctx_) < 0) {
      ctx_ = nullptr;
      setState(DeviceState::Disconnected, "libusb cannot start");
      return makeError(where_name, "libusb cannot start");
    }
    std::vector<Found> found = listFalcons(ctx_);
    if (index_ < 0 || index_ >= static_cast<int>(found.size())) {
      for (Found& f : found) libusb_unref_device(f.device);
      teardownContext();
      const std::string why = found.empty() ? "no Falcon on the USB bus"
                                            : "only " + std::to_string(found.size()) + " Falcon(s) on the USB bus";
      setState(DeviceState::Disconnected, why);
      return makeError(where_name, why);
    }
    location_ = found[index_].location;
    const int rc = libusb_open(found[index_].device, &handle_);
    for (Found& f : found) libusb_unref_device(f.device);
    const std::string where = name_ + " (" + location_.text() + ")";
    if (rc != 0) {
      handle_ = nullptr;
      teardownContext();
      const std::string why = rc == LIBUSB_ERROR_ACCESS ? permissionAdvice(location_.node())
                                                        : std::string("cannot open: ") + libusb_error_name(rc);
      setState(DeviceState::Disconnected, why);
      return makeError(where, why);
    }
    Status s = bringUp(where);
    if (!s) {
      releaseHandle();
      teardownContext();
      return s;
    }
    startIo();
    setState(DeviceState::NeedsHoming, homingReason());
    return Ok{};
  }

  // Claims the interface, loads the firmware if none answers, and leaves the FTDI in firmware mode.
  Status bringUp(const std::string& where) {
    if (libusb_kernel_driver_active(handle_, kInterface) == 1) libusb_detach_kernel_driver(handle_, kInterface);
    if (const int rc = libusb_claim_interface(handle_, kInterface); rc != 0) {
      const std::string why = std::string("cannot claim the USB interface: ") + libusb_error_name(rc);
      setState(rc == LIBUSB_ERROR_NO_DEVICE ? DeviceState::Disconnected : DeviceState::Fault, why);
      return makeError(where, why);
    }
    claimed_ = true;
    auto fail = [&](const Status& st, DeviceState as) {
      const std::string& msg = st.message();
      setState(as, msg.rfind(where + ": ", 0) == 0 ? msg.substr(where.size() + 2) : msg);
      return st;
    };
    if (Status st = firmwareMode(handle_, where); !st) return fail(st, DeviceState::Fault);
    Result<bool> running = probeFirmware(handle_, where);
    if (!running) return fail(running.error(), DeviceState::Fault);
    if (*running) return Ok{};
    const std::string path = firmwarePath(options_);
    if (!fileExists(path)) {
      const std::string why = firmwareMissingReason(path);
      setState(DeviceState::NeedsFirmware, why);
      return makeError(where, why);
    }
    if (Status st = loadFirmware(handle_, path, where); !st) return fail(st, DeviceState::NeedsFirmware);
    running = probeFirmware(handle_, where);
    if (!running) return fail(running.error(), DeviceState::Fault);
    if (!*running) return fail(makeError(where, "firmware " + path + " loaded, but the Falcon does not answer"), DeviceState::Fault);
    return Ok{};
  }

  void startIo() {
    fault_.store(Fault::None, std::memory_order_release);
    homed_.store(false, std::memory_order_release);
    readings_.publish(std::nullopt);  // I/O is stopped: the event thread publishes nothing now
    assembler_.reset();
    have_pose_ = false;
    last_packet_ns_ = steadyNowNs();
    out_ = libusb_alloc_transfer(0);
    in_ = libusb_alloc_transfer(0);
    stop_.store(false, std::memory_order_release);
    out_busy_ = in_busy_ = false;
    submitIn();
    sendCommand(steadyNowNs());
    event_thread_ = std::thread([this] { eventLoop(); });
  }

  void eventLoop() {
    while (!stop_.load(std::memory_order_acquire)) {
      timeval tv{0, 2000};
      libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
      if (fault_.load(std::memory_order_relaxed) == Fault::None && steadyNowNs() - last_packet_ns_ > kStallNs)
        raise(Fault::Stall, 0);
    }
  }

  void raise(Fault f, int usb_error) {
    Fault none = Fault::None;
    usb_error_.store(usb_error, std::memory_order_relaxed);
    if (!fault_.compare_exchange_strong(none, f, std::memory_order_acq_rel)) return;
    // Zero force at once where the Falcon can still hear it; service() names the fault later.
    safetyLayer().disable();
    if (f != Fault::Gone && handle_) sendCommand(steadyNowNs());
  }

  void submitIn() {
    libusb_fill_bulk_transfer(in_, handle_, kEndpointIn, in_buffer_.data(), kInBufferSize, &FalconDevice::onIn, this,
                              kInTimeoutMs);
    const int rc = libusb_submit_transfer(in_);
    if (rc == 0) in_busy_ = true;
    else raise(rc == LIBUSB_ERROR_NO_DEVICE ? Fault::Gone : Fault::UsbError, rc);
  }

  // The next command: the safety layer's force through the Jacobian, or zero once anything is wrong.
  void sendCommand(int64_t now_ns) {
    if (out_busy_) return;
    const SafetyLayer::Output force = output(now_ns);
    Command c;
    const bool homed = homed_.load(std::memory_order_relaxed);
    c.homing = !homed;
    c.leds = homed ? kLedGreen : kLedRed;
    if (force.gate == SafetyGate::Pass && have_pose_ && fault_.load(std::memory_order_relaxed) == Fault::None) {
      const falcon::Torques tau = kinematics_.torquesForForce(angles_, force.wrench.force);
      c.motor = kinematics_.motorWords(tau);
      c.leds = kLedBlue;
    }
    out_packet_ = encodeCommand(c);
    libusb_fill_bulk_transfer(out_, handle_, kEndpointOut, out_packet_.data(), static_cast<int>(kPacketSize),
                              &FalconDevice::onOut, this, kOutTimeoutMs);
    const int rc = libusb_submit_transfer(out_);
    if (rc == 0) out_busy_ = true;
    else raise(rc == LIBUSB_ERROR_NO_DEVICE ? Fault::Gone : Fault::UsbError, rc);
  }

  static Fault faultOf(libusb_transfer_status s) {
    switch (s) {
      case LIBUSB_TRANSFER_TIMED_OUT: return Fault::Timeout;
      case LIBUSB_TRANSFER_NO_DEVICE: return Fault::Gone;
      default: return Fault::UsbError;
    }
  }

  void outDone(libusb_transfer* t) {
    out_busy_ = false;
    if (t->status == LIBUSB_TRANSFER_COMPLETED || t->status == LIBUSB_TRANSFER_CANCELLED) return;
    raise(faultOf(t->status), LIBUSB_ERROR_IO);
  }

  void inDone(libusb_transfer* t) {
    in_busy_ = false;
    if (t->status == LIBUSB_TRANSFER_CANCELLED) return;
    if (t->status != LIBUSB_TRANSFER_COMPLETED) {
      // An IN that timed out means the Falcon went quiet: the stall check names it.
      raise(t->status == LIBUSB_TRANSFER_TIMED_OUT ? Fault::Stall : faultOf(t->status), LIBUSB_ERROR_IO);
      return;
    }
    uint8_t payload[kInBufferSize];
    const size_t n = stripModemStatus(in_buffer_.data(), static_cast<size_t>(t->actual_length), payload);
    falcon::Reply status;
    const int packets = assembler_.feed(payload, n, &status);
    if (stop_.load(std::memory_order_acquire) || fault_.load(std::memory_order_relaxed) != Fault::None) return;
    if (packets > 0) {
      const int64_t now = steadyNowNs();
      last_packet_ns_ = now;
      publish(status, now);
      sendCommand(now);
    }
    submitIn();
  }

  void publish(const falcon::Reply& status, int64_t now_ns) {
    homed_.store((status.homed & kAllAxesHomed) == kAllAxesHomed, std::memory_order_release);
    const falcon::Encoders enc = {status.encoder[0], status.encoder[1], status.encoder[2]};
    const falcon::Angles a = kinematics_.anglesFromEncoders(enc);
    Vec3 p;
    if (!kinematics_.forward(a, &p, have_pose_ ? &position_ : nullptr)) return;  // keep the last good pose
    angles_ = a;
    if (have_pose_) {
      const double dt = static_cast<double>(now_ns - stamp_ns_) * 1e-9;
      if (dt > 0) {
        const double alpha = 1.0 - std::exp(-2.0 * 3.14159265358979 * kVelocityCutoffHz * dt);
        velocity_ += ((p - position_) / dt - velocity_) * alpha;
      }
    }
    position_ = p;
    stamp_ns_ = now_ns;
    have_pose_ = true;
    DeviceReading r;
    r.pose.position = p;
    r.velocity = velocity_;
    r.buttons = status.grip;
    r.stamp_ns = now_ns;
    readings_.publish(r);
  }

  // Stops the loop; with send_zero the last packet on the wire is a zero-force command.
  void stopIo(bool send_zero) {
    safetyLayer().disable();
    if (event_thread_.joinable()) {
      stop_.store(true, std::memory_order_release);
      event_thread_.join();
    }
    if (handle_ && ctx_) {
      if (out_busy_) libusb_cancel_transfer(out_);
      if (in_busy_) libusb_cancel_transfer(in_);
      const int64_t deadline = steadyNowNs() + 200'000'000;
      while ((out_busy_ || in_busy_) && steadyNowNs() < deadline) {
        timeval tv{0, 10000};
        libusb_handle_events_timeout_completed(ctx_, &tv, nullptr);
      }
      if (send_zero && claimed_) {
        const Packet zero = encodeCommand({});
        int done = 0;
        libusb_bulk_transfer(handle_, kEndpointOut, const_cast<uint8_t*>(zero.data()), static_cast<int>(zero.size()), &done,
                             kOutTimeoutMs);
      }
    }
    // A transfer that never completed stays allocated rather than be freed under libusb.
    if (out_ && !out_busy_) libusb_free_transfer(out_);
    if (in_ && !in_busy_) libusb_free_transfer(in_);
    out_ = in_ = nullptr;
    releaseHandle();
    teardownContext();
  }

  void releaseHandle() {
    if (!handle_) return;
    if (claimed_) libusb_release_interface(handle_, kInterface);
    claimed_ = false;
    libusb_close(handle_);
    handle_ = nullptr;
  }

  void teardownContext() {
    if (ctx_) libusb_exit(ctx_);
    ctx_ = nullptr;
  }

  const int index_;
  const FalconOptions options_;
  const std::string name_;
  DeviceSpec spec_;
  falcon::Kinematics kinematics_;
  UsbLocation location_;
  bool want_open_ = false;
  int64_t last_attempt_ns_ = 0;

  libusb_context* ctx_ = nullptr;
  libusb_device_handle* handle_ = nullptr;
  bool claimed_ = false;
  std::thread event_thread_;
  std::atomic<bool> stop_{false};
  std::atomic<Fault> fault_{Fault::None};
  std::atomic<int> usb_error_{0};
  std::atomic<bool> homed_{false};
  TripleBuffer<std::optional<DeviceReading>> readings_;  // event thread -> read(); empty until a status packet came

  // Event thread's (and the control thread's only while the event thread is stopped).
  libusb_transfer* out_ = nullptr;
  libusb_transfer* in_ = nullptr;
  bool out_busy_ = false;
  bool in_busy_ = false;
  Packet out_packet_{};
  std::array<uint8_t, kInBufferSize> in_buffer_{};
  PacketAssembler assembler_;
  std::atomic<int64_t> last_packet_ns_{0};
  bool have_pose_ = false;
  falcon::Angles angles_{};
  Vec3 position_;
  Vec3 velocity_;
  int64_t stamp_ns_ = 0;
};

}  // namespace

// ---- 5. enumerateFalcons, makeFalcon ------------------------------------------------------------
std::vector<DeviceEntry> enumerateFalcons() {
  std::vector<DeviceEntry> entries;
  libusb_context* ctx = nullptr;
  if (libusb_init(&ctx) < 0) return entries;
  std::vector<Found> found = listFalcons(ctx);
  const std::string firmware = firmwarePath({});
  for (size_t i = 0; i < found.size(); ++i) {
    DeviceEntry e;
    e.name = "falcon:" + std::to_string(i);
    e.kind = "pen";
    e.model = "Novint Falcon";
    e.location = found[i].location.text();
    // Opening without claiming tells whether we may use it, and leaves it to whoever has it.
    libusb_device_handle* h = nullptr;
    const int rc = libusb_open(found[i].device, &h);
    if (rc == LIBUSB_ERROR_ACCESS) {
      e.state = DeviceState::Disconnected;
      e.reason = permissionAdvice(found[i].location.node());
    } else if (rc != 0) {
      e.state = DeviceState::Disconnected;
      e.reason = std::string("cannot open: ") + libusb_error_name(rc);
    } else {
      e.state = DeviceState::NeedsHoming;
      if (!fileExists(firmware)) e.reason = "if its firmware is not loaded yet: " + firmwareMissingReason(firmware);
      libusb_close(h);
    }
    libusb_unref_device(found[i].device);
    entries.push_back(std::move(e));
  }
  libusb_exit(ctx);
  return entries;
}

std::unique_ptr<HapticDevice> makeFalcon(int index, const FalconOptions& options) {
  return std::make_unique<FalconDevice>(index, options);
}

}  // namespace dentsim::devices
