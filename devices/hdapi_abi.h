// The part of the OpenHaptics HDAPI binary interface dentsim uses: its types and enum values, declared once for the plug-in and the tests' stand-in library.
//
// Values from the HDAPI reference headers (hdDefines.h, hd.h, hdScheduler.h of OpenHaptics 3.x).
// The plug-in resolves the functions with dlsym; nothing here links the vendor library.
#pragma once

namespace dentsim::devices::hd {

using HDuint = unsigned int;
using HDboolean = unsigned char;
using HDushort = unsigned short;
using HDint = int;
using HDdouble = double;
using HDerror = unsigned int;
using HDenum = unsigned int;
using HDstring = const char*;
using HHD = unsigned int;
using HDCallbackCode = unsigned int;
using HDSchedulerHandle = unsigned long;
// HDCALLBACK and HDAPIENTRY are empty on Linux: plain C calling convention.
using SchedulerCallback = HDCallbackCode (*)(void* user_data);

struct ErrorInfo {
  HDerror errorCode;      // HD_SUCCESS or an HD_* error
  int internalErrorCode;  // the driver's own code
  HHD hHD;                // the device that was current
};

constexpr HDerror kSuccess = 0x0000;
constexpr HDerror kInvalidEnum = 0x0100;
constexpr HDerror kInvalidOperation = 0x0102;
constexpr HDerror kBadHandle = 0x0104;
constexpr HDerror kDeviceFault = 0x0300;
constexpr HDerror kDeviceAlreadyInitiated = 0x0301;
constexpr HDerror kCommError = 0x0302;
constexpr HDerror kIllegalBegin = 0x0400;
constexpr HDerror kIllegalEnd = 0x0401;

constexpr HDenum kCurrentButtons = 0x2000;
constexpr HDenum kCurrentPosition = 0x2050;         // 3 doubles [mm]
constexpr HDenum kCurrentVelocity = 0x2051;         // 3 doubles [mm/s]
constexpr HDenum kCurrentTransform = 0x2052;        // 16 doubles, column-major 4x4, translation [mm]
constexpr HDenum kCurrentAngularVelocity = 0x2053;  // 3 doubles [rad/s]
constexpr HDenum kDeviceModelType = 0x2501;
constexpr HDenum kDeviceSerialNumber = 0x2504;
constexpr HDenum kUsableWorkspaceDimensions = 0x2551;  // minx, miny, minz, maxx, maxy, maxz [mm]
constexpr HDenum kInputDof = 0x2553;
constexpr HDenum kOutputDof = 0x2554;
constexpr HDenum kCalibrationStyle = 0x2555;  // the HD_CALIBRATION_* style bits the pen supports
constexpr HDenum kUpdateRate = 0x2600;        // [Hz]
constexpr HDenum kNominalMaxStiffness = 0x2602;  // [N/mm]
constexpr HDenum kNominalMaxForce = 0x2603;      // [N]
constexpr HDenum kNominalMaxDamping = 0x2609;    // [N s/mm]
constexpr HDenum kNominalMaxTorqueForce = 0x2622;  // [mN m], pens with torque output only
constexpr HDenum kCurrentForce = 0x2700;   // 3 doubles [N]
constexpr HDenum kCurrentTorque = 0x2701;  // 3 doubles [mN m]

constexpr HDenum kForceOutput = 0x4000;
constexpr HDenum kMaxForceClamping = 0x4001;

constexpr HDenum kCalibrationOk = 0x5000;
constexpr HDenum kCalibrationNeedsUpdate = 0x5001;
constexpr HDenum kCalibrationNeedsManualInput = 0x5002;
constexpr int kCalibrationEncoderReset = 1 << 0;
constexpr int kCalibrationAuto = 1 << 1;
constexpr int kCalibrationInkwell = 1 << 2;

constexpr HHD kInvalidHandle = 0xFFFFFFFF;
constexpr HDstring kDefaultDevice = nullptr;
constexpr HDCallbackCode kCallbackDone = 0;
constexpr HDCallbackCode kCallbackContinue = 1;
constexpr HDushort kMaxSchedulerPriority = 0xFFFF;  // USHRT_MAX: the servo loop runs first

}  // namespace dentsim::devices::hd
