// Fake HDAPI library: one simulated pen named "Default" with a 1 kHz scheduler thread, for the OpenHaptics plug-in tests.
//
// It exports the HDAPI entry points the plug-in resolves (C linkage, the vendor's names and
// signatures as given in the OpenHaptics HDAPI reference headers hd.h, hdScheduler.h and
// hdDefines.h), plus fakeHd* controls through which a test sets the pen's pose, buttons and
// calibration, injects an error, and reads back what the plug-in sent to the "motors".
//
// Sections: 1. HDAPI types and values  2. the simulated pen  3. HDAPI entry points  4. test controls
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstring>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "devices/hdapi_abi.h"

namespace {

// ---- 1. HDAPI types and values: the plug-in's own declarations (devices/hdapi_abi.h) ----
using namespace dentsim::devices::hd;
using HDErrorInfo = ErrorInfo;
using HDSchedulerCallback = SchedulerCallback;
constexpr HHD kDefaultHandle = 1;

// ---- 2. the simulated pen ----
// Its numbers are those of a 3D Systems Touch as its data sheet gives them; the tests read them
// back through the plug-in's spec, so any plausible values would do.
struct Pen {
  std::string model = "Touch";
  double max_force_n = 3.3;
  double max_stiffness_n_per_mm = 1.26;
  double max_damping_n_s_per_mm = 0.002;
  double max_torque_mn_m = 0.0;
  int output_dof = 3;
  int input_dof = 6;
  double workspace[6] = {-80, -60, -35, 80, 60, 35};  // min xyz, max xyz [mm]
  double position[3] = {0, 0, 0};                      // [mm]
  double velocity[3] = {0, 0, 0};                      // [mm/s]
  double transform[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};  // column-major
  double angular_velocity[3] = {0, 0, 0};              // [rad/s]
  int buttons = 0;
  HDenum calibration = kCalibrationOk;
  int calibration_styles = 1 << 1;                     // HD_CALIBRATION_AUTO
  int calibration_updates = 0;
  HDenum last_update_style = 0;

  bool initialized = false;
  bool force_output = false;
  bool in_frame = false;
  double frame_force[3] = {0, 0, 0};   // what the frame in progress was given
  double frame_torque[3] = {0, 0, 0};
  double sent_force[3] = {0, 0, 0};    // what the last hdEndFrame sent to the motors [N]
  double sent_torque[3] = {0, 0, 0};   // [mN m]
  long frames = 0;

  HDerror pending_error = kSuccess;    // injected by the test, raised at the next hdBeginFrame
  int pending_internal = 0;
  std::vector<HDErrorInfo> errors;     // HDAPI's error stack: most recent last here
};

struct Scheduled {
  HDSchedulerHandle handle;
  HDSchedulerCallback callback;
  void* user;
};

struct Fake {
  std::mutex pen_mutex;  // the pen's state: the test thread and the scheduler thread both touch it
  Pen pen;

  std::mutex schedule_mutex;  // the callback list; held while callbacks run, so unschedule waits them out
  std::vector<Scheduled> scheduled;
  HDSchedulerHandle next_handle = 1;
  std::thread scheduler;
  std::atomic<bool> scheduler_running{false};
  std::atomic<std::thread::id> scheduler_id{};

  // A test that ends with the scheduler running must not take std::terminate down with it.
  ~Fake() {
    scheduler_running.store(false);
    if (scheduler.joinable()) scheduler.join();
  }
};

Fake& fake() {
  static Fake f;
  return f;
}

void pushError(Pen& pen, HDerror code, int internal = 0) {
  pen.errors.push_back(HDErrorInfo{code, internal, pen.initialized ? kDefaultHandle : kInvalidHandle});
}

void schedulerLoop() {
  Fake& f = fake();
  auto next = std::chrono::steady_clock::now();
  while (f.scheduler_running.load(std::memory_order_acquire)) {
    {
      std::lock_guard lock(f.schedule_mutex);
      for (size_t i = 0; i < f.scheduled.size();) {
        if (f.scheduled[i].callback(f.scheduled[i].user) == kCallbackDone)
          f.scheduled.erase(f.scheduled.begin() + static_cast<long>(i));
        else
          ++i;
      }
    }
    next += std::chrono::milliseconds(1);
    const auto now = std::chrono::steady_clock::now();
    if (next < now) next = now;  // late: skip the missed ticks rather than burst through them
    std::this_thread::sleep_until(next);
  }
}

bool onSchedulerThread() { return fake().scheduler_id.load() == std::this_thread::get_id(); }

void copy3(double* to, const double* from) { std::copy(from, from + 3, to); }

}  // namespace

// ---- 3. HDAPI entry points ----
extern "C" {

HHD hdInitDevice(HDstring config_name) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  // The one configured pen answers to HD_DEFAULT_DEVICE (null) and to its configuration name.
  if (config_name != nullptr && std::strcmp(config_name, "Default") != 0) {
    f.pen.errors.push_back(HDErrorInfo{kDeviceFault, 3, kInvalidHandle});
    return kInvalidHandle;
  }
  if (f.pen.initialized) {
    pushError(f.pen, kDeviceAlreadyInitiated);
    return kInvalidHandle;
  }
  f.pen.initialized = true;
  return kDefaultHandle;
}

void hdDisableDevice(HHD handle) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (handle != kDefaultHandle || !f.pen.initialized) return pushError(f.pen, kBadHandle);
  f.pen.initialized = false;
  f.pen.force_output = false;
  std::fill(f.pen.sent_force, f.pen.sent_force + 3, 0.0);
  std::fill(f.pen.sent_torque, f.pen.sent_torque + 3, 0.0);
}

void hdMakeCurrentDevice(HHD handle) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (handle != kDefaultHandle || !f.pen.initialized) pushError(f.pen, kBadHandle);
}

HDErrorInfo hdGetError() {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (f.pen.errors.empty()) return HDErrorInfo{kSuccess, 0, kInvalidHandle};
  const HDErrorInfo e = f.pen.errors.back();
  f.pen.errors.pop_back();
  return e;
}

HDstring hdGetErrorString(HDerror code) {
  switch (code) {
    case kSuccess: return "no error";
    case kInvalidEnum: return "invalid enumeration";
    case kInvalidOperation: return "invalid operation";
    case kBadHandle: return "bad device handle";
    case kDeviceFault: return "device fault (fake HDAPI): no such device configuration";
    case kDeviceAlreadyInitiated: return "device already initiated";
    case kCommError: return "communication error (fake HDAPI)";
    case kIllegalBegin: return "illegal begin frame";
    case kIllegalEnd: return "illegal end frame";
    default: return "unknown error";
  }
}

void hdBeginFrame(HHD handle) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen& pen = f.pen;
  if (handle != kDefaultHandle || !pen.initialized) return pushError(pen, kBadHandle);
  if (pen.in_frame) return pushError(pen, kIllegalBegin);
  pen.in_frame = true;
  std::fill(pen.frame_force, pen.frame_force + 3, 0.0);
  std::fill(pen.frame_torque, pen.frame_torque + 3, 0.0);
  if (pen.pending_error != kSuccess) {
    pushError(pen, pen.pending_error, pen.pending_internal);
    pen.pending_error = kSuccess;
  }
}

void hdEndFrame(HHD handle) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen& pen = f.pen;
  if (handle != kDefaultHandle || !pen.initialized) return pushError(pen, kBadHandle);
  if (!pen.in_frame) return pushError(pen, kIllegalEnd);
  pen.in_frame = false;
  // Like the real device: what a frame did not set is zero, and nothing goes out while force
  // output is disabled.
  for (int i = 0; i < 3; ++i) {
    pen.sent_force[i] = pen.force_output ? pen.frame_force[i] : 0.0;
    pen.sent_torque[i] = pen.force_output ? pen.frame_torque[i] : 0.0;
  }
  ++pen.frames;
}

void hdEnable(HDenum cap) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (cap == kForceOutput) f.pen.force_output = true;
  else if (cap != kMaxForceClamping) pushError(f.pen, kInvalidEnum);
}

void hdDisable(HDenum cap) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (cap == kForceOutput) f.pen.force_output = false;
  else if (cap != kMaxForceClamping) pushError(f.pen, kInvalidEnum);
}

void hdGetDoublev(HDenum name, HDdouble* out) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen& pen = f.pen;
  switch (name) {
    case kCurrentPosition: return copy3(out, pen.position);
    case kCurrentVelocity: return copy3(out, pen.velocity);
    case kCurrentAngularVelocity: return copy3(out, pen.angular_velocity);
    case kCurrentTransform: std::copy(pen.transform, pen.transform + 16, out); return;
    case kUsableWorkspaceDimensions: std::copy(pen.workspace, pen.workspace + 6, out); return;
    case kNominalMaxForce: *out = pen.max_force_n; return;
    case kNominalMaxStiffness: *out = pen.max_stiffness_n_per_mm; return;
    case kNominalMaxDamping: *out = pen.max_damping_n_s_per_mm; return;
    case kNominalMaxTorqueForce: *out = pen.max_torque_mn_m; return;
    default: pushError(pen, kInvalidEnum);
  }
}

void hdGetIntegerv(HDenum name, HDint* out) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen& pen = f.pen;
  switch (name) {
    case kCurrentButtons: *out = pen.buttons; return;
    case kInputDof: *out = pen.input_dof; return;
    case kOutputDof: *out = pen.output_dof; return;
    case kCalibrationStyle: *out = pen.calibration_styles; return;
    case kUpdateRate: *out = 1000; return;
    default: pushError(pen, kInvalidEnum);
  }
}

void hdSetDoublev(HDenum name, const HDdouble* in) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen& pen = f.pen;
  if (!pen.in_frame) return pushError(pen, kInvalidOperation);  // forces only go out through a frame
  if (name == kCurrentForce) copy3(pen.frame_force, in);
  else if (name == kCurrentTorque && pen.output_dof >= 6) copy3(pen.frame_torque, in);
  else pushError(pen, kInvalidEnum);
}

HDstring hdGetString(HDenum name) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (name == kDeviceModelType) return f.pen.model.c_str();
  if (name == kDeviceSerialNumber) return "FAKE-0001";
  pushError(f.pen, kInvalidEnum);
  return nullptr;
}

HDenum hdCheckCalibration() {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  return f.pen.calibration;
}

void hdUpdateCalibration(HDenum style) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  ++f.pen.calibration_updates;
  f.pen.last_update_style = style;
  // An update only helps a pen that needed just that, in a style it supports.
  if (f.pen.calibration == kCalibrationNeedsUpdate && (static_cast<int>(style) & f.pen.calibration_styles) != 0)
    f.pen.calibration = kCalibrationOk;
}

HDSchedulerHandle hdScheduleAsynchronous(HDSchedulerCallback callback, void* user, HDushort /*priority*/) {
  Fake& f = fake();
  std::unique_lock lock(f.schedule_mutex, std::defer_lock);
  if (!onSchedulerThread()) lock.lock();
  const HDSchedulerHandle h = f.next_handle++;
  f.scheduled.push_back(Scheduled{h, callback, user});
  return h;
}

void hdUnschedule(HDSchedulerHandle handle) {
  Fake& f = fake();
  std::unique_lock lock(f.schedule_mutex, std::defer_lock);
  if (!onSchedulerThread()) lock.lock();
  std::erase_if(f.scheduled, [&](const Scheduled& s) { return s.handle == handle; });
}

void hdStartScheduler() {
  Fake& f = fake();
  if (f.scheduler_running.exchange(true)) return;
  f.scheduler = std::thread([&f] {
    f.scheduler_id.store(std::this_thread::get_id());
    schedulerLoop();
  });
}

void hdStopScheduler() {
  Fake& f = fake();
  if (!f.scheduler_running.exchange(false)) return;
  if (f.scheduler.joinable()) f.scheduler.join();
  f.scheduler_id.store(std::thread::id{});
}

// ---- 4. test controls ----

// Stops the scheduler, drops every callback and puts the pen back to its defaults (a calibrated Touch at the origin).
void fakeHdReset() {
  hdStopScheduler();
  Fake& f = fake();
  {
    std::lock_guard lock(f.schedule_mutex);
    f.scheduled.clear();
  }
  std::lock_guard lock(f.pen_mutex);
  f.pen = Pen{};
}

// Position [mm], velocity [mm/s], angular velocity [rad/s] (each 3), the column-major 4x4 transform (16, may be null).
void fakeHdSetPose(const double* position, const double* velocity, const double* angular_velocity,
                   const double* transform) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  copy3(f.pen.position, position);
  copy3(f.pen.velocity, velocity);
  copy3(f.pen.angular_velocity, angular_velocity);
  if (transform != nullptr) std::copy(transform, transform + 16, f.pen.transform);
}

void fakeHdSetButtons(int buttons) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  f.pen.buttons = buttons;
}

// status: an HD_CALIBRATION_* return value; styles: the HD_CALIBRATION_* style bits the pen supports.
void fakeHdSetCalibration(unsigned int status, int styles) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  f.pen.calibration = status;
  f.pen.calibration_styles = styles;
}

// The number of hdUpdateCalibration calls and the style of the last one.
int fakeHdCalibrationUpdates(unsigned int* last_style) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (last_style != nullptr) *last_style = f.pen.last_update_style;
  return f.pen.calibration_updates;
}

// Makes it a pen that renders torque (output DOF 6) with this largest torque [mN m].
void fakeHdSetTorqueOutput(double max_torque_mn_m) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  f.pen.output_dof = 6;
  f.pen.max_torque_mn_m = max_torque_mn_m;
}

// The next frame reports this HD error (e.g. 0x0302, HD_COMM_ERROR).
void fakeHdInjectError(unsigned int code, int internal) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  f.pen.pending_error = code;
  f.pen.pending_internal = internal;
}

// What the last completed frame sent: force [N] and torque [mN m], 3 each; returns the number of frames completed.
long fakeHdSent(double* force, double* torque) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (force != nullptr) copy3(force, f.pen.sent_force);
  if (torque != nullptr) copy3(torque, f.pen.sent_torque);
  return f.pen.frames;
}

int fakeHdSchedulerRunning() { return fake().scheduler_running.load() ? 1 : 0; }

int fakeHdScheduledCallbacks() {
  Fake& f = fake();
  std::unique_lock lock(f.schedule_mutex, std::defer_lock);
  if (!onSchedulerThread()) lock.lock();
  return static_cast<int>(f.scheduled.size());
}

int fakeHdDeviceInitialized() {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  return f.pen.initialized ? 1 : 0;
}

int fakeHdForceOutputEnabled() {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  return f.pen.force_output ? 1 : 0;
}

}  // extern "C"
