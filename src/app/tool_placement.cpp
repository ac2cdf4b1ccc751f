// The tools' starting places beside the tooth's tissue box.
#include "app/tool_placement.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "sim/tool_library.h"

namespace dentsim::app {

Pose drillStartGrip(const TissueBox& box, double above_mm) {
  const Vec3 c = box.centre();
  Pose p;
  p.position = Vec3{c.x, c.y, box.hi.z + above_mm} + kBurGripLocal;
  return p;
}

Pose mirrorGrip(const TissueBox& box, const Vec3& eye) {
  const Vec3 c = box.centre();
  // An eye below the occlusal surface (an upper tooth, or the indirect-vision task) cannot see it:
  // the mirror goes above the crown, distally, clear of the bur over the crown's centre, and shows
  // the occlusal surface. Otherwise it stands beside the distal side.
  const bool from_below = eye.z < box.hi.z;
  const Vec3 crown = from_below ? Vec3{c.x, c.y, box.hi.z - 1.0} : Vec3{c.x, c.y, box.hi.z - 2.5};
  const Vec3 face = from_below ? Vec3{box.hi.x + 5.0, c.y + 2.0, box.hi.z + 9.0} : Vec3{box.hi.x + 7.0, c.y + 4.0, box.hi.z - 1.0};
  const Vec3 z = normalized(normalized(eye - face) + normalized(crown - face));
  const Vec3 to_tooth = crown - face;
  const Vec3 x = normalized(to_tooth - z * dot(to_tooth, z));
  const Vec3 y = cross(z, x);
  Pose p;
  p.rotation = Quat::fromAxes(x, y, z);
  p.position = face + p.rotation.rotate(kMirrorGripLocal);
  return p;
}

std::vector<Vec3> toolSightPoints(const Pose& drill_grip, const Pose* mirror_grip, double mirror_diameter_mm) {
  std::vector<Vec3> points;
  auto along = [&](const Pose& grip, const Vec3& end_local, double beyond) {
    const Vec3 end = grip.position - grip.rotation.rotate(end_local);
    const Vec3 past = grip.position + (grip.position - end) * beyond;
    for (int i = 0; i <= 10; ++i) points.push_back(end + (past - end) * (i / 10.0));
  };
  along(drill_grip, kBurGripLocal, 0.3);
  if (mirror_grip) {
    along(*mirror_grip, kMirrorGripLocal, 0.0);
    const Vec3 face = mirror_grip->position - mirror_grip->rotation.rotate(kMirrorGripLocal);
    const Vec3 u = mirror_grip->rotation.rotate(Vec3{1, 0, 0}), v = mirror_grip->rotation.rotate(Vec3{0, 1, 0});
    for (double ring : {0.5, 1.0})
      for (int k = 0; k < 12; ++k) {
        const double a = k * std::numbers::pi / 6.0, r = ring * 0.5 * mirror_diameter_mm;
        points.push_back(face + u * (r * std::cos(a)) + v * (r * std::sin(a)));
      }
  }
  return points;
}

void addStillMirror(PenPath& path, const Pose& grip) {
  const double end_s = pathEnd(path);
  for (double t : {0.0, end_s}) {
    PenSample s;
    s.t_s = t;
    s.pen = PenRole::Mirror;
    s.pose = grip;
    path.samples.push_back(s);
  }
  std::stable_sort(path.samples.begin(), path.samples.end(), [](const PenSample& a, const PenSample& b) { return a.t_s < b.t_s; });
}

double pathEnd(const PenPath& path) {
  double end_s = 0.0;
  for (const PenSample& s : path.samples) end_s = std::max(end_s, s.t_s);
  return end_s;
}

}  // namespace dentsim::app
