// Pen scripts in the tooth frame, and the check of where they start.
#include "sim/pen_script.h"

#include <cmath>
#include <cstdio>

#include "sim/tool_library.h"
#include "volume/tooth_frame.h"

namespace dentsim {
namespace {

Vec3 vec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }

// The tissue at `p` [mm], or Empty outside the grid or in empty space.
Material tissueAt(const ToothVolume& tooth, const Vec3& p) {
  const VolumeFrame& f = tooth.frame;
  int64_t i[3];
  for (int a = 0; a < 3; ++a) {
    const double g = std::floor((p[a] - f.origin_mm[size_t(a)]) / f.voxel_mm);
    if (!(g >= 0 && g < double(f.dim()))) return Material::Empty;
    i[a] = int64_t(g);
  }
  const Voxel v = tooth.voxels.voxel(uint32_t(i[0]), uint32_t(i[1]), uint32_t(i[2]));
  return voxelFill(v) > 0 ? voxelMaterial(v) : Material::Empty;
}

std::string millimetres(const Vec3& p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%.2f, %.2f, %.2f) mm", p.x, p.y, p.z);
  return text;
}

}  // namespace

Pose toothFramePose(const ToothVolume& tooth) {
  const ToothAxes& a = tooth.frame.tooth;
  const Vec3 z = normalized(vec(a.crown));
  const Vec3 x = normalized(-vec(a.mesial));
  const Vec3 y = cross(z, x);
  return Pose{toothOcclusalCentreMm(tooth), Quat::fromAxes(x, y, z)};
}

PenPath penPathInSimulationFrame(const PenPath& path, const ToothVolume& tooth) {
  if (path.frame == PenFrame::Simulation) return path;
  const Pose frame = toothFramePose(tooth);
  PenPath out = path;
  out.frame = PenFrame::Simulation;
  for (PenSample& s : out.samples) {
    s.pose.position = frame.apply(s.pose.position);
    s.pose.rotation = frame.rotation * s.pose.rotation;
  }
  return out;
}

std::vector<std::string> penPathStartWarnings(const PenPath& path, const ToothVolume& tooth, const std::string& where) {
  std::vector<std::string> out;
  bool seen[2] = {false, false};
  for (const PenSample& s : path.samples) {
    const size_t pen = s.pen == PenRole::Drill ? 0 : 1;
    if (seen[pen]) continue;
    seen[pen] = true;
    // The bur's tip, and the centre of its head a little above it; the mirror's face centre.
    const std::vector<Vec3> points = s.pen == PenRole::Drill
                                         ? std::vector<Vec3>{s.pose.apply(-kBurGripLocal), s.pose.apply(Vec3{0, 0, 0.5} - kBurGripLocal)}
                                         : std::vector<Vec3>{s.pose.apply(-kMirrorGripLocal)};
    for (const Vec3& p : points) {
      const Material m = tissueAt(tooth, p);
      if (m == Material::Empty) continue;
      const Vec3 centre = toothOcclusalCentreMm(tooth);
      out.push_back(where + ": the " + (s.pen == PenRole::Drill ? "bur" : "mirror") + " starts inside the tooth (" +
                    materialName(m) + " at " + millimetres(p) + ", t = " + std::to_string(s.t_s).substr(0, 6) +
                    " s); start it above the crown: the occlusal centre is " + millimetres(centre) +
                    " and the grip sits " + std::to_string(int(kBurGripLocal.z)) + " mm above the bur's tip (docs/PEN_PATHS.md)");
      break;
    }
    if (seen[0] && seen[1]) break;
  }
  return out;
}

}  // namespace dentsim
