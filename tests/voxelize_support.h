// Test helper shared by the CPU and GPU voxelizer tests: the ray set-up on a grid fitted to the layers.
#pragma once

#include <gtest/gtest.h>

#include "volume/mesh_voxelizer.h"

namespace dentsim::test {

// Fits a 2^level grid to the union of the layers and builds their rays; the frame goes to frame_out.
inline RaySetup raySetupFor(const std::vector<MeshLayer>& layers, int level, const VoxelizeOptions& options,
                            VolumeFrame* frame_out = nullptr) {
  Bounds3 b;
  for (const auto& l : layers) b.add(l.mesh->bounds());
  auto frame = fitGridToLevel(b, level);
  EXPECT_TRUE(frame.ok());
  if (!frame) return {};
  if (frame_out) *frame_out = *frame;
  auto setup = makeRaySetup(layers, *frame, options);
  EXPECT_TRUE(setup.ok()) << (setup ? "" : setup.message());
  return setup ? std::move(setup).value() : RaySetup{};
}

}  // namespace dentsim::test
