// Tests of the OpenVDB voxelization peer: a block whose faces lie on voxel faces fills an exact count.
#include "bench/peers.h"

#include <gtest/gtest.h>

#include "test_meshes.h"

namespace dentsim::bench {
namespace {

// An axis-aligned cube [lo, hi]^3 [mm].
TriangleMesh box(float lo, float hi) { return test::box({lo, lo, lo}, {hi, hi, hi}); }

TEST(OpenvdbPeerTest, BlockOnVoxelFacesFillsExactly) {
  // Voxels of 0.1 mm from origin 0: centres at 0.05 + 0.1 i. The box [0.2, 0.8] holds the centres
  // i = 2..7 on each axis, 6^3 = 216 voxels, and no centre lies on its surface.
  const TriangleMesh b = box(0.2f, 0.8f);
  ASSERT_NEAR(b.signedVolume(), 0.216, 1e-6);
  const PeerVoxelize p = openvdbMeshToVolume(b, 0.1, {0.0, 0.0, 0.0});
#ifdef DENTSIM_HAVE_OPENVDB
  ASSERT_TRUE(p.available);
  EXPECT_EQ(p.interior_voxels, 216u);
  EXPECT_NEAR(p.interior_mm3, 0.216, 1e-9);
  EXPECT_GE(p.active_voxels, p.interior_voxels);  // the exterior band is stored too
  EXPECT_GE(p.threads, 1);
  EXPECT_GT(p.ms, 0.0);
#else
  EXPECT_FALSE(p.available);
#endif
}

TEST(OpenvdbPeerTest, OriginShiftsTheLattice) {
  // Moving the grid by half a voxel puts centres at 0.1 i: [0.2, 0.8] then holds i = 3..7 inside
  // and i = 2 and 8 exactly on its faces, which OpenVDB may count either way: 5^3 to 7^3 voxels.
  const PeerVoxelize p = openvdbMeshToVolume(box(0.2f, 0.8f), 0.1, {-0.05, -0.05, -0.05});
  if (!p.available) GTEST_SKIP() << p.name;
  EXPECT_GE(p.interior_voxels, 125u);
  EXPECT_LE(p.interior_voxels, 343u);
}

}  // namespace
}  // namespace dentsim::bench
