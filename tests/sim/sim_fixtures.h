// Shared fixtures of the sim tests: a flat tissue block in a small grid, a spherical bur, the level-7 built-in molar with a short groove on it.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "core/volume_frame.h"
#include "io/pen_playback.h"
#include "io/session_file.h"
#include "sim/builtin_tooth.h"
#include "sim/scripted_paths.h"
#include "sim/sim_params.h"
#include "sim/tool_library.h"
#include "test_meshes.h"
#include "test_sessions.h"
#include "volume/brick_volume.h"

namespace dentsim::test {

// A 128^3 grid of 0.0125 mm voxels (1.6 mm a side, the voxel of a level-10 molar) whose voxels with
// z < surface_z are solid `m`: the tissue's surface is the plane z = surface_z * 0.0125 mm.
struct Block {
  static constexpr int kLevel = 7;
  static constexpr double kVoxel = 0.0125;
  BrickVolume volume{kLevel};
  VolumeFrame frame = VolumeFrame::axisAligned(kLevel, kVoxel, {0, 0, 0});
  double surface_mm = 0.0;
};

inline Block flatBlock(Material m, uint32_t surface_z = 64) {
  Block b;
  b.surface_mm = surface_z * Block::kVoxel;
  const uint32_t bd = b.volume.brickDim();
  for (uint32_t bz = 0; bz < bd; ++bz)
    for (uint32_t by = 0; by < bd; ++by)
      for (uint32_t bx = 0; bx < bd; ++bx) {
        if ((bz + 1) * DS_BRICK_DIM <= surface_z) {
          b.volume.setBrickUniform({bx, by, bz}, makeVoxel(m));
        } else if (bz * DS_BRICK_DIM < surface_z) {
          for (uint32_t z = bz * DS_BRICK_DIM; z < surface_z; ++z)
            for (uint32_t y = by * DS_BRICK_DIM; y < (by + 1) * DS_BRICK_DIM; ++y)
              for (uint32_t x = bx * DS_BRICK_DIM; x < (bx + 1) * DS_BRICK_DIM; ++x) b.volume.setVoxel(x, y, z, makeVoxel(m));
        }
      }
  return b;
}

// A round bur head: a sphere of radius r [mm] centred at (0, 0, r), so the tip is at the tool origin;
// every point cuts; the grip is at `grip_local`.
inline ToolModel sphereBur(double r, double spacing_mm, Vec3 grip_local = {0, 0, 0}) {
  PointShellParams spacing;
  spacing.head_spacing_mm = spacing_mm;
  spacing.shank_spacing_mm = spacing_mm;
  auto tool = makeToolModel("test_sphere", test::uvSphere({0, 0, r}, r, 192, 96), 2 * r + 1.0, grip_local, spacing);
  return std::move(*tool);
}

// A drill pen over a flat block that presses a round bur of radius r (its grip at the sphere's
// centre) `press` mm below where its tip would touch the surface, at (0.4, 0.8) mm, and slides it
// along +x at `speed_mm_s` with the pedal at `pedal`, from t = 0 to `seconds`.
inline PenPath pressAndSlide(const Block& b, double r, double press, double speed_mm_s, double pedal, double seconds) {
  PenPath path;
  const Vec3 start{0.4, 0.8, b.surface_mm + r - press};
  for (double t : {0.0, seconds}) {
    PenSample s;
    s.t_s = t;
    s.pen = PenRole::Drill;
    s.pose = Pose{start + Vec3{speed_mm_s * t, 0, 0}, Quat{}};
    s.pedal = pedal;
    path.samples.push_back(s);
  }
  return path;
}

// Tissue-on-sphere spring force for a sphere of radius r pressed d deep into a flat surface:
// the integral of stiffness * depth over the spherical cap, k * pi * r * d^2 [N].
inline double capSpringForce(double k, double r, double d) { return k * std::numbers::pi * r * d * d; }

// Level 7: the molar in 0.17 mm voxels, coarse, but a cut takes seconds rather than minutes and the
// bur still spans several voxels.
inline constexpr int kMolarLevel = 7;

// The built-in molar at kMolarLevel, voxelized once per test binary; tests drill copies of it.
inline const ToothVolume& molar() {
  static const ToothVolume tooth = [] {
    auto t = builtinMolarTooth(kMolarLevel);
    EXPECT_TRUE(t.ok()) << t.message();
    return std::move(t).value();
  }();
  return tooth;
}

// A short class I groove on molar(): a third of a lap, about 1.3 s of drilling.
inline PenPath molarGroove() {
  CavityPathSettings s;
  s.laps = 0.3;
  auto path = cavityPreparationPath(molar().voxels, molar().frame, s);
  EXPECT_TRUE(path.ok()) << path.message();
  return path->path;
}

// A professional's stroke as a session holds it: 0.1 s along +x at 1 kHz (101 steps 0.01 mm
// apart), the drill `drill` rendering (0, 0, 2) N through a coupling of `stiffness_n_per_mm`, so
// each step's tool stands 2 / stiffness mm above its pen. Tests of the pro path and the ghost.
inline SessionRecording straightStroke(double stiffness_n_per_mm = 1.0, const std::string& drill = "round_bur_010") {
  SimParams params = defaultSimParams();
  params.coupling.stiffness_n_per_mm = stiffness_n_per_mm;
  SessionRecording s;
  s.info.rate_hz = 1000.0;
  s.info.drill_tool = drill;
  s.info.params_json = simParamsJson(params);
  for (uint64_t k = 0; k <= 100; ++k) {
    SessionStep step;
    step.step = k;
    step.pens = 1;
    step.reading[0].grip.position = {0.01 * double(k), 0.0, 0.0};
    step.force_n[0] = {0.0, 0.0, 2.0};
    s.steps.push_back(step);
  }
  return s;
}

// The header of a session on molar(), for `task` (empty: free drilling).
inline SessionInfo molarSessionInfo(const std::string& created_utc, const std::string& task) {
  SessionInfo info = sessionInfo(created_utc);
  info.task = task;
  info.tooth_source = "builtin:molar:" + std::to_string(kMolarLevel);
  return info;
}

}  // namespace dentsim::test
