// The crown's live reduction map without a window: the margin it reads above, the colours of a box prepared unevenly, and the refresh's rules (one at a time, after a change, an interval apart, each result once).
#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <thread>

#include "app/reduction_map.h"
#include "eval/score_image.h"

namespace dentsim::app {
namespace {

constexpr double kVoxelMm = 0.1;

// A level-6 grid (64 voxels a side, 0.1 mm each) with one box of `m`: x, y in [lo, hi_x), [lo, hi_y), z in [z0, z1).
ToothVolume boxTooth(Material m, uint32_t lo_x, uint32_t hi_x, uint32_t lo_y, uint32_t hi_y, uint32_t z0, uint32_t z1) {
  ToothVolume t;
  t.frame = VolumeFrame::axisAligned(6, kVoxelMm, {0, 0, 0});
  t.voxels = BrickVolume(6);
  for (uint32_t z = z0; z < z1; ++z)
    for (uint32_t y = lo_y; y < hi_y; ++y)
      for (uint32_t x = lo_x; x < hi_x; ++x) t.voxels.setVoxel(x, y, z, makeVoxel(m));
  return t;
}

// The original: enamel x, y in [20, 44), z in [10, 40). The CEJ is its lowest voxel row, centre 10.5
// voxels = 1.05 mm up. The preparation takes 3 voxels off the top (z < 37) and off the -x and -y walls
// (from 23), 1 voxel off the +x wall (x < 43) and 5 off the +y wall (y < 39). Read to the voxel's
// outer faces (eval/crown_prep_reduction.h), that is 0.3 mm occlusally and on -x and -y, 0.1 mm on +x,
// 0.5 mm on +y.
ToothVolume originalBox() { return boxTooth(Material::Enamel, 20, 44, 20, 44, 10, 40); }
ToothVolume preparedBox() { return boxTooth(Material::Enamel, 23, 43, 23, 39, 10, 37); }

// Bands 0.25-0.35 mm on every surface: 0.3 within, 0.1 under, 0.5 over. The map reads above the CEJ
// plus 0.3 mm: 1.35 mm, so rows whose centres are above 13.5 voxels (z >= 14).
Task crownTask() {
  Task t;
  t.name = "box";
  t.kind = TaskKind::Crown;
  t.crown.occlusal_lo_mm = 0.25;
  t.crown.occlusal_hi_mm = 0.35;
  t.crown.axial_lo_mm = 0.25;
  t.crown.axial_hi_mm = 0.35;
  t.crown.margin_above_cej_hi_mm = 0.3;
  return t;
}

TEST(ReductionMap, ReadsAboveTheHighestMarginTheTaskAcceptsOverTheCej) {
  const ToothVolume original = originalBox(), prepared = preparedBox();
  const Task task = crownTask();
  const auto cej = cejHeightMm(original, task.insertion_axis);
  ASSERT_TRUE(cej.has_value());
  EXPECT_NEAR(*cej, 1.05, 1e-9);
  const auto margin = reductionMapMarginMm(task.crown, task.insertion_axis, original, prepared);
  ASSERT_TRUE(margin.has_value());
  EXPECT_NEAR(*margin, 1.35, 1e-9);
}

TEST(ReductionMap, WithoutEnamelItReadsFromTheLowestCutAndNothingBeforeTheFirstCut) {
  const ToothVolume original = boxTooth(Material::Dentin, 20, 44, 20, 44, 10, 40);
  const Task task = crownTask();
  EXPECT_FALSE(cejHeightMm(original, task.insertion_axis).has_value());
  EXPECT_FALSE(reductionMapMarginMm(task.crown, task.insertion_axis, original, original).has_value());
  // A cut whose lowest voxel is row 25 (centre 2.55 mm): the map starts half a voxel under it.
  ToothVolume cut = original;
  cut.voxels.setVoxel(20, 30, 25, makeVoxel(Material::Empty));
  cut.voxels.setVoxel(20, 30, 30, makeVoxel(Material::Empty));
  const auto margin = reductionMapMarginMm(task.crown, task.insertion_axis, original, cut);
  ASSERT_TRUE(margin.has_value());
  EXPECT_NEAR(*margin, 2.5, 1e-9);
  EXPECT_FALSE(drawReductionMap(task, original, original));  // nothing to read: one line, no picture
}

TEST(ReductionMap, AWallLeftThickIsBlueAWallCutTooDeepRedTheRestGreen) {
  const ToothVolume original = originalBox(), prepared = preparedBox();
  const Task task = crownTask();
  auto reduction = measureReduction(original.voxels, prepared.voxels, kVoxelMm, task.insertion_axis, Vec3(-1, 0, 0),
                                    1.35, crownReductionBands(task.crown));
  ASSERT_TRUE(reduction) << reduction.message();
  const CutMarks paint = reductionPaint(*reduction);
  // Mid-wall, mid-height (z 25) and on the occlusal table: the prepared voxel each wall's reading met.
  EXPECT_EQ(paint.at(42, 31, 25), kPaintBlue);   // +x: 0.1 mm off, under
  EXPECT_EQ(paint.at(31, 38, 25), kPaintRed);    // +y: 0.5 mm off, over
  EXPECT_EQ(paint.at(23, 31, 25), kPaintGreen);  // -x: 0.3 mm
  EXPECT_EQ(paint.at(31, 23, 25), kPaintGreen);  // -y: 0.3 mm
  EXPECT_EQ(paint.at(31, 31, 36), kPaintGreen);  // the occlusal table: 0.3 mm
  // The +x wall's whole face from the first row read (z 14) to the table (z 36) is blue.
  for (uint32_t z = 14; z <= 36; ++z) EXPECT_EQ(paint.at(42, 31, z), kPaintBlue) << "z " << z;
  // Below the margin nothing is read or painted.
  EXPECT_EQ(paint.at(42, 31, 13), 0u);
  EXPECT_EQ(paint.at(23, 31, 13), 0u);
  // Blue only on the +x face (x 42), red only on the +y face (y 38): a reading paints the voxel its
  // own ray met, and only the +x wall's rays read under, only the +y wall's over.
  for (uint32_t z = 0; z < 64; ++z)
    for (uint32_t y = 0; y < 64; ++y)
      for (uint32_t x = 0; x < 64; ++x) {
        const uint32_t c = paint.at(x, y, z);
        if (c == kPaintBlue) {
          EXPECT_EQ(x, 42u) << y << " " << z;
        }
        if (c == kPaintRed) {
          EXPECT_EQ(y, 38u) << x << " " << z;
        }
      }
  // Lent to the tooth voxels behind for the picture: the +x wall two voxels deep (x 41 and 42), the
  // +y wall on y 37 and 38, never across the box to another wall.
  const CutMarks thick = reductionPaint(*reduction, &prepared.voxels);
  EXPECT_EQ(thick.at(41, 31, 25), kPaintBlue);
  EXPECT_EQ(thick.at(31, 37, 25), kPaintRed);
  EXPECT_EQ(thick.at(24, 31, 25), kPaintGreen);
  EXPECT_EQ(thick.at(31, 31, 35), kPaintGreen);
  EXPECT_EQ(thick.at(31, 31, 30), 0u);  // the box's core is no one's
  for (uint32_t z = 0; z < 64; ++z)
    for (uint32_t y = 0; y < 64; ++y)
      for (uint32_t x = 0; x < 64; ++x) {
        const uint32_t c = thick.at(x, y, z);
        if (c == kPaintBlue) {
          EXPECT_TRUE(x == 41 || x == 42) << x << " " << y << " " << z;
        }
        if (c == kPaintRed) {
          EXPECT_TRUE(y == 37 || y == 38) << x << " " << y << " " << z;
        }
      }
  // The map itself: a picture, and the bands in its legend.
  auto map = drawReductionMap(task, original, prepared);
  ASSERT_TRUE(map) << map.message();
  EXPECT_GT(map->picture.width, 0);
  EXPECT_EQ(map->legend, "occlusal 0.25-0.35 mm, axial 0.25-0.35 mm");
  EXPECT_NEAR(map->margin_mm, 1.35, 1e-9);
}

// ---- the refresh --------------------------------------------------------------------------------------

using Clock = ReductionMapRefresh::Clock;

ReductionMap mapOfWidth(int width) {
  ReductionMap m;
  m.picture.width = width;
  return m;
}

// Polls take() until the job in flight has finished (it returns at once once released).
std::optional<Result<ReductionMap>> takeWhenDone(ReductionMapRefresh& r) {
  for (int i = 0; i < 20000; ++i) {
    if (auto done = r.take()) return done;
    if (!r.running()) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return std::nullopt;
}

TEST(ReductionMapRefresh, NothingIsDueUntilTheToothChanges) {
  ReductionMapRefresh r(std::chrono::seconds(1));
  const Clock::time_point t0{};
  EXPECT_FALSE(r.due(t0));
  r.toothChanged();
  EXPECT_TRUE(r.due(t0));  // the first map comes at once
}

TEST(ReductionMapRefresh, OneJobAtATimeAndTheNextOnlyAnIntervalAfterTheLastStart) {
  ReductionMapRefresh r(std::chrono::seconds(1));
  const Clock::time_point t0{};
  std::promise<void> release;
  std::shared_future<void> gate = release.get_future().share();
  r.toothChanged();
  r.start(t0, [gate] {
    gate.wait();
    return Result<ReductionMap>(mapOfWidth(7));
  });
  EXPECT_TRUE(r.running());
  EXPECT_FALSE(r.stale());
  r.toothChanged();                                      // cut on while it runs
  EXPECT_FALSE(r.due(t0 + std::chrono::seconds(5)));     // never two at once
  EXPECT_FALSE(r.take().has_value());                    // not finished: nothing to swap in
  release.set_value();
  auto done = takeWhenDone(r);
  ASSERT_TRUE(done.has_value());
  ASSERT_TRUE(*done);
  EXPECT_EQ((*done)->picture.width, 7);
  EXPECT_FALSE(r.take().has_value());                    // swapped in once
  EXPECT_FALSE(r.due(t0 + std::chrono::milliseconds(999)));  // the change waits for the interval
  EXPECT_TRUE(r.due(t0 + std::chrono::seconds(1)));
}

TEST(ReductionMapRefresh, AfterTheLastMapNoNewOneWithoutAChange) {
  ReductionMapRefresh r(std::chrono::seconds(1));
  const Clock::time_point t0{};
  r.toothChanged();
  r.start(t0, [] { return Result<ReductionMap>(mapOfWidth(3)); });
  auto done = r.wait();
  ASSERT_TRUE(done.has_value());
  EXPECT_EQ((**done).picture.width, 3);
  EXPECT_FALSE(r.due(t0 + std::chrono::hours(1)));
}

TEST(ReductionMapRefresh, ADiscardedJobsResultIsDroppedAndItsChangeForgotten) {
  ReductionMapRefresh r(std::chrono::seconds(1));
  const Clock::time_point t0{};
  r.toothChanged();
  r.start(t0, [] { return Result<ReductionMap>(mapOfWidth(5)); });
  r.toothChanged();
  r.discard();  // another tooth, the switch off, a score shown over it
  EXPECT_FALSE(r.wait().has_value());
  EXPECT_FALSE(r.running());
  EXPECT_FALSE(r.due(t0 + std::chrono::hours(1)));
  r.toothChanged();  // the caller wants a new map
  EXPECT_TRUE(r.due(t0 + std::chrono::seconds(1)));
}

}  // namespace
}  // namespace dentsim::app
