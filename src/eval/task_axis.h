// The insertion axes a task may ask for on its tooth: the one `task new` writes by default and the ones `task check` accepts, by the task's kind and Black's class.
//
// The bur enters a preparation along the path the restoration will later be seated on. An
// occlusal cavity (class I, II), an endodontic access and a caries excavation from above are cut
// near the tooth's long axis, its crown axis. A class V sits on a smooth surface near the gum, and
// is cut along that surface's normal, across the long axis: the tooth frame's buccal axis, or its
// opposite for a lingual one. A bur more than 90 degrees from the crown axis comes in from the
// roots' side, which no kind of preparation does.
//
//   kind and class                       valid insertion axis (angle to the tooth's axis)
//   cavity class V                       within 35 deg of the buccal or the lingual axis
//                                        (of the plane across the crown axis when the tooth's
//                                        buccal side was only assumed), and at most 90 from the crown
//   any other cavity, access, caries     within 45 deg of the crown axis
#pragma once

#include <optional>
#include <string>

#include "core/rigid.h"
#include "core/volume_frame.h"
#include "eval/task.h"

namespace dentsim {

// Within this of the crown axis, a bur enters along the tooth [deg]: halfway between along it and
// across it, so that an axis nearer the crown than the side is an occlusal approach.
inline constexpr double kCrownAxisToleranceDeg = 45.0;
// Within this of the smooth surface's normal, a class V bur cuts that surface [deg]. The shipped
// class V holds its bur level, 15 deg off the cervical bulge's normal (docs/SCORING.md, section
// 10); 35 leaves a teacher 20 more, and keeps the class V axes (at least 55 from the crown) apart
// from the occlusal ones.
inline constexpr double kSmoothSurfaceToleranceDeg = 35.0;
// Beyond this from the crown axis, the bur comes in from the roots' side [deg].
inline constexpr double kRootsSideDeg = 90.0;

// The angle between two directions [deg], in [0, 180]; neither need be unit.
double angleDeg(const Vec3& a, const Vec3& b);

// The Black class a built-in ideal path cuts (class1_cavity: 1, class2_cavity: 2, class5_cavity: 5),
// or 0 for any other name.
int builtinPathClass(const std::string& path);

// The task's Black class: its cavity_class when given, else the class its built-in ideal path
// cuts, else 0. Always 0 for a task that is not a cavity.
int taskCavityClass(const Task& task);

// The axis a new task of this kind and class starts with on a tooth of these axes (unit): the
// buccal axis for a class V cavity, the crown axis for everything else.
Vec3 defaultInsertionAxis(TaskKind kind, int cavity_class, const ToothAxes& axes);

// The axis as `task new` and `task set-ideal` write it into a task file: each component to four
// decimals (a hundredth of a degree), never -0.
Vec3 axisForTaskFile(const Vec3& axis);

// What is wrong with the task's insertion_axis on a tooth of these axes: one line naming the kind,
// the angle and the valid range ("points 60 degrees from the tooth's crown axis; a class I cavity's
// bur stands within 45 degrees of it"), without the key; none when the axis is valid.
std::optional<std::string> checkInsertionAxis(const Task& task, const ToothAxes& axes);

}  // namespace dentsim
