// OpenHaptics plug-in: loads the vendor's HDAPI with dlopen, runs the 1 kHz servo callback, and keeps the pen's state.
//
// Sections: 1. HDAPI declarations  2. the loaded library  3. the pen: open, servo callback, read,
// service, close  4. enumeration and the factory.
//
// The build never needs OpenHaptics: the handful of HDAPI types, values and entry points used here
// are declared below from the OpenHaptics HDAPI reference (its headers hd.h, hdScheduler.h and
// hdDefines.h, OpenHaptics 3.x), and resolved by name at run time. HDAPI works in millimetres and
// newtons, as dentsim does; torques are in mN m, which is exactly N mm.
#include "devices/openhaptics_pen.h"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "core/seqlock.h"
#include "core/steady_clock.h"
#include "devices/hdapi_abi.h"

namespace dentsim::devices {
namespace {

// ---- 1. HDAPI declarations: devices/hdapi_abi.h ----

// mN m to N mm: 1e-3 N x 1e3 mm. Named so that the conversion is visible where torque goes out.
constexpr double kNmmPerMilliNm = 1.0;
// How long open() waits for the scheduler's first servo frame, and close() for its last [ms].
constexpr int kFirstFrameTimeoutMs = 1000;
constexpr int kLastFrameTimeoutMs = 100;
// While calibrated, the servo loop asks again this often [frames]; until then, every frame.
constexpr long kCalibrationCheckPeriod = 100;

// ---- 2. the loaded library ----
// The HDAPI entry points, resolved from one dlopen handle; dlclose on destruction.
struct HdLibrary {
  void* handle = nullptr;
  std::string path;
  hd::HHD (*hdInitDevice)(hd::HDstring) = nullptr;
  void (*hdDisableDevice)(hd::HHD) = nullptr;
  void (*hdMakeCurrentDevice)(hd::HHD) = nullptr;
  hd::ErrorInfo (*hdGetError)() = nullptr;
  hd::HDstring (*hdGetErrorString)(hd::HDerror) = nullptr;
  void (*hdBeginFrame)(hd::HHD) = nullptr;
  void (*hdEndFrame)(hd::HHD) = nullptr;
  void (*hdEnable)(hd::HDenum) = nullptr;
  void (*hdDisable)(hd::HDenum) = nullptr;
  void (*hdGetDoublev)(hd::HDenum, hd::HDdouble*) = nullptr;
  void (*hdGetIntegerv)(hd::HDenum, hd::HDint*) = nullptr;
  void (*hdSetDoublev)(hd::HDenum, const hd::HDdouble*) = nullptr;
  hd::HDstring (*hdGetString)(hd::HDenum) = nullptr;
  hd::HDenum (*hdCheckCalibration)() = nullptr;
  void (*hdUpdateCalibration)(hd::HDenum) = nullptr;
  hd::HDSchedulerHandle (*hdScheduleAsynchronous)(hd::SchedulerCallback, void*, hd::HDushort) = nullptr;
  void (*hdUnschedule)(hd::HDSchedulerHandle) = nullptr;
  void (*hdStartScheduler)() = nullptr;
  void (*hdStopScheduler)() = nullptr;

  HdLibrary() = default;
  HdLibrary(const HdLibrary&) = delete;
  HdLibrary& operator=(const HdLibrary&) = delete;
  ~HdLibrary() {
    if (handle != nullptr) dlclose(handle);
  }

  // "<what>: <HD text> (HD error 0x0302, internal 7)" for the newest error, then drains the stack.
  // Empty when there is none. Control thread only: it allocates.
  std::string takeError(const std::string& what) const {
    hd::ErrorInfo e = hdGetError();
    if (e.errorCode == hd::kSuccess) return {};
    const char* text = hdGetErrorString(e.errorCode);
    char codes[64];
    std::snprintf(codes, sizeof codes, " (HD error 0x%04x, internal %d)", e.errorCode, e.internalErrorCode);
    std::string message = what + ": " + (text != nullptr ? text : "unknown HD error") + codes;
    drainErrors();
    return message;
  }
  // Empties HDAPI's error stack (bounded: a broken library must not hang us). No allocation.
  void drainErrors() const {
    for (int i = 0; i < 64; ++i)
      if (hdGetError().errorCode == hd::kSuccess) return;
  }
};

std::string libraryPath(const OpenHapticsOptions& options) {
  if (!options.library.empty()) return options.library;
  const char* env = std::getenv("DENTSIM_OPENHAPTICS_LIB");
  return env != nullptr && *env != '\0' ? std::string(env) : std::string("libHD.so");
}

template <class F>
bool resolve(void* handle, const char* symbol, F* out) {
  void* p = dlsym(handle, symbol);
  if (p == nullptr) return false;
  *out = reinterpret_cast<F>(p);
  return true;
}

Result<std::unique_ptr<HdLibrary>> loadHdLibrary(const std::string& path) {
  auto lib = std::make_unique<HdLibrary>();
  lib->path = path;
  dlerror();
  lib->handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (lib->handle == nullptr) {
    const char* why = dlerror();
    const std::string detail = why != nullptr ? why : "";
    // Absent is the ordinary case (no OpenHaptics on this machine); a library that is there but
    // does not load (a missing dependency, the wrong architecture) needs the loader's own words.
    if (detail.empty() || detail.find("No such file") != std::string::npos)
      return Error{"OpenHaptics not installed (" + path + " not found; set DENTSIM_OPENHAPTICS_LIB)"};
    return Error{"OpenHaptics library " + path + " does not load: " + detail};
  }
  HdLibrary& l = *lib;
  // The first symbol missing is named: a wrong file or an HDAPI too old for this plug-in.
  const char* missing = nullptr;
  auto need = [&](const char* symbol, auto* fn) {
    if (missing == nullptr && !resolve(l.handle, symbol, fn)) missing = symbol;
  };
  need("hdInitDevice", &l.hdInitDevice);
  need("hdDisableDevice", &l.hdDisableDevice);
  need("hdMakeCurrentDevice", &l.hdMakeCurrentDevice);
  need("hdGetError", &l.hdGetError);
  need("hdGetErrorString", &l.hdGetErrorString);
  need("hdBeginFrame", &l.hdBeginFrame);
  need("hdEndFrame", &l.hdEndFrame);
  need("hdEnable", &l.hdEnable);
  need("hdDisable", &l.hdDisable);
  need("hdGetDoublev", &l.hdGetDoublev);
  need("hdGetIntegerv", &l.hdGetIntegerv);
  need("hdSetDoublev", &l.hdSetDoublev);
  need("hdGetString", &l.hdGetString);
  need("hdCheckCalibration", &l.hdCheckCalibration);
  need("hdUpdateCalibration", &l.hdUpdateCalibration);
  need("hdScheduleAsynchronous", &l.hdScheduleAsynchronous);
  need("hdUnschedule", &l.hdUnschedule);
  need("hdStartScheduler", &l.hdStartScheduler);
  need("hdStopScheduler", &l.hdStopScheduler);
  if (missing != nullptr)
    return Error{"OpenHaptics library " + path + ": missing symbol " + missing + " (not an HDAPI library?)"};
  return lib;
}

// The HD_CALIBRATION_* style the library should update with, or 0 when the user has to act.
int updateStyle(int supported) {
  if (supported & hd::kCalibrationAuto) return hd::kCalibrationAuto;
  if (supported & hd::kCalibrationInkwell) return hd::kCalibrationInkwell;
  return 0;
}

// What the user does to calibrate a pen with these supported styles.
std::string calibrationAdvice(int supported) {
  if (supported & hd::kCalibrationInkwell) return "not calibrated: put the stylus in the inkwell";
  if (supported & hd::kCalibrationEncoderReset)
    return "not calibrated: hold the arm in its reset position and run Touch Diagnostic's calibration";
  return "not calibrated: move the stylus through its whole workspace";
}

// ---- 3. the pen ----

class OpenHapticsPen final : public HapticDevice {
 public:
  OpenHapticsPen(std::string device_name, const OpenHapticsOptions& options)
      : HapticDevice(options.safety), device_name_(std::move(device_name)), options_(options) {
    spec_.model = "OpenHaptics pen";
  }
  ~OpenHapticsPen() override { close(); }

  std::string name() const override { return "openhaptics:" + device_name_; }
  const DeviceSpec& spec() const override { return spec_; }

  Status open() override;
  void close() override;
  void service() override;
  bool read(double t_s, DeviceReading* out) override;

 private:
  static hd::HDCallbackCode servoCallback(void* self) { return static_cast<OpenHapticsPen*>(self)->servo(); }
  hd::HDCallbackCode servo();
  hd::HDCallbackCode servoFault(const hd::ErrorInfo& error, bool in_frame);
  Status fail(DeviceState state, const std::string& why);
  bool servoStoppedOnFault();
  Status readSpec();
  void shutDown();

  std::string device_name_;
  OpenHapticsOptions options_;
  DeviceSpec spec_;
  std::unique_ptr<HdLibrary> lib_;  // set while open; the servo callback uses it
  hd::HHD device_ = hd::kInvalidHandle;
  hd::HDSchedulerHandle servo_handle_ = 0;
  // HDAPI has one scheduler per process: stopped only by the pen that started it. (Two pens from
  // one process would need a shared owner for it; dentsim opens one OpenHaptics pen at a time.)
  bool scheduler_started_ = false;
  bool renders_torque_ = false;
  int calibration_styles_ = 0;

  // servo thread -> others
  SeqLock<DeviceReading> reading_;  // the servo callback's latest sample, for read()
  std::atomic<long> frames_{0};               // servo frames completed
  std::atomic<bool> calibrated_{false};
  std::atomic<bool> servo_running_{false};    // the callback is scheduled and has not returned DONE
  // others -> servo thread
  std::atomic<bool> stop_requested_{false};   // close(): send one zero frame and finish
  char fault_text_[256] = {};                 // why it stopped; written before servo_running_ goes false
  // servo thread only
  long calibration_countdown_ = 0;
};

Status OpenHapticsPen::fail(DeviceState state, const std::string& why) {
  setState(state, why);
  return makeError(name(), why);
}

// After a control-thread state change: if the servo loop has ended on an error meanwhile, its Fault wins.
bool OpenHapticsPen::servoStoppedOnFault() {
  if (lib_ == nullptr || servo_running_.load(std::memory_order_acquire) || fault_text_[0] == '\0') return false;
  if (state() != DeviceState::Fault) setState(DeviceState::Fault, fault_text_);
  return true;
}

Status OpenHapticsPen::open() {
  if (lib_ != nullptr) {
    if (servo_running_.load(std::memory_order_acquire)) return Ok{};  // open and running: state says how
    shutDown();  // its servo loop ended on a fault: start over
  }
  auto lib = loadHdLibrary(libraryPath(options_));
  if (!lib) return fail(DeviceState::Disconnected, lib.message());
  lib_ = std::move(*lib);
  HdLibrary& l = *lib_;
  l.drainErrors();  // errors left over from earlier use of the library

  // "Default" is HD_DEFAULT_DEVICE: the pen Touch Setup marks as the default.
  const char* config = device_name_ == "Default" ? hd::kDefaultDevice : device_name_.c_str();
  device_ = l.hdInitDevice(config);
  const std::string init_error = l.takeError("hdInitDevice(\"" + device_name_ + "\")");
  if (device_ == hd::kInvalidHandle || !init_error.empty()) {
    const std::string why = init_error.empty() ? "hdInitDevice(\"" + device_name_ + "\") failed" : init_error;
    if (device_ != hd::kInvalidHandle) l.hdDisableDevice(device_);
    device_ = hd::kInvalidHandle;
    lib_.reset();
    return fail(DeviceState::Disconnected, why);
  }
  l.hdMakeCurrentDevice(device_);
  if (Status s = readSpec(); !s) {
    shutDown();
    return fail(DeviceState::Disconnected, s.message());
  }
  safetyLayer().setLimits(spec_.max_force_n, spec_.max_torque_n_mm);

  // Forces go out only through the safety layer; the device's own clamp is a second line.
  l.hdEnable(hd::kForceOutput);
  l.hdEnable(hd::kMaxForceClamping);
  stop_requested_.store(false, std::memory_order_release);
  fault_text_[0] = '\0';
  calibration_countdown_ = 0;
  const long frames_before = frames_.load(std::memory_order_acquire);
  servo_running_.store(true, std::memory_order_release);
  servo_handle_ = l.hdScheduleAsynchronous(&OpenHapticsPen::servoCallback, this, hd::kMaxSchedulerPriority);
  l.hdStartScheduler();
  scheduler_started_ = true;
  if (std::string e = l.takeError("starting the HDAPI servo loop"); !e.empty()) {
    shutDown();
    return fail(DeviceState::Disconnected, e);
  }

  // Wait (bounded) for the first frame, so that the state below is the pen's, not a guess.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(kFirstFrameTimeoutMs);
  while (frames_.load(std::memory_order_acquire) == frames_before && servo_running_.load(std::memory_order_acquire) &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (servoStoppedOnFault()) return makeError(name(), reason());  // the first frame failed
  if (frames_.load(std::memory_order_acquire) == frames_before) {
    shutDown();
    char why[96];
    std::snprintf(why, sizeof why, "the HDAPI scheduler ran no servo frame within %d ms", kFirstFrameTimeoutMs);
    return fail(DeviceState::Disconnected, why);
  }
  if (!calibrated_.load(std::memory_order_acquire))
    setState(DeviceState::NeedsHoming, calibrationAdvice(calibration_styles_));
  else
    setState(DeviceState::Ready);
  if (servoStoppedOnFault()) return makeError(name(), reason());
  return Ok{};
}

Status OpenHapticsPen::readSpec() {
  HdLibrary& l = *lib_;
  const char* model = l.hdGetString(hd::kDeviceModelType);
  spec_.model = model != nullptr && *model != '\0' ? model : "OpenHaptics pen";
  double workspace[6] = {0, 0, 0, 0, 0, 0};
  l.hdGetDoublev(hd::kNominalMaxForce, &spec_.max_force_n);
  l.hdGetDoublev(hd::kNominalMaxStiffness, &spec_.max_stiffness_n_per_mm);
  l.hdGetDoublev(hd::kNominalMaxDamping, &spec_.max_damping_n_s_per_mm);
  l.hdGetDoublev(hd::kUsableWorkspaceDimensions, workspace);
  int input_dof = 3, output_dof = 3, rate_hz = 1000;
  l.hdGetIntegerv(hd::kInputDof, &input_dof);
  l.hdGetIntegerv(hd::kOutputDof, &output_dof);
  l.hdGetIntegerv(hd::kCalibrationStyle, &calibration_styles_);
  l.hdGetIntegerv(hd::kUpdateRate, &rate_hz);
  // Touch, Omni and Touch X render force only (3 output DOF); the 6-DOF Premium renders torque too.
  renders_torque_ = output_dof >= 6;
  spec_.max_torque_n_mm = 0.0;
  if (renders_torque_) {
    double max_torque_mn_m = 0.0;
    l.hdGetDoublev(hd::kNominalMaxTorqueForce, &max_torque_mn_m);
    spec_.max_torque_n_mm = max_torque_mn_m * kNmmPerMilliNm;
  }
  if (std::string e = l.takeError("reading the pen's properties"); !e.empty()) return Error{e};
  if (!(spec_.max_force_n > 0) || !std::isfinite(spec_.max_force_n)) {
    char why[96];
    std::snprintf(why, sizeof why, "HDAPI reports a maximum force of %g N; refusing to drive it", spec_.max_force_n);
    return Error{why};
  }
  spec_.workspace_min_mm = {workspace[0], workspace[1], workspace[2]};
  spec_.workspace_max_mm = {workspace[3], workspace[4], workspace[5]};
  spec_.rate_hz = rate_hz > 0 ? rate_hz : 1000.0;
  spec_.senses_rotation = input_dof >= 6;
  spec_.physical = true;
  return Ok{};
}

// The servo callback, on HDAPI's scheduler thread at about 1 kHz: sample, then send output(). It
// never allocates or blocks on the steady path; only the one-time fault path below builds a reason.
hd::HDCallbackCode OpenHapticsPen::servo() {
  HdLibrary& l = *lib_;
  l.hdMakeCurrentDevice(device_);
  if (calibration_countdown_-- <= 0) {
    hd::HDenum c = l.hdCheckCalibration();
    // Auto and inkwell pens recalibrate by themselves once asked; others wait for the user.
    if (c == hd::kCalibrationNeedsUpdate && updateStyle(calibration_styles_) != 0) {
      l.hdUpdateCalibration(static_cast<hd::HDenum>(updateStyle(calibration_styles_)));
      c = l.hdCheckCalibration();
    }
    const bool ok = c == hd::kCalibrationOk;
    calibrated_.store(ok, std::memory_order_release);
    calibration_countdown_ = ok ? kCalibrationCheckPeriod : 0;
  }

  l.hdBeginFrame(device_);
  double position[3] = {0, 0, 0}, velocity[3] = {0, 0, 0}, angular_velocity[3] = {0, 0, 0};
  double transform[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  int buttons = 0;
  l.hdGetDoublev(hd::kCurrentPosition, position);
  l.hdGetDoublev(hd::kCurrentVelocity, velocity);
  l.hdGetDoublev(hd::kCurrentTransform, transform);
  l.hdGetDoublev(hd::kCurrentAngularVelocity, angular_velocity);
  l.hdGetIntegerv(hd::kCurrentButtons, &buttons);
  if (const hd::ErrorInfo e = l.hdGetError(); e.errorCode != hd::kSuccess) return servoFault(e, true);

  const int64_t now_ns = steadyNowNs();
  DeviceReading r;
  r.pose.position = {position[0], position[1], position[2]};
  // HDAPI's transform is column-major 4x4 (OpenGL's layout): its rotation, row by row.
  r.pose.rotation = Quat::fromMatrix({transform[0], transform[4], transform[8], transform[1], transform[5], transform[9],
                                      transform[2], transform[6], transform[10]});
  r.velocity = {velocity[0], velocity[1], velocity[2]};
  r.angular_velocity = {angular_velocity[0], angular_velocity[1], angular_velocity[2]};
  r.buttons = static_cast<uint32_t>(buttons);
  r.stamp_ns = now_ns;
  reading_.store(r);

  const bool stopping = stop_requested_.load(std::memory_order_acquire);
  // The only force source: the safety layer's answer (zero unless enabled, armed and fresh).
  const Wrench w = stopping ? Wrench{} : output(now_ns).wrench;
  const double force[3] = {w.force.x, w.force.y, w.force.z};
  l.hdSetDoublev(hd::kCurrentForce, force);
  if (renders_torque_) {
    const double torque[3] = {w.moment.x / kNmmPerMilliNm, w.moment.y / kNmmPerMilliNm, w.moment.z / kNmmPerMilliNm};
    l.hdSetDoublev(hd::kCurrentTorque, torque);
  }
  l.hdEndFrame(device_);
  if (const hd::ErrorInfo e = l.hdGetError(); e.errorCode != hd::kSuccess) return servoFault(e, false);
  frames_.fetch_add(1, std::memory_order_acq_rel);
  if (stopping) {
    servo_running_.store(false, std::memory_order_release);
    return hd::kCallbackDone;
  }
  return hd::kCallbackContinue;
}

// Any HD error in the servo loop: zero force (in this frame if one is open, else in one more),
// force output off, Fault with HDAPI's words, and the callback ends. Reopening is the way back.
hd::HDCallbackCode OpenHapticsPen::servoFault(const hd::ErrorInfo& error, bool in_frame) {
  HdLibrary& l = *lib_;
  safetyLayer().disable();
  const double zero[3] = {0, 0, 0};
  if (!in_frame) l.hdBeginFrame(device_);
  l.hdSetDoublev(hd::kCurrentForce, zero);
  if (renders_torque_) l.hdSetDoublev(hd::kCurrentTorque, zero);
  l.hdEndFrame(device_);
  l.hdDisable(hd::kForceOutput);
  l.drainErrors();  // the rest (often the same error again from the zero frame) adds nothing
  const char* text = l.hdGetErrorString(error.errorCode);
  std::snprintf(fault_text_, sizeof fault_text_,
                "HDAPI servo loop: %s (HD error 0x%04x, internal %d); zero force, close and open the pen again",
                text != nullptr ? text : "unknown HD error", error.errorCode, error.internalErrorCode);
  // Stopped before Fault is set: a control thread that sets a state after seeing the loop still
  // running is overwritten by this Fault, and one that sees it stopped sets Fault itself.
  servo_running_.store(false, std::memory_order_release);
  // The servo loop ends here, so this one allocation (the reason string) is off its steady path.
  setState(DeviceState::Fault, fault_text_);
  return hd::kCallbackDone;
}

bool OpenHapticsPen::read(double /*t_s*/, DeviceReading* out) {
  if (!tracking(state())) return false;
  return reading_.load(out);
}

void OpenHapticsPen::service() {
  if (servoStoppedOnFault()) return;
  const DeviceState s = state();
  if (s == DeviceState::NeedsHoming && calibrated_.load(std::memory_order_acquire) &&
      servo_running_.load(std::memory_order_acquire)) {
    setState(DeviceState::Ready);
  } else if ((s == DeviceState::Ready || s == DeviceState::Enabled) && !calibrated_.load(std::memory_order_acquire)) {
    setState(DeviceState::NeedsHoming, calibrationAdvice(calibration_styles_));
  }
}

// Stops the servo loop (after one zero-force frame when it still runs) and releases everything.
void OpenHapticsPen::shutDown() {
  if (lib_ == nullptr) return;
  HdLibrary& l = *lib_;
  safetyLayer().disable();
  if (servo_running_.load(std::memory_order_acquire)) {
    stop_requested_.store(true, std::memory_order_release);
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(kLastFrameTimeoutMs);
    while (servo_running_.load(std::memory_order_acquire) && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  if (scheduler_started_) l.hdStopScheduler();
  scheduler_started_ = false;
  // A callback that never answered is still scheduled: take it out before the library goes.
  if (servo_running_.exchange(false, std::memory_order_acq_rel)) l.hdUnschedule(servo_handle_);
  if (device_ != hd::kInvalidHandle) {
    l.hdMakeCurrentDevice(device_);
    l.hdDisable(hd::kForceOutput);
    l.hdDisableDevice(device_);
  }
  l.drainErrors();
  device_ = hd::kInvalidHandle;
  lib_.reset();  // dlclose
}

void OpenHapticsPen::close() {
  const bool was_open = lib_ != nullptr;
  shutDown();
  if (was_open || state() != DeviceState::Disconnected) setState(DeviceState::Disconnected, "closed");
}

}  // namespace

// ---- 4. enumeration and the factory ----

std::vector<DeviceEntry> enumerateOpenHaptics(const OpenHapticsOptions& options) {
  const std::string path = libraryPath(options);
  DeviceEntry entry;
  entry.name = "openhaptics:Default";
  entry.kind = "pen";
  entry.model = "OpenHaptics pen";
  entry.location = path;
  auto lib = loadHdLibrary(path);
  if (!lib) {
    entry.state = DeviceState::Disconnected;
    entry.reason = lib.message();
    return {entry};
  }
  // HDAPI cannot list its configurations; the default one is probed by opening it briefly. A pen
  // that is in use elsewhere answers with an error, which becomes the reason.
  HdLibrary& l = **lib;
  l.drainErrors();
  const hd::HHD device = l.hdInitDevice(hd::kDefaultDevice);
  const std::string error = l.takeError("hdInitDevice(\"Default\")");
  if (device == hd::kInvalidHandle || !error.empty()) {
    if (device != hd::kInvalidHandle) l.hdDisableDevice(device);
    entry.state = DeviceState::Disconnected;
    entry.reason = error.empty() ? "hdInitDevice(\"Default\") failed" : error;
    return {entry};
  }
  l.hdMakeCurrentDevice(device);
  if (const char* model = l.hdGetString(hd::kDeviceModelType); model != nullptr && *model != '\0') entry.model = model;
  if (const char* serial = l.hdGetString(hd::kDeviceSerialNumber); serial != nullptr && *serial != '\0')
    entry.location = path + " (serial " + serial + ")";
  int styles = 0;
  l.hdGetIntegerv(hd::kCalibrationStyle, &styles);
  const hd::HDenum calibration = l.hdCheckCalibration();
  entry.state = calibration == hd::kCalibrationNeedsManualInput ? DeviceState::NeedsHoming : DeviceState::Ready;
  if (entry.state == DeviceState::NeedsHoming) entry.reason = calibrationAdvice(styles);
  l.hdDisableDevice(device);
  l.drainErrors();
  return {entry};
}

std::unique_ptr<HapticDevice> makeOpenHapticsPen(const std::string& device_name, const OpenHapticsOptions& options) {
  return std::make_unique<OpenHapticsPen>(device_name, options);
}

}  // namespace dentsim::devices
