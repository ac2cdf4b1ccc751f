// Tests for src/eval/task_axis.cpp: a new task's default axis is the tooth's own, and each kind's valid axes, with the angle and range named.
#include "eval/task_axis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "eval_fixtures.h"

namespace dentsim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A tooth leaning 17 degrees toward +x (the micro-CT molar), its sides known: crown
// (sin 17, 0, cos 17), buccal -y, mesial = buccal x crown.
ToothAxes leaningTooth() {
  ToothAxes a;
  a.crown = {std::sin(17 * kDeg), 0, std::cos(17 * kDeg)};
  a.buccal = {0, -1, 0};
  a.mesial = {-std::cos(17 * kDeg), 0, std::sin(17 * kDeg)};
  a.crown_source = a.buccal_source = a.mesial_source = AxisSource::Given;
  return a;
}

Task cavityOfClass(int black, Vec3 axis) {
  Task t = test::cavityTask();
  t.cavity_class = black;
  t.insertion_axis = normalized(axis);
  return t;
}

// The axis `deg` degrees from the leaning crown, tipped toward +y (across the lean).
Vec3 offCrown(double deg) {
  const ToothAxes a = leaningTooth();
  const Vec3 crown{a.crown[0], a.crown[1], a.crown[2]};
  return std::cos(deg * kDeg) * crown + std::sin(deg * kDeg) * Vec3{0, 1, 0};
}

TEST(TaskAxis, ANewTaskStandsAlongTheToothNotTheGrid) {
  const ToothAxes a = leaningTooth();
  for (TaskKind kind : {TaskKind::Caries, TaskKind::Cavity, TaskKind::Access}) {
    const Vec3 axis = defaultInsertionAxis(kind, 1, a);
    EXPECT_NEAR(axis.x, std::sin(17 * kDeg), 1e-12);  // 0.2924, not the grid's 0
    EXPECT_NEAR(axis.z, std::cos(17 * kDeg), 1e-12);
  }
  // A class V comes from buccal; a class V's number on a caries task means nothing.
  EXPECT_EQ(defaultInsertionAxis(TaskKind::Cavity, 5, a), (Vec3{0, -1, 0}));
  EXPECT_NEAR(defaultInsertionAxis(TaskKind::Caries, 5, a).z, std::cos(17 * kDeg), 1e-12);
}

TEST(TaskAxis, TheClassComesFromTheTaskOrItsBuiltInPath) {
  Task t = test::cavityTask();
  EXPECT_EQ(taskCavityClass(t), 0);
  t.ideal = IdealSpec{IdealKind::BuiltinPath, "class5_cavity", "", "", "", ""};
  EXPECT_EQ(taskCavityClass(t), 5);
  t.cavity_class = 2;  // said outright, it wins
  EXPECT_EQ(taskCavityClass(t), 2);
  Task access = test::cavityTask();
  access.kind = TaskKind::Access;
  access.cavity_class = 5;
  EXPECT_EQ(taskCavityClass(access), 0);
  EXPECT_EQ(builtinPathClass("class1_cavity"), 1);
  EXPECT_EQ(builtinPathClass("access_cavity"), 0);
}

TEST(TaskAxis, AnOcclusalCavityStandsWithin45DegreesOfTheCrown) {
  const ToothAxes a = leaningTooth();
  EXPECT_FALSE(checkInsertionAxis(cavityOfClass(1, offCrown(0)), a));
  EXPECT_FALSE(checkInsertionAxis(cavityOfClass(1, offCrown(30)), a));
  // The grid's +z is 17 degrees off this tooth: still an occlusal approach.
  EXPECT_FALSE(checkInsertionAxis(cavityOfClass(1, {0, 0, 1}), a));
  const auto sixty = checkInsertionAxis(cavityOfClass(1, offCrown(60)), a);
  ASSERT_TRUE(sixty);
  EXPECT_EQ(*sixty, "points 60 degrees from the tooth's crown axis; a class I cavity's bur stands within 45 degrees of it");
  Task access = cavityOfClass(0, offCrown(50));
  access.kind = TaskKind::Access;
  EXPECT_EQ(checkInsertionAxis(access, a).value_or(""),
            "points 50 degrees from the tooth's crown axis; an access cavity's bur stands within 45 degrees of it");
  Task caries = test::cariesTask();
  caries.insertion_axis = offCrown(46);
  EXPECT_EQ(checkInsertionAxis(caries, a).value_or(""),
            "points 46 degrees from the tooth's crown axis; a caries task's bur stands within 45 degrees of it");
  // The buccal axis is a class I's mistake.
  EXPECT_EQ(checkInsertionAxis(cavityOfClass(1, {0, -1, 0}), a).value_or(""),
            "points 90 degrees from the tooth's crown axis; a class I cavity's bur stands within 45 degrees of it");
}

TEST(TaskAxis, AClassVStandsAlongTheBuccalOrLingualNormal) {
  const ToothAxes a = leaningTooth();
  // Buccal, lingual, and 30 degrees off buccal toward the crown, all valid.
  EXPECT_FALSE(checkInsertionAxis(cavityOfClass(5, {0, -1, 0}), a));
  EXPECT_FALSE(checkInsertionAxis(cavityOfClass(5, {0, 1, 0}), a));
  EXPECT_FALSE(checkInsertionAxis(cavityOfClass(5, {0, -std::cos(30 * kDeg), std::sin(30 * kDeg)}), a));
  // 50 degrees off buccal, 130 off lingual.
  EXPECT_EQ(checkInsertionAxis(cavityOfClass(5, {0, -std::cos(50 * kDeg), std::sin(50 * kDeg)}), a).value_or(""),
            "points 50 degrees from the tooth's buccal axis and 130 from its lingual axis; a class V cavity's bur "
            "stands within 35 degrees of either (the smooth surface's normal)");
  // The shipped class V on the built-in molar: level from buccal, crown +z, 90 degrees exactly.
  ToothAxes upright;
  upright.crown_source = upright.buccal_source = upright.mesial_source = AxisSource::Given;
  Task shipped = test::cavityTask();
  shipped.ideal = IdealSpec{IdealKind::BuiltinPath, "class5_cavity", "", "", "", ""};
  shipped.insertion_axis = {0, -1, 0};
  EXPECT_FALSE(checkInsertionAxis(shipped, upright));
  // Tipped below level toward the roots, it is wrong whatever the class.
  shipped.insertion_axis = normalized(Vec3{0, -1, -0.2});
  EXPECT_EQ(checkInsertionAxis(shipped, upright).value_or(""), "points 101 degrees from the tooth's crown axis, into the roots");
}

TEST(TaskAxis, AClassVOnAToothOfUnknownSidesNeedsOnlyToStandAcrossTheCrown) {
  ToothAxes a;  // all assumed: crown +z, buccal -y
  a.crown_source = AxisSource::Found;
  EXPECT_FALSE(checkInsertionAxis(cavityOfClass(5, {1, 0, 0}), a));  // the mesial side may well be buccal
  EXPECT_FALSE(checkInsertionAxis(cavityOfClass(5, {1, 0, std::tan(30 * kDeg)}), a));
  EXPECT_EQ(checkInsertionAxis(cavityOfClass(5, {1, 0, 1}), a).value_or(""),
            "points 45 degrees from the tooth's crown axis; a class V cavity's bur stands across it, 55 to 90 degrees "
            "from it (within 35 of a smooth surface's normal; the tooth's buccal side is not known)");
}

}  // namespace
}  // namespace dentsim
