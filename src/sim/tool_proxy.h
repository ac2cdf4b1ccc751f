// ToolProxy: the virtual coupling between a pen and its tool, stepped implicitly so that stiff tissue stays stable at 1 kHz.
//
// The pen (device) never touches the tooth; its tool (the proxy) does. A spring and damper join
// the two, in translation and in rotation. Each step moves the proxy to where the coupling, the
// contact forces and a small drag balance, by one Newton step on the linearized contact (backward
// Euler for a massless proxy): stiff contact then costs no stability, and the step only removes
// energy. The pen is shown the coupling's force, clamped to what it can display, so the stiffness
// the hand feels never exceeds the coupling's, whatever the tissue's (Colgate's passivity
// argument for virtual couplings).
#pragma once

#include <span>
#include <string>

#include "core/pen_source.h"
#include "core/rigid.h"
#include "sim/contact.h"
#include "sim/point_shell.h"
#include "sim/sim_params.h"
#include "sim/voxel_field.h"

namespace dentsim {

// A tool as the simulation holds it: constant after loading.
struct ToolModel {
  std::string name;        // "round_bur_010", "mirror_size4"; names the bur's cutting ability
  PointShell shell;        // the points, tool frame [mm]
  Vec3 grip_local;         // the grip point in the tool frame [mm]: the pen holds it; moments are about it
  bool cuts = false;       // a bur cuts with its head; the mirror never cuts
};

struct ProxyStep {
  Wrench display;          // what the pen is told to render: force [N], moment about the grip [N mm]; clamped
  Wrench coupling;         // the same before clamping
  Wrench contact;          // the tissue's wrench on the tool (moment about the grip), before the step
  ContactForce detail;     // the contact sums the step used
  ContactStats stats;      // how much of the shell was tested
  std::span<const ContactPoint> contacts;  // the intersection set at the start of the step
  bool force_clamped = false;  // |coupling force| exceeded the device's limit
  uint32_t sweep_poses = 0;    // sub-poses the swept check followed the move through (0: a slow move, not swept)
  uint32_t sweep_taken = 0;    // of which the proxy took (fewer: it met tissue on the way)
  bool held = false;           // the budget cut the contact pass short and the proxy's move was shortened
};

class ToolProxy {
 public:
  explicit ToolProxy(const ToolModel& tool);

  // Puts the proxy on the pen, at rest.
  void reset(const Pose& grip);
  // One coupling step of dt seconds against the field. With a budget, the contact pass may stop
  // early (ContactFinder::find); the swept check never does (its cost is bounded by its sub-poses).
  ProxyStep step(VoxelField& field, const SimParams& params, const PenReading& pen, double dt,
                 const ContactBudget* budget = nullptr);

  const Pose& grip() const { return grip_; }                 // the proxy's grip frame
  Pose toolPose() const {                                     // tool frame to simulation frame
    return {grip_.position - grip_.rotation.rotate(tool_.grip_local), grip_.rotation};
  }
  const Vec3& velocity() const { return velocity_; }          // of the grip point [mm/s]
  const Vec3& angularVelocity() const { return angular_velocity_; }  // [rad/s]
  const ToolModel& tool() const { return tool_; }

 private:
  const ToolModel& tool_;
  double reach_mm_ = 0.0;  // the farthest shell point from the grip [mm]: bounds how far a turn moves a point
  ContactFinder finder_;
  Pose grip_;
  Vec3 velocity_;
  Vec3 angular_velocity_;
};

// A move in which some shell point may travel more than this many voxels is swept (ContactFinder::sweep)
// in sub-poses this far apart: well inside what the contact's march resolves (12 voxels), so that
// no wall thicker than two voxels can be stepped over.
inline constexpr double kSweepVoxels = 2.0;
inline constexpr uint32_t kMaxSweepPoses = 64;
// A step whose contact pass the budget cut short moves no shell point further than this [voxel].
inline constexpr double kShortPassVoxels = 0.5;

// Solves m x = b for a symmetric positive definite m by Cholesky; false when m is not.
bool solveSpd6(const Mat6& m, const double* b, double* x);

// Scales v down to length max_len if longer; returns whether it did.
bool clampLength(Vec3* v, double max_len);

}  // namespace dentsim
