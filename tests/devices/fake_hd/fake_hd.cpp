// Fake HDAPI library: simulated pens by configuration name ("Default", or one per $GTDD_HOME/config/*.config) with one 1 kHz scheduler thread, for the OpenHaptics plug-in tests.
//
// It exports the HDAPI entry points the plug-in resolves (C linkage, the vendor's names and
// signatures as given in the OpenHaptics HDAPI reference headers hd.h, hdScheduler.h and
// hdDefines.h), plus fakeHd* controls through which a test sets a pen's pose, buttons and
// calibration, injects an error or unplugs it, and reads back what the plug-in sent to its motors.
//
// Devices. Like the vendor's Touch setup, the configured pens are the files NAME.config in
// $GTDD_HOME/config; "Default Device.config" is the one HD_DEFAULT_DEVICE opens. Without
// GTDD_HOME there is one pen, "Default". fakeHdReset() reads the folder again.
//
// What it checks that the real library would not say. The plug-in must address a device from a
// control thread only while the scheduler is stopped (HDAPI has one current device, which the
// servo thread switches between pens), and must leave every pen at zero force when the scheduler
// stops. Breaches are counted (fakeHdMisuse, fakeHdStoppedPushing) for the tests to assert on.
//
// For tests that run dentsim as a program: DENTSIM_FAKE_HD_FAULT="NAME@FRAME" raises
// HD_COMM_ERROR on that pen's FRAME-th frame, and "NAME@signal" on its first frame after the
// process gets SIGUSR1 (so a test can wait until the session runs); DENTSIM_FAKE_HD_LOG=FILE gets
// one line per pen when the scheduler stops and when the library unloads (see writeLog).
//
// Sections: 1. HDAPI types and values  2. the simulated pens  3. HDAPI entry points  4. test controls
#include <dirent.h>
#include <signal.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
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

// ---- 2. the simulated pens ----
// Its numbers are those of a 3D Systems Touch as its data sheet gives them; the tests read them
// back through the plug-in's spec, so any plausible values would do.
struct Pen {
  std::string name = "Default";
  std::string model = "Touch";
  std::string serial = "FAKE-0001";
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

  bool plugged = true;
  bool initialized = false;
  bool force_output = false;
  bool in_frame = false;
  double frame_force[3] = {0, 0, 0};   // what the frame in progress was given
  double frame_torque[3] = {0, 0, 0};
  double sent_force[3] = {0, 0, 0};    // what the last hdEndFrame sent to the motors [N]
  double sent_torque[3] = {0, 0, 0};   // [mN m]
  long frames = 0;
  long last_force_tick = -1;           // the scheduler pass of the newest frame that sent a force
  long error_tick = -1;                // the scheduler pass in which an injected error was raised
  long sent_after_stop = 0;            // frames that sent a force while the scheduler was stopped
  long stopped_pushing = 0;            // scheduler stops that left this pen's motors pushing

  HDerror pending_error = kSuccess;    // injected by the test, raised at the next hdBeginFrame
  int pending_internal = 0;
  long fault_at_frame = -1;            // DENTSIM_FAKE_HD_FAULT: raise HD_COMM_ERROR on this frame
  bool fault_on_signal = false;        // DENTSIM_FAKE_HD_FAULT=NAME@signal: raise it after SIGUSR1
};

std::atomic<bool> g_fault_signal{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");
extern "C" void onFaultSignal(int) { g_fault_signal.store(true); }

struct Scheduled {
  HDSchedulerHandle handle;
  HDSchedulerCallback callback;
  void* user;
};

std::vector<Pen> configuredPens() {
  std::vector<Pen> pens;
  const char* home = std::getenv("GTDD_HOME");
  if (home != nullptr && *home != '\0') {
    const std::string dir = std::string(home) + "/config";
    if (DIR* d = opendir(dir.c_str())) {
      while (const dirent* e = readdir(d)) {
        const std::string file = e->d_name;
        const std::string ext = ".config";
        if (file.size() <= ext.size() || file.compare(file.size() - ext.size(), ext.size(), ext) != 0) continue;
        Pen p;
        p.name = file.substr(0, file.size() - ext.size());
        pens.push_back(p);
      }
      closedir(d);
    }
    std::sort(pens.begin(), pens.end(), [](const Pen& a, const Pen& b) { return a.name < b.name; });
  }
  if (pens.empty()) pens.emplace_back();
  for (size_t i = 0; i < pens.size(); ++i) pens[i].serial = "FAKE-000" + std::to_string(i + 1);
  if (const char* fault = std::getenv("DENTSIM_FAKE_HD_FAULT"); fault != nullptr) {
    const std::string f = fault;
    const size_t at = f.rfind('@');
    for (Pen& p : pens) {
      if (at == std::string::npos || f.substr(0, at) != p.name) continue;
      if (f.substr(at + 1) == "signal") {
        p.fault_on_signal = true;
        struct sigaction sa {};
        sa.sa_handler = onFaultSignal;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGUSR1, &sa, nullptr);
      } else {
        p.fault_at_frame = std::atol(f.c_str() + at + 1);
      }
    }
  }
  return pens;
}

struct Fake {
  std::mutex pen_mutex;  // the pens' state: the test thread and the scheduler thread both touch it
  std::vector<Pen> pens = configuredPens();
  size_t selected = 0;               // the pen the fakeHd* controls address
  HHD current = kInvalidHandle;      // hdMakeCurrentDevice's: one for the process, as in HDAPI
  std::vector<HDErrorInfo> errors;   // HDAPI's error stack: most recent last here
  long misuse = 0;                   // device calls from another thread while the scheduler ran
  long ticks = 0;                    // scheduler passes completed

  std::mutex schedule_mutex;  // the callback list; held while callbacks run, so unschedule waits them out
  std::vector<Scheduled> scheduled;
  HDSchedulerHandle next_handle = 1;
  std::thread scheduler;
  std::atomic<bool> scheduler_running{false};
  std::atomic<std::thread::id> scheduler_id{};

  // A test that ends with the scheduler running must not take std::terminate down with it.
  ~Fake();
};

void writeLog(Fake& f, const char* when);

Fake::~Fake() {
  scheduler_running.store(false);
  if (scheduler.joinable()) scheduler.join();
  std::lock_guard lock(pen_mutex);
  writeLog(*this, "unload");
}

Fake& fake() {
  static Fake f;
  return f;
}

bool onSchedulerThread() { return fake().scheduler_id.load() == std::this_thread::get_id(); }

// One line per pen to $DENTSIM_FAKE_HD_LOG, appended: what a test of the whole program checks.
void writeLog(Fake& f, const char* when) {
  const char* path = std::getenv("DENTSIM_FAKE_HD_LOG");
  if (path == nullptr || *path == '\0') return;
  FILE* out = std::fopen(path, "a");
  if (out == nullptr) return;
  for (const Pen& p : f.pens)
    std::fprintf(out, "%s %s frames=%ld error_tick=%ld last_force_tick=%ld sent_after_stop=%ld stopped_pushing=%ld misuse=%ld\n",
                 when, p.name.c_str(), p.frames, p.error_tick, p.last_force_tick, p.sent_after_stop, p.stopped_pushing,
                 f.misuse);
  std::fclose(out);
}

void pushError(Fake& f, HDerror code, int internal, HHD handle) { f.errors.push_back(HDErrorInfo{code, internal, handle}); }

// The pen a handle names (handles are 1 + the pen's index), or null.
Pen* penOf(Fake& f, HHD handle) {
  if (handle == 0 || handle > f.pens.size()) return nullptr;
  return &f.pens[handle - 1];
}

// The current pen for a device call, counting a control thread's call while the scheduler runs.
Pen* currentPen(Fake& f) {
  if (f.scheduler_running.load(std::memory_order_acquire) && !onSchedulerThread()) ++f.misuse;
  Pen* p = penOf(f, f.current);
  if (p == nullptr || !p->initialized) {
    pushError(f, kBadHandle, 0, f.current);
    return nullptr;
  }
  return p;
}

bool anyForce(const double* force) { return force[0] != 0 || force[1] != 0 || force[2] != 0; }

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
    {
      std::lock_guard lock(f.pen_mutex);
      ++f.ticks;
    }
    next += std::chrono::milliseconds(1);
    const auto now = std::chrono::steady_clock::now();
    if (next < now) next = now;  // late: skip the missed ticks rather than burst through them
    std::this_thread::sleep_until(next);
  }
}

void copy3(double* to, const double* from) { std::copy(from, from + 3, to); }

}  // namespace

// ---- 3. HDAPI entry points ----
extern "C" {

HHD hdInitDevice(HDstring config_name) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (f.scheduler_running.load() && !onSchedulerThread()) ++f.misuse;
  // HD_DEFAULT_DEVICE (null) opens "Default Device", else the only pen "Default", else the first.
  size_t index = f.pens.size();
  for (size_t i = 0; i < f.pens.size(); ++i) {
    const std::string& n = f.pens[i].name;
    if (config_name == nullptr ? (n == "Default Device" || n == "Default") : n == config_name) index = i;
  }
  if (config_name == nullptr && index == f.pens.size()) index = 0;
  if (index == f.pens.size() || !f.pens[index].plugged) {
    pushError(f, kDeviceFault, 3, kInvalidHandle);
    return kInvalidHandle;
  }
  Pen& pen = f.pens[index];
  const HHD handle = static_cast<HHD>(index + 1);
  if (pen.initialized) {
    pushError(f, kDeviceAlreadyInitiated, 0, handle);
    return kInvalidHandle;
  }
  pen.initialized = true;
  f.current = handle;  // HDAPI makes a newly initialised device current
  return handle;
}

void hdDisableDevice(HHD handle) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (f.scheduler_running.load() && !onSchedulerThread()) ++f.misuse;
  Pen* pen = penOf(f, handle);
  if (pen == nullptr || !pen->initialized) return pushError(f, kBadHandle, 0, handle);
  pen->initialized = false;
  pen->force_output = false;
  pen->in_frame = false;
  std::fill(pen->sent_force, pen->sent_force + 3, 0.0);
  std::fill(pen->sent_torque, pen->sent_torque + 3, 0.0);
  if (f.current == handle) f.current = kInvalidHandle;
}

void hdMakeCurrentDevice(HHD handle) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (f.scheduler_running.load() && !onSchedulerThread()) ++f.misuse;
  Pen* pen = penOf(f, handle);
  if (pen == nullptr || !pen->initialized) return pushError(f, kBadHandle, 0, handle);
  f.current = handle;
}

HDErrorInfo hdGetError() {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (f.errors.empty()) return HDErrorInfo{kSuccess, 0, kInvalidHandle};
  const HDErrorInfo e = f.errors.back();
  f.errors.pop_back();
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
  Pen* pen = penOf(f, handle);
  if (pen == nullptr || !pen->initialized) return pushError(f, kBadHandle, 0, handle);
  if (pen->in_frame) return pushError(f, kIllegalBegin, 0, handle);
  pen->in_frame = true;
  f.current = handle;
  std::fill(pen->frame_force, pen->frame_force + 3, 0.0);
  std::fill(pen->frame_torque, pen->frame_torque + 3, 0.0);
  if (pen->fault_on_signal && g_fault_signal.exchange(false)) pen->pending_error = kCommError;
  if (pen->fault_at_frame >= 0 && pen->frames + 1 >= pen->fault_at_frame) {
    pen->pending_error = kCommError;
    pen->pending_internal = 7;
    pen->fault_at_frame = -1;
  }
  if (!pen->plugged && pen->pending_error == kSuccess) {
    pen->pending_error = kCommError;
    pen->pending_internal = 5;  // the cable is out: every frame fails
  }
  if (pen->pending_error != kSuccess) {
    pushError(f, pen->pending_error, pen->pending_internal, handle);
    if (pen->error_tick < 0) pen->error_tick = f.ticks;
    if (pen->plugged) pen->pending_error = kSuccess;
  }
}

void hdEndFrame(HHD handle) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen* pen = penOf(f, handle);
  if (pen == nullptr || !pen->initialized) return pushError(f, kBadHandle, 0, handle);
  if (!pen->in_frame) return pushError(f, kIllegalEnd, 0, handle);
  pen->in_frame = false;
  // Like the real device: what a frame did not set is zero, and nothing goes out while force
  // output is disabled or the cable is out.
  const bool out = pen->force_output && pen->plugged;
  for (int i = 0; i < 3; ++i) {
    pen->sent_force[i] = out ? pen->frame_force[i] : 0.0;
    pen->sent_torque[i] = out ? pen->frame_torque[i] : 0.0;
  }
  if (anyForce(pen->sent_force) || anyForce(pen->sent_torque)) {
    pen->last_force_tick = f.ticks;
    if (!f.scheduler_running.load()) ++pen->sent_after_stop;
  }
  ++pen->frames;
}

void hdEnable(HDenum cap) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen* pen = currentPen(f);
  if (pen == nullptr) return;
  if (cap == kForceOutput) pen->force_output = true;
  else if (cap != kMaxForceClamping) pushError(f, kInvalidEnum, 0, f.current);
}

void hdDisable(HDenum cap) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen* pen = currentPen(f);
  if (pen == nullptr) return;
  if (cap == kForceOutput) pen->force_output = false;
  else if (cap != kMaxForceClamping) pushError(f, kInvalidEnum, 0, f.current);
}

void hdGetDoublev(HDenum name, HDdouble* out) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen* pen = currentPen(f);
  if (pen == nullptr) return;
  switch (name) {
    case kCurrentPosition: return copy3(out, pen->position);
    case kCurrentVelocity: return copy3(out, pen->velocity);
    case kCurrentAngularVelocity: return copy3(out, pen->angular_velocity);
    case kCurrentTransform: std::copy(pen->transform, pen->transform + 16, out); return;
    case kUsableWorkspaceDimensions: std::copy(pen->workspace, pen->workspace + 6, out); return;
    case kNominalMaxForce: *out = pen->max_force_n; return;
    case kNominalMaxStiffness: *out = pen->max_stiffness_n_per_mm; return;
    case kNominalMaxDamping: *out = pen->max_damping_n_s_per_mm; return;
    case kNominalMaxTorqueForce: *out = pen->max_torque_mn_m; return;
    default: pushError(f, kInvalidEnum, 0, f.current);
  }
}

void hdGetIntegerv(HDenum name, HDint* out) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen* pen = currentPen(f);
  if (pen == nullptr) return;
  switch (name) {
    case kCurrentButtons: *out = pen->buttons; return;
    case kInputDof: *out = pen->input_dof; return;
    case kOutputDof: *out = pen->output_dof; return;
    case kCalibrationStyle: *out = pen->calibration_styles; return;
    case kUpdateRate: *out = 1000; return;
    default: pushError(f, kInvalidEnum, 0, f.current);
  }
}

void hdSetDoublev(HDenum name, const HDdouble* in) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen* pen = currentPen(f);
  if (pen == nullptr) return;
  if (!pen->in_frame) return pushError(f, kInvalidOperation, 0, f.current);  // forces only go out through a frame
  if (name == kCurrentForce) copy3(pen->frame_force, in);
  else if (name == kCurrentTorque && pen->output_dof >= 6) copy3(pen->frame_torque, in);
  else pushError(f, kInvalidEnum, 0, f.current);
}

HDstring hdGetString(HDenum name) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen* pen = currentPen(f);
  if (pen == nullptr) return nullptr;
  if (name == kDeviceModelType) return pen->model.c_str();
  if (name == kDeviceSerialNumber) return pen->serial.c_str();
  pushError(f, kInvalidEnum, 0, f.current);
  return nullptr;
}

HDenum hdCheckCalibration() {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen* pen = currentPen(f);
  return pen != nullptr ? pen->calibration : kCalibrationNeedsManualInput;
}

void hdUpdateCalibration(HDenum style) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen* pen = currentPen(f);
  if (pen == nullptr) return;
  ++pen->calibration_updates;
  pen->last_update_style = style;
  // An update only helps a pen that needed just that, in a style it supports.
  if (pen->calibration == kCalibrationNeedsUpdate && (static_cast<int>(style) & pen->calibration_styles) != 0)
    pen->calibration = kCalibrationOk;
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
  std::lock_guard lock(f.pen_mutex);
  for (Pen& p : f.pens)
    if (p.initialized && (anyForce(p.sent_force) || anyForce(p.sent_torque))) ++p.stopped_pushing;
  writeLog(f, "stop");
}

// ---- 4. test controls: each addresses the selected pen (fakeHdSelect; the first after a reset) ----

// Stops the scheduler, drops every callback, reads the configured pens again and puts them back to
// their defaults (calibrated Touches at the origin).
void fakeHdReset() {
  hdStopScheduler();
  Fake& f = fake();
  {
    std::lock_guard lock(f.schedule_mutex);
    f.scheduled.clear();
  }
  std::lock_guard lock(f.pen_mutex);
  f.pens = configuredPens();
  f.selected = 0;
  f.current = kInvalidHandle;
  f.errors.clear();
  f.misuse = 0;
  f.ticks = 0;
}

// The fakeHd* calls after this address the pen configured as `name`. 0 when there is none.
int fakeHdSelect(const char* name) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  for (size_t i = 0; i < f.pens.size(); ++i)
    if (f.pens[i].name == name) {
      f.selected = i;
      return 1;
    }
  return 0;
}

// Position [mm], velocity [mm/s], angular velocity [rad/s] (each 3), the column-major 4x4 transform (16, may be null).
void fakeHdSetPose(const double* position, const double* velocity, const double* angular_velocity,
                   const double* transform) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen& pen = f.pens[f.selected];
  copy3(pen.position, position);
  copy3(pen.velocity, velocity);
  copy3(pen.angular_velocity, angular_velocity);
  if (transform != nullptr) std::copy(transform, transform + 16, pen.transform);
}

void fakeHdSetButtons(int buttons) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  f.pens[f.selected].buttons = buttons;
}

// status: an HD_CALIBRATION_* return value; styles: the HD_CALIBRATION_* style bits the pen supports.
void fakeHdSetCalibration(unsigned int status, int styles) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  f.pens[f.selected].calibration = status;
  f.pens[f.selected].calibration_styles = styles;
}

// The number of hdUpdateCalibration calls and the style of the last one.
int fakeHdCalibrationUpdates(unsigned int* last_style) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  if (last_style != nullptr) *last_style = f.pens[f.selected].last_update_style;
  return f.pens[f.selected].calibration_updates;
}

// Makes it a pen that renders torque (output DOF 6) with this largest torque [mN m].
void fakeHdSetTorqueOutput(double max_torque_mn_m) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  f.pens[f.selected].output_dof = 6;
  f.pens[f.selected].max_torque_mn_m = max_torque_mn_m;
}

// The next frame reports this HD error (e.g. 0x0302, HD_COMM_ERROR).
void fakeHdInjectError(unsigned int code, int internal) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  f.pens[f.selected].pending_error = code;
  f.pens[f.selected].pending_internal = internal;
}

// Pulls the pen's cable (every frame fails with HD_COMM_ERROR, it sends nothing, and it cannot be
// initialised) or plugs it back in.
void fakeHdSetPlugged(int plugged) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  Pen& pen = f.pens[f.selected];
  pen.plugged = plugged != 0;
  if (pen.plugged) pen.pending_error = kSuccess;
}

// What the last completed frame sent: force [N] and torque [mN m], 3 each; returns the number of frames completed.
long fakeHdSent(double* force, double* torque) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  const Pen& pen = f.pens[f.selected];
  if (force != nullptr) copy3(force, pen.sent_force);
  if (torque != nullptr) copy3(torque, pen.sent_torque);
  return pen.frames;
}

// In scheduler passes: the newest that sent this pen a force, and the one in which its injected
// error was raised (-1: none). Returns the passes completed.
long fakeHdTicks(long* last_force_tick, long* error_tick) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  const Pen& pen = f.pens[f.selected];
  if (last_force_tick != nullptr) *last_force_tick = pen.last_force_tick;
  if (error_tick != nullptr) *error_tick = pen.error_tick;
  return f.ticks;
}

// Breaches of the plug-in's rules: [0] device calls from a control thread while the scheduler ran,
// [1] forces sent while the scheduler was stopped (this pen), [2] stops that left this pen pushing.
void fakeHdBreaches(long* out) {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  out[0] = f.misuse;
  out[1] = f.pens[f.selected].sent_after_stop;
  out[2] = f.pens[f.selected].stopped_pushing;
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
  return f.pens[f.selected].initialized ? 1 : 0;
}

int fakeHdForceOutputEnabled() {
  Fake& f = fake();
  std::lock_guard lock(f.pen_mutex);
  return f.pens[f.selected].force_output ? 1 : 0;
}

}  // extern "C"
