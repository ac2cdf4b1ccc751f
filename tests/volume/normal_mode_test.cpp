// Tests for src/volume/normal_mode.cpp: the one check of a neighbour count, and the text form both ways.
#include "volume/normal_mode.h"

#include <gtest/gtest.h>

namespace dentsim {
namespace {

TEST(NormalMode, NeighbourCountsAreThePapersModes) {
  EXPECT_EQ(normalModeFromNeighbours(8.0), NormalMode::Box8);
  EXPECT_EQ(normalModeFromNeighbours(64.0), NormalMode::Box64);
  EXPECT_EQ(normalModeFromNeighbours(216), NormalMode::Box216);
  // Cubes of other sides, and near misses of the modes, are no mode.
  for (double n : {0.0, 1.0, 27.0, 125.0, 512.0, 64.5, -8.0}) EXPECT_FALSE(normalModeFromNeighbours(n)) << n;
}

TEST(NormalMode, BoxSideCubedIsTheNeighbourCount) {
  for (NormalMode m : kNormalModes) {
    const uint32_t side = normalBoxSide(m);
    EXPECT_EQ(int(side * side * side), normalNeighbours(m));
  }
}

TEST(NormalMode, TextRoundTrips) {
  for (NormalMode m : kNormalModes) EXPECT_EQ(parseNormalMode(normalModeName(m)), m);
  EXPECT_EQ(normalModeName(NormalMode::Box64), "64");
  for (const char* bad : {"", "27", "64.0", " 8", "abc"}) EXPECT_FALSE(parseNormalMode(bad)) << bad;
}

}  // namespace
}  // namespace dentsim
