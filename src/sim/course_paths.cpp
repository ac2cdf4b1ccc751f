// The course registry: built-in path names to their generators, and the faulty attempts made from each.
#include "sim/course_paths.h"

#include <algorithm>
#include <cmath>

#include "sim/crown_paths.h"
#include "sim/restorative_paths.h"
#include "sim/scripted_paths.h"

namespace dentsim {

std::string builtinPathNames() {
  std::string out;
  for (const char* name : kBuiltinPaths) out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

bool isBuiltinPath(const std::string& name) {
  return std::any_of(kBuiltinPaths.begin(), kBuiltinPaths.end(), [&](const char* p) { return name == p; });
}

namespace {

// A restorative path's plan as the attempts need it: the path and when the pedal is down.
struct Planned {
  PenPath path;
  double cut_start_s = 0.0, cut_end_s = 0.0;
};

// The pocket's settings and the outline's width for an attempt: the over-cutter's outline is wider,
// the heavy hand presses further and past the floor.
template <typename Settings>
Settings withFault(Settings s, Attempt attempt, const AttemptFaults& faults) {
  if (attempt == Attempt::Overcut) s.widen = faults.overcut_widen;
  if (attempt == Attempt::Heavy) {
    s.pocket.press_mm = std::max(s.pocket.press_mm, 0.1) * faults.heavy_press;
    s.pocket.floor_overshoot_mm = s.pocket.press_mm;
  }
  return s;
}

Result<Planned> restorativePath(const Exercise& e, Attempt attempt, const BrickVolume& volume, const VolumeFrame& frame,
                                const SimParams& params, const AttemptFaults& faults) {
  auto planned = [](const auto& made) -> Result<Planned> {
    if (!made) return made.error();
    return Planned{made->cut.path, made->cut.cut_start_s, made->cut.cut_end_s};
  };
  if (e.path == "class2_cavity")
    return planned(class2CavityPath(volume, frame, params, e.bur, withFault(Class2Settings{}, attempt, faults)));
  if (e.path == "class5_cavity") {
    Class5Settings s;
    s.axis = e.insertion_axis;
    return planned(class5CavityPath(volume, frame, params, e.bur, withFault(s, attempt, faults)));
  }
  if (e.path == "access_cavity")
    return planned(accessCavityPath(volume, frame, params, e.bur, withFault(AccessSettings{}, attempt, faults)));
  return makeError(e.path, "no built-in path of that name (there are " + builtinPathNames() + ")");
}

// The class I path's settings for the exercise's bur.
CavityPathSettings class1Settings(const Exercise& e) {
  CavityPathSettings s;
  if (const std::optional<double> r = burHeadRadiusMm(e.bur)) s.bur_radius_mm = *r;
  return s;
}

}  // namespace

Result<PenPath> expertPath(const Exercise& exercise, const BrickVolume& volume, const VolumeFrame& frame,
                           const SimParams& params) {
  if (exercise.path == "crown_prep") {
    auto made = crownPrepPath(volume, frame, params, exercise.bur, exercise.insertion_axis);
    if (!made) return made.error();
    return made->path;
  }
  if (exercise.path == "caries_removal") return cariesAttemptPath(Attempt::Expert, volume, frame, params, exercise.bur);
  if (exercise.path == "class1_cavity") {
    auto path = cavityPreparationPath(volume, frame, class1Settings(exercise));
    if (!path) return path.error();
    return path->path;
  }
  auto made = restorativePath(exercise, Attempt::Expert, volume, frame, params, {});
  if (!made) return made.error();
  return made->path;
}

Result<PenPath> taskAttemptPath(const Exercise& exercise, Attempt attempt, const BrickVolume& volume,
                                const VolumeFrame& frame, const SimParams& params, const AttemptFaults& faults) {
  if (exercise.path.empty() || exercise.path == "caries_removal") {
    if (exercise.kind != "caries")
      return makeError("task of kind " + exercise.kind, "names no built-in path, so there is no scripted attempt at it");
    return cariesAttemptPath(attempt, volume, frame, params, exercise.bur, {}, faults);
  }
  if (exercise.path == "class1_cavity") return cavityAttemptPath(attempt, volume, frame, class1Settings(exercise), faults);
  if (!isBuiltinPath(exercise.path))
    return makeError(exercise.path, "no built-in path of that name (there are " + builtinPathNames() + ")");
  if (exercise.path == "crown_prep") {
    auto made = crownPrepPath(volume, frame, params, exercise.bur, exercise.insertion_axis);
    if (!made) return made.error();
    switch (attempt) {
      case Attempt::Expert: return made->path;
      case Attempt::Undercut:
        return stoppedPath(made->path, made->cut_start_s + faults.undercut_share * (made->cut_end_s - made->cut_start_s), 3.0,
                           0.3, exercise.insertion_axis);
      case Attempt::Slow: return slowedPath(made->path, faults.slow_factor);
      case Attempt::Token: return stoppedPath(made->path, made->cut_start_s + faults.token_s, 3.0, 0.3, exercise.insertion_axis);
      default:
        return makeError(std::string("attempt ") + attemptName(attempt),
                         "has no crown_prep path of its own: a crown's faults are derived from the professional's session "
                         "(dentsim task validate)");
    }
  }
  // The wrong place is the same groove for every exercise, cut with its bur.
  if (attempt == Attempt::Trench) return cavityAttemptPath(Attempt::Trench, volume, frame, class1Settings(exercise), faults);
  auto made = restorativePath(exercise, attempt, volume, frame, params, faults);
  if (!made) return made.error();
  switch (attempt) {
    case Attempt::Undercut:
      return stoppedPath(made->path, made->cut_start_s + faults.undercut_share * (made->cut_end_s - made->cut_start_s), 3.0, 0.3,
                         exercise.insertion_axis);
    case Attempt::Slow: return slowedPath(made->path, faults.slow_factor);
    case Attempt::Token: return stoppedPath(made->path, made->cut_start_s + faults.token_s, 3.0, 0.3, exercise.insertion_axis);
    case Attempt::Tilted: {
      // Lean toward the mesial (-x), or toward +z for an axis that runs along x.
      const Vec3 toward = std::abs(exercise.insertion_axis.x) > 0.9 ? Vec3{0, 0, 1} : Vec3{-1, 0, 0};
      return tiltedPath(made->path, exercise.insertion_axis, toward, faults.tilt_deg);
    }
    default: return made->path;
  }
}

}  // namespace dentsim
