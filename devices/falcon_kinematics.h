// The Falcon's delta kinematics: encoder counts to arm angles, angles to grip position and back, and the Jacobian.
//
// The Novint Falcon is a three-arm translational parallel manipulator of the kind analysed in
// R. E. Stamper's 1997 thesis (University of Maryland) on the 3-DOF translational parallel
// manipulator. Each arm is a motor-driven thigh, a parallelogram shin that keeps the grip from
// turning, and two short rungs at its ends. The link names a..f, r, s and the arm azimuths are
// Stamper's; the numbers are those the open Falcon driver community (libnifalcon) published from
// measurements of the device. This file is pure math: it never touches USB.
//
// Conventions (all of them are the Geometry defaults below; a different unit only changes those):
//   Device frame [mm]. Origin on the Falcon's central axis, in the plane of the three thigh hinges
//     (Stamper's fixed frame). Seen from the user sitting in front of the Falcon: +x to the right,
//     +y up, +z out of the front face toward the user (right-handed). The grip lives at z > 0
//     (about 70..180 mm along the axis); the workspace box is centred on the z axis, where by
//     symmetry the three arm angles are equal.
//   Arm angle theta_i [rad]. The thigh's rotation about its hinge, measured in the arm's own plane
//     (spanned by the arm's radial direction u_i and z) from u_i toward +z: theta = 0 points the
//     thigh straight outward, and a larger theta swings the knee toward the user. Arm 0 is the top
//     arm, arms 1 and 2 follow clockwise as seen from the front (azimuths 105, -15, -135 degrees).
//   Encoder counts. theta = angle_at_zero_count + counts / countsPerRadian(): the count grows with
//     theta. countsPerRadian() = encoder counts per motor turn (320 slots, quadrature x4 = 1280)
//     times the capstan ratio (thigh drum diameter 110 mm / motor shaft diameter 14.25 mm = 7.719),
//     over 2 pi: about 1572.6 counts per radian of arm angle. Encoder 0 is theta = 35 degrees.
//   Torques. Motor shaft torques [N mm], measured in the encoder's sense: the motor angle
//     2 pi counts / 1280 grows with theta, and a positive torque pushes it (and theta) up. A motor
//     torque t gives the thigh t * capstan_ratio, so power balances: t . d(motor angle) = F . dp.
//   Motor command words (int16, one per motor, as the firmware packet takes them).
//     word = command_sign * command_words_per_n_mm * t, rounded, saturated symmetrically to
//     +-max_command_word (32767), NaN -> 0. The scale (10 000 words per N m of thigh torque, i.e.
//     about 77.2 words per N mm of motor torque) and the sign (a positive word turns theta down) are
//     libnifalcon's empirical force path; we found no published motor torque constant or
//     amplifier gain. Check both on hardware before trusting forces above a few newtons: a +z force
//     command must pull the grip toward the user.
#pragma once

#include <array>
#include <cstdint>

#include "core/rigid.h"

namespace dentsim::devices::falcon {

using Angles = std::array<double, 3>;    // the three arm angles [rad]
using Encoders = std::array<int32_t, 3>; // the three motors' encoder counts
using Torques = std::array<double, 3>;   // motor shaft torques [N mm]
using Matrix3 = std::array<double, 9>;   // row-major

// The mechanism's published measurements. Lengths follow Stamper's figure of one arm: in the arm's
// frame (u radial outward, v tangential, w = z) the hinge sits at (r, s, 0) from the origin.
struct Geometry {
  double a = 60.0;         // thigh: hinge axis to knee axis [mm]
  double b = 102.5;        // shin: the parallelogram's long side [mm]
  double c = 14.0;         // shin's lower joint to the grip centre, u component [mm]
  double d = 11.25;        // lower rung: parallelogram to the effector joint [mm]
  double e = 11.25;        // upper rung: knee to the parallelogram [mm]
  double f = -25.0;        // shin's lower joint to the grip centre, v component [mm]
  double r = 37.233758;    // origin to the thigh hinge, u component [mm]
  double s = -27.330909;   // origin to the thigh hinge, v component [mm]
  // Each arm's radial direction u_i, from +x toward +y: 90, -30, -150 degrees plus the 15 degree
  // tilt of the whole star that libnifalcon measured [rad].
  std::array<double, 3> arm_azimuth_rad = {1.8325957145940461, -0.26179938779914941,
                                           -2.3561944901923448};

  double encoder_counts_per_motor_turn = 1280.0;  // 320-slot code wheel, quadrature x4
  double capstan_ratio = 110.0 / 14.25;           // thigh drum / motor shaft diameter [1]
  // The arm angle at encoder count 0 [rad]: 35 degrees, libnifalcon's figure ("approximately");
  // homing defines it, so correct it here if a calibration says otherwise.
  double angle_at_zero_count_rad = 0.61086523819801535;

  double command_words_per_n_mm = 77.192982456140356;  // |word| per N mm of motor torque
  int command_sign = -1;                               // word sign for a positive torque
  int16_t max_command_word = 32767;                    // the symmetric saturation limit

  // The box the grip centre is promised to reach, device frame [mm]. Novint advertises about 4 in
  // (102 mm) along each axis, but with the link lengths above the largest cube that reaches
  // everywhere with every |J| entry under 250 mm/rad is about 90 mm (centred near z = 110); this
  // 80 mm cube keeps a margin (the tests check a 13^3 grid, corners included, under 200 mm/rad).
  Vec3 workspace_min_mm{-40.0, -40.0, 70.0};
  Vec3 workspace_max_mm{40.0, 40.0, 150.0};
};

class Kinematics {
 public:
  Kinematics();
  explicit Kinematics(const Geometry& geometry);

  const Geometry& geometry() const { return geometry_; }
  double countsPerRadian() const { return counts_per_radian_; }  // [counts/rad] of arm angle
  Vec3 workspaceCentre() const;                                  // [mm], the box's centre

  Angles anglesFromEncoders(const Encoders& e) const;
  Encoders encodersFromAngles(const Angles& a) const;  // rounded to whole counts; NaN -> 0
  // Grip position [mm], device frame -> angles. False when out of reach (z <= 0 included: behind
  // the hinges only the mirror image of the mechanism would fit), or not finite.
  bool inverse(const Vec3& position_mm, Angles* out) const;
  // Angles -> grip position [mm] (Newton's method from `guess`, or the workspace centre). False when
  // it does not converge.
  bool forward(const Angles& a, Vec3* position_mm, const Vec3* guess = nullptr) const;
  // J with dp = J da [mm/rad], row-major, at the pose of angles a.
  // Analytic (implicit differentiation of each arm's constraint); all NaN when forward() fails.
  Matrix3 jacobian(const Angles& a) const;
  // The motor torques that render force F [N] at the grip: tau = J^T F, through the gearing.
  // [N mm] per motor, in the encoder's sense; NaN when the angles have no pose.
  Torques torquesForForce(const Angles& a, const Vec3& force_n) const;
  // Motor command words for the packet, saturated to the amplifier's range.
  // Symmetric: +-max_command_word; a NaN torque gives 0 (no pose, no force).
  std::array<int16_t, 3> motorWords(const Torques& t) const;

  // The same Jacobian at a known grip position, skipping the forward solve; false when out of
  // reach or singular. *out is all NaN on false, as jacobian() is when forward() fails.
  bool jacobianAt(const Vec3& position_mm, Matrix3* out) const;
  // forward() convergence: the last Newton step is below this [mm], within this many steps.
  static constexpr double kForwardTolerance_mm = 1e-9;
  static constexpr int kForwardMaxSteps = 60;

 private:
  Geometry geometry_;
  double counts_per_radian_ = 0.0;
  std::array<double, 3> cos_azimuth_{}, sin_azimuth_{};  // of each arm's radial direction
};

}  // namespace dentsim::devices::falcon
