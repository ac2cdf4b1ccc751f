// OpenHaptics plug-in: loads the vendor's HDAPI with dlopen, runs one 1 kHz servo callback for every open pen, and keeps each pen's state.
//
// Sections: 1. HDAPI declarations  2. the loaded library  3. the shared scheduler and the pen: open,
// servo frame, read, service, close  4. enumeration and the factory.
//
// The build never needs OpenHaptics: the handful of HDAPI types, values and entry points used here
// are declared below from the OpenHaptics HDAPI reference (its headers hd.h, hdScheduler.h and
// hdDefines.h, OpenHaptics 3.x), and resolved by name at run time. HDAPI works in millimetres and
// newtons, as dentsim does; torques are in mN m, which is exactly N mm.
#include "devices/openhaptics_pen.h"

#include <dirent.h>
#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "core/seqlock.h"
#include "core/steady_clock.h"
#include "devices/hdapi_abi.h"
#include "devices/touch_serial.h"

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

// ---- 3. the scheduler every open pen shares, and the pen ----

class OpenHapticsPen;

// HDAPI has one scheduler per process, and one current device. dentsim's pens therefore share one
// HdServo while any is open: the library, the scheduler, and one servo callback that serves every
// open pen in turn, each made current and inside its own begin/end frame (as the vendor's
// dual-device examples do). A control thread only addresses a device while the scheduler is
// stopped, so it never switches the current device under the servo thread; every stop is preceded
// by a pass of zero-force frames, so no pen is left pushing when the scheduler stops.
class HdServo {
 public:
  // The one for `library_path`, loading it when no pen is open. Another library while pens from
  // one are open is an error: a process cannot hold two HDAPIs.
  static Result<std::shared_ptr<HdServo>> acquire(const std::string& library_path);
  explicit HdServo(std::unique_ptr<HdLibrary> lib) : lib_(std::move(lib)) {}
  ~HdServo();
  HdServo(const HdServo&) = delete;
  HdServo& operator=(const HdServo&) = delete;

  HdLibrary& lib() { return *lib_; }
  // Control thread: stops the scheduler (zero frames first), runs `init`, which may address the
  // new pen's device, then serves `pen` too and starts the scheduler again. On an error the pen is
  // not served, and the other pens run on.
  Status attach(OpenHapticsPen* pen, const std::function<Status()>& init);
  // Control thread: the same stop, then `pen` is served no more and `release` may address its
  // device; the scheduler starts again when other pens are left.
  void detach(OpenHapticsPen* pen, const std::function<void()>& release);

 private:
  static hd::HDCallbackCode callback(void* self);
  void pause();   // zero frames for every pen, then stop; control_ held
  Status resume();  // start when any pen is served; control_ held

  static constexpr size_t kMaxPens = 4;  // drill and mirror, and room for a teacher's pair
  std::unique_ptr<HdLibrary> lib_;
  std::mutex control_;  // attach and detach, from any control thread
  std::array<std::atomic<OpenHapticsPen*>, kMaxPens> pens_{};
  std::atomic<bool> zero_all_{false};  // the servo callback sends zero to every pen
  std::atomic<long> passes_{0};        // servo callback passes completed
  bool running_ = false;               // control_ held
  bool scheduled_ = false;
  hd::HDSchedulerHandle handle_ = 0;
};

std::mutex g_servo_mutex;
std::weak_ptr<HdServo> g_servo;  // alive while any pen holds it

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

  // Servo thread, from HdServo's callback: one frame for this pen (zero force when `zero`).
  void servoFrame(bool zero);

 private:
  void servoFault(const hd::ErrorInfo& error, bool in_frame);
  Status fail(DeviceState state, const std::string& why);
  bool servoStoppedOnFault();
  Status initDevice();
  Status readSpec();
  void shutDown();

  std::string device_name_;
  OpenHapticsOptions options_;
  DeviceSpec spec_;
  std::shared_ptr<HdServo> servo_;  // set while open
  HdLibrary* lib_ = nullptr;        // servo_'s library, for the servo thread
  hd::HHD device_ = hd::kInvalidHandle;
  bool renders_torque_ = false;
  int calibration_styles_ = 0;

  // servo thread -> others
  SeqLock<DeviceReading> reading_;  // the servo callback's latest sample, for read()
  std::atomic<long> frames_{0};               // servo frames completed
  std::atomic<bool> calibrated_{false};
  std::atomic<bool> servo_running_{false};    // served and not stopped by a fault
  char fault_text_[256] = {};                 // why it stopped; written before servo_running_ goes false
  // servo thread only
  long calibration_countdown_ = 0;
  // read()'s thread only: the newest sample it got, for a read that finds the servo mid-store
  DeviceReading last_reading_;
  bool have_last_reading_ = false;
};

// ---- the shared scheduler ----

Result<std::shared_ptr<HdServo>> HdServo::acquire(const std::string& library_path) {
  std::lock_guard lock(g_servo_mutex);
  if (auto servo = g_servo.lock()) {
    if (servo->lib().path != library_path)
      return Error{"OpenHaptics library " + library_path + ": pens from " + servo->lib().path +
                   " are open in this dentsim, and one process holds one HDAPI"};
    return servo;
  }
  auto lib = loadHdLibrary(library_path);
  if (!lib) return lib.error();
  (*lib)->drainErrors();  // errors left over from earlier use of the library
  auto servo = std::make_shared<HdServo>(std::move(*lib));
  g_servo = servo;
  return servo;
}

HdServo::~HdServo() {
  std::lock_guard lock(control_);
  pause();
  if (scheduled_) lib_->hdUnschedule(handle_);
  lib_->drainErrors();
}

hd::HDCallbackCode HdServo::callback(void* self) {
  HdServo& s = *static_cast<HdServo*>(self);
  const bool zero = s.zero_all_.load(std::memory_order_acquire);
  for (auto& slot : s.pens_)
    if (OpenHapticsPen* pen = slot.load(std::memory_order_acquire)) pen->servoFrame(zero);
  s.passes_.fetch_add(1, std::memory_order_acq_rel);
  return hd::kCallbackContinue;
}

void HdServo::pause() {
  if (!running_) return;
  // Two whole passes of zero frames (the first may have begun before the flag): every served pen's
  // motors read zero before the scheduler stops. Bounded: a stalled scheduler is stopped anyway.
  zero_all_.store(true, std::memory_order_release);
  const long target = passes_.load(std::memory_order_acquire) + 2;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(kLastFrameTimeoutMs);
  while (passes_.load(std::memory_order_acquire) < target && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  lib_->hdStopScheduler();
  running_ = false;
  zero_all_.store(false, std::memory_order_release);
}

Status HdServo::resume() {
  bool any = false;
  for (auto& slot : pens_) any = any || slot.load(std::memory_order_acquire) != nullptr;
  if (!any) return Ok{};
  if (!scheduled_) {
    handle_ = lib_->hdScheduleAsynchronous(&HdServo::callback, this, hd::kMaxSchedulerPriority);
    scheduled_ = true;
  }
  lib_->hdStartScheduler();
  running_ = true;
  if (std::string e = lib_->takeError("starting the HDAPI servo loop"); !e.empty()) return Error{e};
  return Ok{};
}

Status HdServo::attach(OpenHapticsPen* pen, const std::function<Status()>& init) {
  std::lock_guard lock(control_);
  pause();
  Status st = init();
  if (st) {
    auto free_slot = std::find_if(pens_.begin(), pens_.end(), [](const auto& s) { return s.load() == nullptr; });
    if (free_slot == pens_.end()) st = Error{"more OpenHaptics pens than dentsim serves at once (4)"};
    else free_slot->store(pen, std::memory_order_release);
  }
  Status started = resume();
  if (!st) return st;
  if (!started) {
    for (auto& slot : pens_)
      if (slot.load() == pen) slot.store(nullptr, std::memory_order_release);
    return started;
  }
  return Ok{};
}

void HdServo::detach(OpenHapticsPen* pen, const std::function<void()>& release) {
  std::lock_guard lock(control_);
  pause();
  for (auto& slot : pens_)
    if (slot.load() == pen) slot.store(nullptr, std::memory_order_release);
  release();
  (void)resume();  // an error starting again shows in the other pens' first frames
}

// ---- the pen ----

Status OpenHapticsPen::fail(DeviceState state, const std::string& why) {
  setState(state, why);
  return makeError(name(), why);
}

// After a control-thread state change: if the servo loop has ended on an error meanwhile, its Fault wins.
bool OpenHapticsPen::servoStoppedOnFault() {
  if (servo_ == nullptr || servo_running_.load(std::memory_order_acquire) || fault_text_[0] == '\0') return false;
  if (state() != DeviceState::Fault) setState(DeviceState::Fault, fault_text_);
  return true;
}

// Inside HdServo::attach, scheduler stopped: the device by its configuration name, its spec, force on.
Status OpenHapticsPen::initDevice() {
  HdLibrary& l = *lib_;
  // "Default" is HD_DEFAULT_DEVICE: the pen Touch Setup marks as the default.
  const char* config = device_name_ == "Default" ? hd::kDefaultDevice : device_name_.c_str();
  device_ = l.hdInitDevice(config);
  const std::string init_error = l.takeError("hdInitDevice(\"" + device_name_ + "\")");
  if (device_ == hd::kInvalidHandle || !init_error.empty()) {
    std::string why = init_error.empty() ? "hdInitDevice(\"" + device_name_ + "\") failed" : init_error;
    if (device_ != hd::kInvalidHandle) l.hdDisableDevice(device_);
    device_ = hd::kInvalidHandle;
    l.drainErrors();
    // HDAPI does not say why; a Touch's serial node closed to this user is the usual reason.
    if (const std::string denied = touchSerialPermissionProblem(options_.sysfs_root, options_.dev_root); !denied.empty())
      why = denied + " (" + why + ")";
    return Error{why};
  }
  l.hdMakeCurrentDevice(device_);
  if (Status s = readSpec(); !s) {
    l.hdDisableDevice(device_);
    device_ = hd::kInvalidHandle;
    l.drainErrors();
    return s;
  }
  safetyLayer().setLimits(spec_.max_force_n, spec_.max_torque_n_mm);
  // Forces go out only through the safety layer; the device's own clamp is a second line.
  l.hdEnable(hd::kForceOutput);
  l.hdEnable(hd::kMaxForceClamping);
  fault_text_[0] = '\0';
  calibration_countdown_ = 0;
  servo_running_.store(true, std::memory_order_release);
  return Ok{};
}

Status OpenHapticsPen::open() {
  if (servo_ != nullptr) {
    if (servo_running_.load(std::memory_order_acquire)) return Ok{};  // open and running: state says how
    shutDown();  // its servo loop ended on a fault: start over
  }
  auto servo = HdServo::acquire(libraryPath(options_));
  if (!servo) return fail(DeviceState::Disconnected, servo.message());
  servo_ = std::move(*servo);
  lib_ = &servo_->lib();
  const long frames_before = frames_.load(std::memory_order_acquire);
  if (Status st = servo_->attach(this, [this] { return initDevice(); }); !st) {
    shutDown();
    return fail(DeviceState::Disconnected, st.message());
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

// One servo frame, on HDAPI's scheduler thread at about 1 kHz: sample, then send output(). It
// never allocates or blocks on the steady path; only the one-time fault path below builds a reason.
void OpenHapticsPen::servoFrame(bool zero) {
  if (!servo_running_.load(std::memory_order_acquire)) return;  // stopped on a fault: served no more
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

  // The only force source: the safety layer's answer (zero unless enabled, armed and fresh, and
  // zero while the other pen of the student is down). Asked even when the scheduler is about to
  // stop, so that the watchdog keeps counting.
  const Wrench asked = output(now_ns).wrench;
  const Wrench w = zero ? Wrench{} : asked;
  const double force[3] = {w.force.x, w.force.y, w.force.z};
  l.hdSetDoublev(hd::kCurrentForce, force);
  if (renders_torque_) {
    const double torque[3] = {w.moment.x / kNmmPerMilliNm, w.moment.y / kNmmPerMilliNm, w.moment.z / kNmmPerMilliNm};
    l.hdSetDoublev(hd::kCurrentTorque, torque);
  }
  l.hdEndFrame(device_);
  if (const hd::ErrorInfo e = l.hdGetError(); e.errorCode != hd::kSuccess) return servoFault(e, false);
  frames_.fetch_add(1, std::memory_order_acq_rel);
}

// Any HD error in this pen's frame: the other pens of the student are told first (their next frame,
// in this same pass where they come after this one, is zero), then this pen gets a zero frame,
// force output off, Fault with HDAPI's words, and it is served no more. Reopening is the way back.
void OpenHapticsPen::servoFault(const hd::ErrorInfo& error, bool in_frame) {
  HdLibrary& l = *lib_;
  safetyLayer().haltGroup();
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
  // This pen's frames end here, so this one allocation (the reason string) is off its steady path.
  setState(DeviceState::Fault, fault_text_);
}

bool OpenHapticsPen::read(double /*t_s*/, DeviceReading* out) {
  if (!tracking(state())) return false;
  if (reading_.load(out)) {
    last_reading_ = *out;
    have_last_reading_ = true;
    return true;
  }
  // The servo thread is inside its store (preempted there on a loaded machine): the previous
  // sample, a servo frame older, stands, rather than a pen that seems to vanish for a step.
  if (!have_last_reading_) return false;
  *out = last_reading_;
  return true;
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

// Zero force, out of the shared servo callback (the scheduler stops for the moment, after zero
// frames for every pen, and runs on for the others), the device released.
void OpenHapticsPen::shutDown() {
  if (servo_ == nullptr) return;
  safetyLayer().disable();
  servo_->detach(this, [this] {
    if (device_ == hd::kInvalidHandle) return;
    HdLibrary& l = *lib_;
    l.hdMakeCurrentDevice(device_);
    l.hdDisable(hd::kForceOutput);
    l.hdDisableDevice(device_);
    l.drainErrors();
  });
  servo_running_.store(false, std::memory_order_release);
  device_ = hd::kInvalidHandle;
  lib_ = nullptr;
  servo_.reset();  // the last pen's: the scheduler is unscheduled and the library closed
}

void OpenHapticsPen::close() {
  const bool was_open = servo_ != nullptr;
  shutDown();
  if (was_open || state() != DeviceState::Disconnected) setState(DeviceState::Disconnected, "closed");
}

}  // namespace

// ---- 4. enumeration and the factory ----

std::vector<std::string> configuredOpenHapticsNames() {
  // Touch Setup saves one NAME.config per pen in $GTDD_HOME/config (the driver's install guides set
  // GTDD_HOME to /usr/share/3DSystems); "Default Device" is the one HD_DEFAULT_DEVICE opens.
  const char* home = std::getenv("GTDD_HOME");
  const std::string dir = std::string(home != nullptr && *home != '\0' ? home : "/usr/share/3DSystems") + "/config";
  std::vector<std::string> names;
  if (DIR* d = opendir(dir.c_str())) {
    while (const dirent* e = readdir(d)) {
      const std::string file = e->d_name;
      const std::string ext = ".config";
      if (file.size() <= ext.size() || file.compare(file.size() - ext.size(), ext.size(), ext) != 0) continue;
      const std::string name = file.substr(0, file.size() - ext.size());
      names.push_back(name == "Default Device" ? "Default" : name);
    }
    closedir(d);
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<DeviceEntry> enumerateOpenHaptics(const OpenHapticsOptions& options) {
  const std::string path = libraryPath(options);
  std::vector<std::string> names = configuredOpenHapticsNames();
  if (names.empty()) names.push_back("Default");  // no configuration folder: what HD_DEFAULT_DEVICE finds
  std::vector<DeviceEntry> entries;
  for (const std::string& name : names) {
    DeviceEntry entry;
    entry.name = "openhaptics:" + name;
    entry.kind = "pen";
    entry.model = "OpenHaptics pen";
    entry.location = path;
    entries.push_back(entry);
  }
  auto lib = loadHdLibrary(path);
  if (!lib) {
    for (DeviceEntry& e : entries) {
      e.state = DeviceState::Disconnected;
      e.reason = lib.message();
    }
    return entries;
  }
  {
    std::lock_guard lock(g_servo_mutex);
    if (!g_servo.expired()) {
      // Probing would address devices under the running servo loop: say so instead.
      for (DeviceEntry& e : entries) {
        e.state = DeviceState::Disconnected;
        e.reason = "not probed: OpenHaptics pens are open in this dentsim";
      }
      return entries;
    }
  }
  // HDAPI cannot list its pens; each configured one is probed by opening it briefly. A pen that is
  // in use elsewhere, or unplugged, answers with an error, which becomes the reason.
  HdLibrary& l = **lib;
  l.drainErrors();
  for (size_t i = 0; i < entries.size(); ++i) {
    DeviceEntry& entry = entries[i];
    const std::string& name = names[i];
    const hd::HHD device = l.hdInitDevice(name == "Default" ? hd::kDefaultDevice : name.c_str());
    const std::string error = l.takeError("hdInitDevice(\"" + name + "\")");
    if (device == hd::kInvalidHandle || !error.empty()) {
      if (device != hd::kInvalidHandle) l.hdDisableDevice(device);
      entry.state = DeviceState::Disconnected;
      entry.reason = error.empty() ? "hdInitDevice(\"" + name + "\") failed" : error;
      if (const std::string denied = touchSerialPermissionProblem(options.sysfs_root, options.dev_root); !denied.empty())
        entry.reason = denied + " (" + entry.reason + ")";
      l.drainErrors();
      continue;
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
  }
  return entries;
}

std::unique_ptr<HapticDevice> makeOpenHapticsPen(const std::string& device_name, const OpenHapticsOptions& options) {
  return std::make_unique<OpenHapticsPen>(device_name, options);
}

}  // namespace dentsim::devices
