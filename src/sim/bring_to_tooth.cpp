// Finding the professional's first contact and backing the bur off it.
#include "sim/bring_to_tooth.h"

#include "sim/voxel_field.h"

namespace dentsim {
namespace {

// The shell's points tested: the cutting head's where the tool has one (a bur meets the tooth with
// its head first, and the head is a fraction of the shell), else all.
bool touches(const ToolModel& drill, const Pose& grip, VoxelField& field) {
  const PointShell& shell = drill.shell;
  const bool head_only = drill.cuts && !shell.cutting.empty();
  for (size_t i = 0; i < shell.positions.size(); ++i) {
    if (head_only && !shell.cutting[i]) continue;
    const Vec3 p = grip.position + grip.rotation.rotate(shell.positions[i] - drill.grip_local);
    if (field.sample(field.toVoxel(p)).phi > 0.0) return true;
  }
  return false;
}

}  // namespace

bool shellTouches(const ToolModel& drill, const Pose& grip, const BrickVolume& volume, const VolumeFrame& frame) {
  VoxelField field(volume, frame);
  return touches(drill, grip, field);
}

std::optional<BringToTooth> bringToTooth(const PenPath& pro, const ToolModel& drill, const BrickVolume& volume,
                                         const VolumeFrame& frame, double clearance_mm) {
  VoxelField field(volume, frame);
  for (const PenSample& s : pro.samples) {
    if (s.pen != PenRole::Drill || !touches(drill, s.pose, field)) continue;
    const Vec3 up = s.pose.rotation.rotate(Vec3{0, 0, 1});
    const double step = 0.25 * frame.voxel_mm;
    Pose grip = s.pose;
    double backed = 0.0;
    while (touches(drill, grip, field)) {
      if (backed > 20.0) return std::nullopt;  // buried: no way out along the axis
      grip.position += up * step;
      backed += step;
    }
    grip.position += up * clearance_mm;
    return BringToTooth{grip, s.t_s, backed + clearance_mm};
  }
  return std::nullopt;
}

}  // namespace dentsim
