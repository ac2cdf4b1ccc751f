// Contact between a tool's point shell and the tooth's voxels: which points are inside tissue, how deep, and the force and moment.
//
// Contents
//   1. ContactPoint, Mat6
//   2. ContactFinder: the intersection set of a posed point shell (clusters skip empty chunks)
//   3. contactForce: spring, Hunt-Crossley damper and friction per point, summed to a wrench about a
//      reference point, with the stiffness the implicit proxy step needs
//
// Depth: a point inside tissue is pushed out along the tissue's surface normal (the field's
// gradient). Within half a voxel of the surface the field is linear across the surface, so the
// depth is phi / |grad phi|; deeper, the point marches along its inward normal (the way the tool
// came in) until it leaves the tissue, and the depth is the distance to the tangent plane there
// (VPS's tangent-plane force model).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/rigid.h"
#include "sim/point_shell.h"
#include "sim/sim_params.h"
#include "sim/voxel_field.h"

namespace dentsim {

// ---- 1. types -----------------------------------------------------------------------------------------

// One shell point inside tissue.
struct ContactPoint {
  uint32_t point = 0;       // index into the shell
  Vec3 position;            // where the point is, simulation frame [mm]
  Vec3 normal;              // tissue surface normal, out of the tissue: the push direction (unit)
  double depth_mm = 0.0;    // penetration along `normal` [mm], > 0
  double area_mm2 = 0.0;    // the point's share of the tool surface [mm^2]
  Material material = Material::Empty;  // the tissue it is in
  bool cutting = false;     // the point belongs to the cutting head
};

// A symmetric 6x6 matrix over (translation, rotation), row-major.
using Mat6 = std::array<double, 36>;

// ---- 2. ContactFinder ---------------------------------------------------------------------------------

struct ContactStats {
  uint32_t clusters_tested = 0;   // clusters whose points were tested
  uint32_t clusters_skipped = 0;  // clusters skipped: only empty chunks around them
  uint32_t points_tested = 0;     // points sampled against the field
  uint32_t points_clear = 0;      // points not sampled: still within their clearance
  uint32_t contacts = 0;          // points inside tissue
};

class ContactFinder {
 public:
  // Preallocates for a shell of up to max_points points; find() never allocates.
  explicit ContactFinder(size_t max_points, double max_march_voxels = 12.0);

  // The intersection set of `shell` placed by `tool_pose` (tool frame to simulation frame). Between
  // calls tissue may only be removed (cutting), or forgetClearances() must be called first.
  std::span<const ContactPoint> find(VoxelField& field, const PointShell& shell, const Pose& tool_pose,
                                     ContactStats* stats = nullptr);

  // Tissue was added or replaced: sample every point again.
  void forgetClearances();

 private:
  // Depth and normal of one point known to be inside tissue; false when it is not inside after all.
  bool resolve(VoxelField& field, const Vec3& u, const Vec3& inward, const FieldSample& s0, ContactPoint* out) const;

  // Copies the shell's positions as floats, laid out for the 4-wide clearance test.
  void adoptShell(const PointShell& shell);

  // Per point, where it was last sampled outside tissue, in voxel coordinates, and the square of its
  // clearance there [voxel^2]; negative: sample it. Floats, by component (the clearance test runs four
  // points at once): the bound is shrunk by more than their rounding.
  std::vector<float> clear_x_, clear_y_, clear_z_, clear_r2_;
  std::vector<float> shell_x_, shell_y_, shell_z_;  // the shell's positions, tool frame [mm]
  std::vector<uint32_t> due_;                        // the points of a cluster due for a sample
  std::vector<float> due_x_, due_y_, due_z_;         // (padded) where they are [voxel]
  std::vector<float> due_phi_;                       // (padded) the field there
  std::vector<ContactPoint> contacts_;
  const PointShell* clearance_shell_ = nullptr;  // the shell the arrays belong to
  const VoxelField* clearance_field_ = nullptr;  // and the field
  double max_march_voxels_;
};

// ---- 3. force -----------------------------------------------------------------------------------------

// The tool's motion, for damping and friction: point velocity = linear + angular x (point - reference).
struct ToolMotion {
  Vec3 reference;         // the point the moment is taken about, simulation frame [mm]
  Vec3 linear;            // velocity of the reference point [mm/s]
  Vec3 angular;           // angular velocity [rad/s]
};

struct ContactForce {
  Wrench wrench;                 // on the tool: force [N], moment about the reference [N mm]
  double normal_force_n = 0.0;   // sum of the points' normal force magnitudes [N]
  double spring_force_n = 0.0;   // the spring part alone, summed as magnitudes [N]
  Mat6 stiffness{};              // d(-wrench)/d(displacement): springs, [N/mm, N, N mm]
  Mat6 friction_damping{};       // d(-wrench)/d(velocity) of regularized friction [N s/mm, ...]
  double impact_speed_mm_s = 0.0;  // largest normal speed into tissue among the points, 0 if none [mm/s]
};

// Sums the contacts' forces. friction_slip_mm_s: below this sliding speed friction is viscous,
// so it never chatters at rest [mm/s].
ContactForce contactForce(std::span<const ContactPoint> contacts, const SimParams& params, const ToolMotion& motion,
                          double friction_slip_mm_s = 1.0);

}  // namespace dentsim
