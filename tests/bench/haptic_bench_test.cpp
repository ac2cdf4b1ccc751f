// Tests of the haptic benchmark: the scripted cavity path on the molar, the resting height on a flat slab, and a short run's report (no timing goals).
#include "bench/haptic_bench.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "model/builtin_assets.h"
#include "sim/builtin_tooth.h"
#include "test_support.h"
#include "volume/mesh_voxelizer.h"

namespace dentsim::bench {
namespace {

// The built-in molar, kept alive for the CPU reference maker (which holds pointers to its meshes).
struct Molar {
  MolarLayers layers = std::move(loadBuiltinMolar()).value();
  VolumeMaker maker() const {
    return cpuVolumeMaker(builtinMolarLayers(layers));
  }
};

// A short preparation: a quarter of a lap, so a run lasts under two seconds.
CavityPathSettings shortPath() {
  CavityPathSettings p;
  p.laps = 0.25;
  p.hold_s = 0.05;
  p.dwell_s = 0.1;
  return p;
}

TEST(HapticBenchTest, RestingHeightOnAFlatSlab) {
  // 32^3 voxels of 0.1 mm, enamel below voxel z = 16: the field crosses zero halfway between the
  // centres of voxels 15 and 16, at z = 16 x 0.1 = 1.6 mm. A ball resting on a plane touches it with
  // its lowest point, so the tip height is 1.6 mm whatever the radius.
  BrickVolume volume(5);
  for (uint32_t z = 0; z < 16; ++z)
    for (uint32_t y = 0; y < 32; ++y)
      for (uint32_t x = 0; x < 32; ++x) volume.setVoxel(x, y, z, makeVoxel(Material::Enamel));
  const VolumeFrame frame = VolumeFrame::axisAligned(5, 0.1, {0, 0, 0});
  for (double r : {0.2, 0.5}) {
    const std::optional<double> tip = restingTipHeight(volume, frame, 1.6, 1.6, r);
    ASSERT_TRUE(tip.has_value());
    EXPECT_NEAR(*tip, 1.6, 1e-3) << "radius " << r;
  }
  // Outside the grid there is nothing to rest on.
  EXPECT_FALSE(restingTipHeight(volume, frame, 10.0, 10.0, 0.5).has_value());
}

TEST(HapticBenchTest, CavityPathOnTheMolar) {
  const Molar molar;
  auto tooth = molar.maker()(7);
  ASSERT_TRUE(tooth.ok()) << tooth.message();
  const CavityPathSettings s;  // the benchmark's own path
  auto cavity = cavityPreparationPath(tooth->voxels, tooth->frame, s);
  ASSERT_TRUE(cavity.ok()) << cavity.message();
  const PenPath& path = cavity->path;
  ASSERT_TRUE(checkPenPath(path, "cavity").ok());

  // The fossa lies on the occlusal table: within the search radius of the crown's centre, below the
  // cusp tips (z = 7.6 mm) and well above the CEJ (z = 0).
  const Vec3 d = cavity->fossa_mm - cavity->crown_centre_mm;
  EXPECT_LE(std::hypot(d.x, d.y), s.fossa_search_mm + 1e-9);
  EXPECT_GT(cavity->fossa_mm.z, 3.0);
  EXPECT_LT(cavity->fossa_mm.z, 7.6);

  // One lap of a 2 x 1.2 mm oval: Ramanujan's perimeter pi (3(a+b) - sqrt((3a+b)(a+3b))) = 5.105 mm.
  EXPECT_NEAR(cavity->outline_mm, 5.105, 0.005);
  const double expected_s =
      s.hold_s + s.descent_s + s.dwell_s + s.laps * cavity->outline_mm / s.speed_mm_s + s.lift_s;
  EXPECT_NEAR(cavity->duration_s, expected_s, 1e-9);
  EXPECT_NEAR(cavity->duration_s, 5.8, 0.1);  // "about 6 s"

  // The pen starts above the outline's +x end, gripping the vertical bur 19 mm above its tip.
  const Vec3 first = path.samples.front().pose.position;
  EXPECT_NEAR(first.x, cavity->fossa_mm.x + 0.5 * s.oval_x_mm, 1e-12);
  EXPECT_NEAR(first.y, cavity->fossa_mm.y, 1e-12);
  const double start_rest = first.z - 19.0 - s.approach_mm;  // the bur's resting height there
  EXPECT_GE(start_rest, cavity->fossa_mm.z - 1e-9) << "the fossa is the lowest resting point nearby";

  // Every sample: the drill, vertical, sampled every 10 ms at most; the pedal is down exactly between
  // the cut's start and end; the outline stays on the oval.
  double lowest = HUGE_VAL;
  for (size_t i = 0; i < path.samples.size(); ++i) {
    const PenSample& p = path.samples[i];
    EXPECT_EQ(p.pen, PenRole::Drill);
    EXPECT_EQ(p.pose.rotation, Quat{});
    if (i > 0) {
      EXPECT_LE(p.t_s - path.samples[i - 1].t_s, s.sample_s + 1e-9);
    }
    EXPECT_EQ(p.pedal, p.t_s >= cavity->cut_start_s && p.t_s < cavity->cut_end_s ? 1.0 : 0.0) << "t " << p.t_s;
    const double ex = (p.pose.position.x - cavity->fossa_mm.x) / (0.5 * s.oval_x_mm);
    const double ey = (p.pose.position.y - cavity->fossa_mm.y) / (0.5 * s.oval_y_mm);
    EXPECT_NEAR(ex * ex + ey * ey, 1.0, 1e-3) << "t " << p.t_s;
    lowest = std::min(lowest, p.pose.position.z - 19.0);
  }
  // The target presses press_mm under the start's resting height, and no more than a lap's step
  // deeper than press_mm under the surface (which the fossa bounds from below nearby).
  EXPECT_LE(lowest, start_rest - s.press_mm + 1e-9);
  EXPECT_GT(lowest, cavity->fossa_mm.z - s.press_mm - s.laps * s.step_down_mm - 1.0);
}

TEST(HapticBenchTest, ShortRunReportIsConsistent) {
  const Molar molar;
  HapticBenchSettings s;
  s.path = shortPath();
  std::vector<std::string> lines;
  auto row = runHapticBench(7, molar.maker(), s, [&](const std::string& line) { lines.push_back(line); });
  ASSERT_TRUE(row.ok()) << row.message();
  const HapticBenchRow& r = *row;
  EXPECT_FALSE(lines.empty());
  EXPECT_EQ(r.level, 7);
  EXPECT_GT(r.shell_points, r.shell_cutting_points);
  EXPECT_GT(r.shell_cutting_points, 0u);

  // Steps: the loop ran until its time passed the path's end; the bench thread looks every 10 ms, so
  // it overshoots by a few steps (generous slack for a busy machine).
  const auto needed = uint64_t(std::ceil(r.path.duration_s * 1000.0 - 1e-9)) + 1;
  EXPECT_GE(r.thread.steps, needed);
  EXPECT_LE(r.thread.steps, needed + 1000);
  EXPECT_EQ(r.load.steps, r.thread.steps);  // every step's snapshot was seen once
  EXPECT_LE(r.missed_deadlines, r.thread.steps);
  EXPECT_EQ(r.pen_dropouts, 0u);
  EXPECT_FALSE(r.scheduler.empty());
  // The thread asked idle CPUs to stay awake (the default bound, 0 us); granted only where the
  // request file opens for writing, and the report says which.
  const int qos = ::open("/dev/cpu_dma_latency", O_WRONLY | O_CLOEXEC);
  if (qos >= 0) ::close(qos);
  EXPECT_EQ(r.idle_latency_held, qos >= 0) << r.idle_latency_note;
  EXPECT_NE(r.idle_latency_note.find("/dev/cpu_dma_latency"), std::string::npos) << r.idle_latency_note;

  // Percentiles are ordered.
  for (const StepTimeSummary* t : {&r.thread, &r.step_only, &r.after_idle}) {
    EXPECT_GT(t->p50_us, 0.0);
    EXPECT_LE(t->p50_us, t->p90_us);
    EXPECT_LE(t->p90_us, t->p99_us);
    EXPECT_LE(t->p99_us, t->p999_us);
    EXPECT_LE(t->p999_us, t->max_us);
    EXPECT_LE(t->mean_us, t->max_us);
    ASSERT_EQ(t->tail.size(), 9u);
    for (size_t i = 1; i < t->tail.size(); ++i) EXPECT_LE(t->tail[i - 1].second, t->tail[i].second);
  }

  // Work: points tested every step, some in tissue, a force shown, and tissue removed.
  EXPECT_GT(r.load.points_mean, 0.0);
  EXPECT_LE(double(r.load.points_max), double(r.shell_points));
  EXPECT_GT(r.load.clear_mean, 0.0) << "points within their clearance skip their sample";
  EXPECT_LE(r.load.points_mean + r.load.clear_mean, double(r.shell_points));
  EXPECT_GT(r.load.contacts_max, 0u);
  EXPECT_GT(r.load.contact_steps, 0u);
  EXPECT_GT(r.load.force_mean_n, 0.0);
  EXPECT_LE(r.load.force_max_n, 8.0 + 1e-9);  // the device's force clamp
  EXPECT_GT(r.removed_mm3, 0.0);
  EXPECT_GT(r.voxels_changed, 0u);
  EXPECT_EQ(r.deferred_cuts, 0u);

  // Every edit made reached the drain thread, and replaying them gave the loop's voxels.
  EXPECT_EQ(r.edits_drained, r.voxels_changed);
  EXPECT_TRUE(r.mirror_checked);
  EXPECT_TRUE(r.mirror_equal);

  // The thread kept to the step budget; whatever it reached, replaying its steps' schedules on a
  // copy of the tooth gave its voxels.
  EXPECT_TRUE(r.budgeted);
  EXPECT_EQ(r.rate_hz, 1000.0);
  EXPECT_TRUE(r.replay_checked);
  EXPECT_TRUE(r.replay_equal);
  EXPECT_LE(r.contact_overruns, r.thread.steps);
  EXPECT_LE(r.late_cut_steps, r.thread.steps);
  EXPECT_LE(double(r.load.points_left_max), double(r.shell_points));

  // The step-only run plays the very same steps without a budget. Where the budget never cut the
  // thread's work short (the usual case at level 7), the loop is deterministic and the two agree
  // exactly, force for force; otherwise the force error says by how much.
  ASSERT_TRUE(r.has_step_only);
  EXPECT_EQ(r.step_only.steps, r.thread.steps);
  EXPECT_GT(r.force_error.steps, 0u);
  EXPECT_GT(r.force_error.mean_contact_n, 0.0);
  EXPECT_LE(r.force_error.rms_n, r.force_error.max_n);
  if (r.contact_overruns == 0 && r.late_cut_steps == 0) {
    EXPECT_EQ(r.force_error.max_n, 0.0);
    EXPECT_EQ(r.step_only_voxels_changed, r.voxels_changed);
    EXPECT_EQ(r.step_only_removed_mm3, r.removed_mm3);
    EXPECT_EQ(r.step_only_load.points_max, r.load.points_max);
    EXPECT_EQ(r.step_only_load.clear_mean, r.load.clear_mean);
    EXPECT_EQ(r.step_only_load.contacts_max, r.load.contacts_max);
  }
  // The path error's floor: step only again with the pen a tenth of a micrometre off.
  ASSERT_TRUE(r.has_path_floor);
  EXPECT_EQ(r.path_floor_offset_mm, s.floor_offset_mm);
  EXPECT_GT(r.path_floor.steps, 0u);
  EXPECT_GT(r.path_floor.mean_contact_n, 0.0);
  EXPECT_LE(r.path_floor.rms_n, r.path_floor.max_n);
  // The bare timer ran as many steps as the thread, at the thread's policy, each a busy wait as long
  // as the thread's mean step.
  ASSERT_TRUE(r.has_bare_timer);
  EXPECT_EQ(r.bare_steps, r.thread.steps);
  EXPECT_EQ(r.bare_scheduler, r.scheduler);
  EXPECT_EQ(r.bare_busy_us, r.thread.mean_us);
  EXPECT_LE(r.bare_missed, r.bare_steps);
  EXPECT_GE(r.bare_max_wake_late_us, 0.0);
  // The run whose steps each start 1 ms after the last has no budget either: it cuts as step only.
  ASSERT_TRUE(r.has_after_idle);
  EXPECT_EQ(r.after_idle.steps, r.thread.steps);
  EXPECT_EQ(r.after_idle_voxels_changed, r.step_only_voxels_changed);
  EXPECT_EQ(r.after_idle_removed_mm3, r.step_only_removed_mm3);

  // The goals are computed, not asserted: this is a tiny level on a shared machine.
  EXPECT_EQ(r.p99_met, r.thread.p99_us < s.goal_p99_us);
  EXPECT_EQ(r.max_met, r.thread.max_us < s.goal_max_us);

  // The report: JSON, Markdown and SVG name the level and its figures.
  HapticReportInfo info;
  info.model = "test molar";
  info.settings = s;
  const std::vector<HapticBenchRow> rows{r};
  const nlohmann::json j = hapticReportJson(info, rows);
  EXPECT_EQ(j["benchmark"], "haptic");
  ASSERT_EQ(j["levels"].size(), 1u);
  EXPECT_EQ(j["levels"][0]["thread"]["times"]["steps"], r.thread.steps);
  EXPECT_EQ(j["levels"][0]["thread"]["edits_drained"], r.edits_drained);
  EXPECT_EQ(j["levels"][0]["thread"]["budget"]["replay_equal"], r.replay_equal);
  EXPECT_EQ(j["levels"][0]["force_error"]["rms_n"], r.force_error.rms_n);
  EXPECT_EQ(j["levels"][0]["path_error_floor"]["error"]["rms_n"], r.path_floor.rms_n);
  EXPECT_EQ(j["levels"][0]["path_error_floor"]["pen_offset_mm"], s.floor_offset_mm);
  EXPECT_EQ(j["levels"][0]["bare_timer"]["missed_deadlines"], r.bare_missed);
  EXPECT_EQ(j["levels"][0]["bare_timer"]["steps"], r.bare_steps);

  EXPECT_TRUE(j["goals"]["met"].is_null());  // no level 10 here
  const std::string md = hapticReportMarkdown(info, rows);
  EXPECT_NE(md.find("| 7 | "), std::string::npos);
  EXPECT_NE(md.find("step only"), std::string::npos);
  EXPECT_NE(md.find("passes cut short"), std::string::npos);
  EXPECT_NE(md.find("| after idle | "), std::string::npos);
  EXPECT_NE(md.find("| bare timer ("), std::string::npos);
  EXPECT_NE(md.find("its floor RMS"), std::string::npos);
  EXPECT_NE(md.find(r.idle_latency_note), std::string::npos);
  EXPECT_EQ(j["levels"][0]["thread"]["idle_latency"]["held"], r.idle_latency_held);
  EXPECT_EQ(j["levels"][0]["after_idle"]["times"]["steps"], r.after_idle.steps);
  EXPECT_EQ(j["levels"][0]["after_idle"]["voxels_changed"], r.after_idle_voxels_changed);
  const std::string svg = hapticRowsSvg(rows, s);
  EXPECT_NE(svg.find("level 7, thread"), std::string::npos);
  EXPECT_NE(svg.find("level 7, after idle"), std::string::npos);

  const test::TempDir dir;
  ASSERT_TRUE(writeHapticReport(dir.path().string(), info, rows).ok());
  for (const char* name : {"haptic.json", "haptic.md", "haptic.svg"})
    EXPECT_GT(std::filesystem::file_size(dir.path() / name), 100u) << name;
}

TEST(HapticBenchTest, BadPathSettingsAreErrors) {
  BrickVolume volume(5);
  const VolumeFrame frame = VolumeFrame::axisAligned(5, 0.1, {0, 0, 0});
  CavityPathSettings s;
  s.laps = 0;
  EXPECT_FALSE(cavityPreparationPath(volume, frame, s).ok());
  // An empty volume has no fossa.
  auto empty = cavityPreparationPath(volume, frame, CavityPathSettings{});
  ASSERT_FALSE(empty.ok());
  EXPECT_NE(empty.message().find("no tissue"), std::string::npos);
}

}  // namespace
}  // namespace dentsim::bench
