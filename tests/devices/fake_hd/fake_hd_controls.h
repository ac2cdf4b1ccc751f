// The fake HDAPI's test controls (tests/devices/fake_hd/fake_hd.cpp), resolved by dlsym from the same library the OpenHaptics plug-in loads.
#pragma once

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <thread>

#include "core/rigid.h"

namespace dentsim::devices::test {

#ifdef DENTSIM_FAKE_HD_LIB
constexpr const char* kFakeHdLibrary = DENTSIM_FAKE_HD_LIB;
#else
constexpr const char* kFakeHdLibrary = nullptr;
#endif

// HDAPI facts the tests speak in (hdDefines.h of the HDAPI reference).
constexpr unsigned kHdCalibrationOk = 0x5000;
constexpr unsigned kHdCalibrationNeedsUpdate = 0x5001;
constexpr unsigned kHdCalibrationNeedsManualInput = 0x5002;
constexpr int kHdCalibrationAuto = 1 << 1;
constexpr int kHdCalibrationInkwell = 1 << 2;
constexpr unsigned kHdCommError = 0x0302;
constexpr double kFakeTouchMaxForceN = 3.3;  // what the fake reports as HD_NOMINAL_MAX_FORCE

struct FakeHd {
  void* handle = nullptr;
  void (*reset)() = nullptr;
  int (*select)(const char*) = nullptr;
  void (*setPose)(const double*, const double*, const double*, const double*) = nullptr;
  void (*setButtons)(int) = nullptr;
  void (*setCalibration)(unsigned int, int) = nullptr;
  int (*calibrationUpdates)(unsigned int*) = nullptr;
  void (*setTorqueOutput)(double) = nullptr;
  void (*injectError)(unsigned int, int) = nullptr;
  void (*setPlugged)(int) = nullptr;
  long (*sent)(double*, double*) = nullptr;
  long (*ticks)(long*, long*) = nullptr;
  void (*breaches)(long*) = nullptr;
  int (*schedulerRunning)() = nullptr;
  int (*scheduledCallbacks)() = nullptr;
  int (*deviceInitialized)() = nullptr;
  int (*forceOutputEnabled)() = nullptr;

  // Loads the library and every control; a failed ASSERT leaves `handle` null or a control unset.
  void load() {
    handle = dlopen(kFakeHdLibrary, RTLD_NOW | RTLD_LOCAL);
    ASSERT_NE(handle, nullptr) << dlerror();
    get("fakeHdReset", &reset);
    get("fakeHdSelect", &select);
    get("fakeHdSetPose", &setPose);
    get("fakeHdSetButtons", &setButtons);
    get("fakeHdSetCalibration", &setCalibration);
    get("fakeHdCalibrationUpdates", &calibrationUpdates);
    get("fakeHdSetTorqueOutput", &setTorqueOutput);
    get("fakeHdInjectError", &injectError);
    get("fakeHdSetPlugged", &setPlugged);
    get("fakeHdSent", &sent);
    get("fakeHdTicks", &ticks);
    get("fakeHdBreaches", &breaches);
    get("fakeHdSchedulerRunning", &schedulerRunning);
    get("fakeHdScheduledCallbacks", &scheduledCallbacks);
    get("fakeHdDeviceInitialized", &deviceInitialized);
    get("fakeHdForceOutputEnabled", &forceOutputEnabled);
  }
  void unload() {
    if (handle == nullptr) return;
    if (reset != nullptr) reset();
    dlclose(handle);
    handle = nullptr;
  }

  template <class F>
  void get(const char* symbol, F* fn) {
    *fn = reinterpret_cast<F>(dlsym(handle, symbol));
    ASSERT_NE(*fn, nullptr) << symbol;
  }

  // The selected pen's last force sent [N], and its frames completed.
  Vec3 force() const {
    double f[3];
    sent(f, nullptr);
    return {f[0], f[1], f[2]};
  }
  long frames() const { return sent(nullptr, nullptr); }
  void setPosition(const Vec3& p, const Vec3& v = {}) {
    const double position[3] = {p.x, p.y, p.z}, velocity[3] = {v.x, v.y, v.z}, zero[3] = {0, 0, 0};
    setPose(position, velocity, zero, nullptr);
  }
  // The whole pose: HDAPI's column-major 4x4 transform, whose column j is the rotated axis j.
  void setGrip(const Pose& grip, const Vec3& v = {}) {
    double t[16] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
    for (int j = 0; j < 3; ++j) {
      Vec3 axis;
      axis[j] = 1.0;
      const Vec3 c = grip.rotation.rotate(axis);
      for (int i = 0; i < 3; ++i) t[j * 4 + i] = c[i];
    }
    for (int i = 0; i < 3; ++i) t[12 + i] = grip.position[i];
    const double position[3] = {grip.position.x, grip.position.y, grip.position.z}, velocity[3] = {v.x, v.y, v.z},
                 zero[3] = {0, 0, 0};
    setPose(position, velocity, zero, t);
  }
  struct Breaches {
    long control_calls_while_running = 0;  // a control thread addressed a device under the servo loop
    long sent_after_stop = 0;              // the selected pen got a force with the scheduler stopped
    long stopped_pushing = 0;              // a scheduler stop left the selected pen pushing
  };
  Breaches breachCounts() const {
    long b[3] = {0, 0, 0};
    breaches(b);
    return {b[0], b[1], b[2]};
  }
};

// Polls `done` every 0.2 ms until it holds or `limit_ms` passes; true when it held. The limit only
// decides how long a failure is waited for.
inline bool waitFor(const std::function<bool()>& done, double limit_ms = 10000) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::microseconds(static_cast<int64_t>(limit_ms * 1000));
  while (std::chrono::steady_clock::now() < deadline) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
  return done();
}

}  // namespace dentsim::devices::test
