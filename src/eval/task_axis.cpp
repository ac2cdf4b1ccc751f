// The insertion axes by kind and class: the default of a new task and the check of a written one.
#include "eval/task_axis.h"

#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "eval/task_kinds.h"

namespace dentsim {
namespace {

Vec3 toVec(const std::array<double, 3>& a) { return Vec3{a[0], a[1], a[2]}; }

// "a class I cavity", "a cavity", "an access cavity", "a caries task": what the message is about.
std::string kindText(TaskKind kind, int cavity_class) {
  if (kind == TaskKind::Cavity && cavity_class > 0) return std::string("a class ") + cavityClassName(cavity_class) + " cavity";
  return kindWithArticle(taskKindRow(kind));
}

std::string degrees(double deg) { return std::to_string(int(std::lround(deg))); }

}  // namespace

double angleDeg(const Vec3& a, const Vec3& b) {
  // atan2 of |a x b| and a.b stays exact near 0 and 180, where acos of the dot loses digits.
  return std::atan2(norm(cross(a, b)), dot(a, b)) * (180.0 / std::numbers::pi);
}

int builtinPathClass(const std::string& path) {
  for (const CavityClassRow& row : kCavityClassTable)
    if (path == row.builtin_ideal) return row.black;
  return 0;
}

int taskCavityClass(const Task& task) {
  if (task.kind != TaskKind::Cavity) return 0;
  if (task.cavity_class > 0) return task.cavity_class;
  if (task.ideal && task.ideal->kind == IdealKind::BuiltinPath) return builtinPathClass(task.ideal->path);
  return 0;
}

Vec3 defaultInsertionAxis(TaskKind kind, int cavity_class, const ToothAxes& axes) {
  const Vec3 axis = kind == TaskKind::Cavity && cavity_class == 5 ? toVec(axes.buccal) : toVec(axes.crown);
  return normalized(axis);
}

Vec3 axisForTaskFile(const Vec3& axis) {
  auto round4 = [](double v) { return std::round(v * 1e4) / 1e4 + 0.0; };  // -0 + 0 is +0
  return Vec3{round4(axis.x), round4(axis.y), round4(axis.z)};
}

std::optional<std::string> checkInsertionAxis(const Task& task, const ToothAxes& axes) {
  const Vec3 crown = toVec(axes.crown);
  const double from_crown = angleDeg(task.insertion_axis, crown);
  const int black = taskCavityClass(task);
  const std::string what = kindText(task.kind, black);
  // Into the roots is wrong for every kind, and says so first. A level axis (exactly 90) is a class
  // V's, so rounding must not push it over.
  if (from_crown > kRootsSideDeg + 1e-9)
    return "points " + degrees(from_crown) + " degrees from the tooth's crown axis, into the roots";
  if (black == 5) {
    const double limit = kSmoothSurfaceToleranceDeg;
    // A side only assumed says nothing of where the buccal surface is: any level axis may be its normal.
    if (axes.buccal_source == AxisSource::Assumed) {
      const double from_level = kRootsSideDeg - from_crown;
      if (from_level <= limit) return std::nullopt;
      return "points " + degrees(from_crown) + " degrees from the tooth's crown axis; " + what + "'s bur stands across it, " +
             degrees(kRootsSideDeg - limit) + " to 90 degrees from it (within " + degrees(limit) +
             " of a smooth surface's normal; the tooth's buccal side is not known)";
    }
    const Vec3 buccal = toVec(axes.buccal);
    const double from_buccal = angleDeg(task.insertion_axis, buccal);
    const double from_lingual = 180.0 - from_buccal;
    if (from_buccal <= limit || from_lingual <= limit) return std::nullopt;
    return "points " + degrees(from_buccal) + " degrees from the tooth's buccal axis and " + degrees(from_lingual) +
           " from its lingual axis; " + what + "'s bur stands within " + degrees(limit) +
           " degrees of either (the smooth surface's normal)";
  }
  if (from_crown <= kCrownAxisToleranceDeg) return std::nullopt;
  return "points " + degrees(from_crown) + " degrees from the tooth's crown axis; " + what + "'s bur stands within " +
         degrees(kCrownAxisToleranceDeg) + " degrees of it";
}

}  // namespace dentsim
