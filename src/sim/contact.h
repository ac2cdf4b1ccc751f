// Contact between a tool's point shell and the tooth's voxels: which points are inside tissue, how deep, and the force and moment.
//
// Contents
//   1. ContactPoint, Mat6
//   2. ContactFinder: the intersection set of a posed point shell (clusters skip empty chunks), in full
//      or within a budget (a deadline or a point count, or a cluster count replay prescribes)
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
  uint32_t contacts = 0;          // points inside tissue (those carried over included)
  // A budgeted pass only:
  uint32_t clusters_reached = 0;  // clusters the pass reached, in its order (tested or skipped)
  uint32_t clusters_left = 0;     // clusters it did not reach: first in the next pass
  uint32_t points_left = 0;       // their points
  uint32_t contacts_carried = 0;  // contacts of those clusters taken from the last pass
};

// What a pass may spend. A pass reaches clusters in the order: those the last pass did not reach,
// then those that were in contact, then the rest; it stops before a cluster whose points would be
// sampled once the deadline has passed or the points sampled reach max_points, but never before the
// first such cluster: a pass begun late still gets somewhere. Replay gives
// `clusters` instead: exactly that many, whatever the clock says.
struct ContactBudget {
  static constexpr uint32_t kAll = 0xFFFFFFFFu;
  int64_t deadline_ns = 0;        // steady clock (core/steady_clock.h); 0: none
  uint32_t max_points = 0;        // 0: none
  uint32_t clusters = kAll;       // not kAll: reach exactly this many clusters (the two above unused)
};

class ContactFinder {
 public:
  // Preallocates for a shell of up to max_points points; find() never allocates.
  explicit ContactFinder(size_t max_points, double max_march_voxels = 12.0);

  // The intersection set of `shell` placed by `tool_pose` (tool frame to simulation frame), ordered
  // by point. Between calls tissue may only be removed (cutting), or forgetClearances() must be
  // called first. With a budget, the clusters the pass does not reach keep the contacts the last
  // pass found for them (the partial pass blended with the last whole one, point by point); a pass
  // that reaches every cluster gives what an unbudgeted one gives.
  std::span<const ContactPoint> find(VoxelField& field, const PointShell& shell, const Pose& tool_pose,
                                     ContactStats* stats = nullptr, const ContactBudget* budget = nullptr);

  // Tissue was added or replaced: sample every point again (and carry no contact over).
  void forgetClearances();

  // The swept check of a move (Xu & Barbic's continuous collision, in discrete sub-poses): the
  // shell is placed at each of `poses` in turn (the move's sub-poses, from just after the pose of
  // the last find() to its end) and every point that was not in the last find()'s contact set is
  // sampled. Returns how many sub-poses the move may take: up to and including the first at which
  // such a point is a voxel or more inside tissue (it is then in contact, and the next step's
  // springs hold it), or all of them. The first sub-pose is always taken, so a move never stalls.
  uint32_t sweep(VoxelField& field, const PointShell& shell, std::span<const Pose> poses);

 private:
  // Depth and normal of one point known to be inside tissue; false when it is not inside after all.
  bool resolve(VoxelField& field, const Vec3& u, const Vec3& inward, const FieldSample& s0, ContactPoint* out) const;

  // Copies the shell's positions as floats, laid out for the 4-wide clearance test.
  void adoptShell(const PointShell& shell);
  // Tests one cluster's points (tool frame to voxel coordinates by m, t), appending its contacts.
  struct Placement;
  void testCluster(VoxelField& field, const PointShell& shell, const ShellCluster& cluster, const Placement& at,
                   uint32_t* looks, ContactStats* st);
  // The order of a budgeted pass (see ContactBudget) into order_.
  void orderClusters(const PointShell& shell);

  // Per point, where it was last sampled outside tissue, in voxel coordinates, and the square of its
  // clearance there [voxel^2]; negative: sample it. Floats, by component (the clearance test runs four
  // points at once): the bound is shrunk by more than their rounding.
  std::vector<float> clear_x_, clear_y_, clear_z_, clear_r2_;
  std::vector<float> shell_x_, shell_y_, shell_z_;  // the shell's positions, tool frame [mm]
  std::vector<uint32_t> due_;                        // the points of a cluster due for a sample
  std::vector<float> due_x_, due_y_, due_z_;         // (padded) where they are [voxel]
  std::vector<float> due_phi_;                       // (padded) the field there
  std::vector<ContactPoint> contacts_;
  std::vector<ContactPoint> last_contacts_;   // the last pass's, by point: carried over for clusters not reached
  std::vector<uint32_t> order_;               // (clusters) a budgeted pass's order
  std::vector<uint32_t> left_;                // (clusters) the clusters the last pass did not reach, in its order
  std::vector<uint8_t> in_contact_;           // (points) set only during sweep(): the last find()'s contacts
  std::vector<uint64_t> queued_;              // (clusters) the pass that put a cluster in order_ (dedup stamp)
  uint64_t pass_ = 0;
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
