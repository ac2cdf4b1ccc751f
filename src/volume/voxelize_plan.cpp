// Voxelization cost estimates from the surface's area and the rays' footprint, and the check against the machine's free memory.
#include "volume/voxelize_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "io/input_budget.h"
#include "volume/brick_layout.h"

namespace dentsim {
namespace {

// Rates and sizes behind the estimates, fitted to peaks (max RSS) and times measured on this
// project's 2-core build machine at levels 9 to 12 (`dentsim bench plan`, docs/PERFORMANCE.md);
// the sizes follow what the code keeps. The GPU rates are lavapipe's, the Vulkan driver CI has: a
// hardware GPU takes a fraction of that time, so the estimate errs high there.
constexpr double kBricksPerSurfaceBrickFace = 1.5;  // a sheet of random slope crosses |nx|+|ny|+|nz| ~ 1.5
constexpr double kBrickBytes = DS_BRICK_VOXELS;     // one byte a voxel
constexpr double kBrickCopies = 3.0;                // the pool, the volume built from it, the file's copy
constexpr double kCpuRayBytes = 56.0;               // a hit list and a merged list per ray, and its mask
constexpr double kHitBytes = 12.0;                  // a key, its copy when merged, allocator slack
constexpr double kGpuRayBytes = 16.0;               // counts, offsets, masks and donors per ray of a band
constexpr uint64_t kGpuBandRays = uint64_t{1} << 24;
constexpr double kBaseBytes = 64.0 * 1024 * 1024;     // the program and the meshes
constexpr double kGpuBaseBytes = 160.0 * 1024 * 1024; // and a Vulkan device (lavapipe's own pools)
constexpr double kCpuSecondsPerRay = 38e-9;
constexpr double kCpuSecondsPerHit = 180e-9;
constexpr double kCpuSecondsPerBrick = 60e-6;
// Beyond about half a gigabyte the CPU path's hit lists outgrow the caches and its sort waits on
// memory: level 12 of the CHAI3D molar took 6.9 times level 11 where rays, hits and bricks grew 4.
constexpr double kCpuCacheBytes = 0.5e9;
constexpr double kCpuSecondsPerByteBeyondCache = 10.0 / 1e9;
constexpr double kGpuSecondsPerRay = 45e-9;
constexpr double kGpuSecondsPerHit = 180e-9;
constexpr double kGpuSecondsPerBrick = 60e-6;
constexpr double kGpuStartSeconds = 0.3;             // the instance, the device and the pipelines
constexpr double kImportSecondsPerBrick = 25e-6;     // 512 voxels of n^3 samples, the fill and the file
constexpr double kImportSecondsPerSourceVoxel = 15e-9;
constexpr double kImportSourceBytes = 3.0;           // labels (2 bytes) and tissue codes (1) per source voxel
constexpr double kImportCodeBytes = 1.0;             // the codes, kept while the bricks are built
constexpr double kImportBytesPerBrick = 1700.0;      // the volume, its chunk tiles and the file's copy (~3.3 x 512)
constexpr double kScanBytesPerVoxel = 6.0;           // floats (4) and the segmentation's labels and masks (2)
constexpr double kScanSecondsPerVoxel = 85e-9;       // decode, smoothing, thresholds and components

double chunkTableBytes(int level) {
  const double chunks_per_side = std::max(1.0, std::ldexp(1.0, level - DS_BRICK_LOG2 - DS_CHUNK_LOG2));
  return chunks_per_side * chunks_per_side * chunks_per_side * 4.0;
}

uint64_t bricksForFaces(double faces) {
  return uint64_t(std::ceil(kBricksPerSurfaceBrickFace * faces / double(DS_BRICK_DIM * DS_BRICK_DIM)));
}

std::string withThousands(uint64_t v) {
  std::string s = std::to_string(v);
  for (int i = int(s.size()) - 3; i > 0; i -= 3) s.insert(size_t(i), " ");
  return s;
}


}  // namespace

VoxelizeCost estimateMeshVoxelize(const RaySetup& setup, bool gpu) {
  VoxelizeCost c;
  c.level = setup.level;
  const double S = setup.subsamples;
  c.rays = uint64_t(setup.ray_x1 - setup.ray_x0) * (setup.ray_y1 - setup.ray_y0);
  // Corners are in sub-ray units across and voxels along the rays: the area in voxel faces, and
  // the hits as each triangle's footprint in rays.
  double faces = 0.0, hits = 0.0;
  for (size_t t = 0; t + 9 <= setup.corners.size(); t += 9) {
    const float* p = &setup.corners[t];
    const double ax = (p[3] - p[0]) / S, ay = (p[4] - p[1]) / S, az = p[5] - p[2];
    const double bx = (p[6] - p[0]) / S, by = (p[7] - p[1]) / S, bz = p[8] - p[2];
    const double nx = ay * bz - az * by, ny = az * bx - ax * bz, nz = ax * by - ay * bx;
    faces += 0.5 * std::sqrt(nx * nx + ny * ny + nz * nz);
    hits += 0.5 * std::abs(nz) * S * S;
  }
  const double grid_bricks = std::ldexp(1.0, 3 * (setup.level - DS_BRICK_LOG2));
  c.surface_bricks = uint64_t(std::min(double(bricksForFaces(faces)), grid_bricks));  // no more than the grid has
  c.crossings_per_ray = c.rays > 0 ? hits / double(c.rays) : 0.0;
  const double bricks = double(c.surface_bricks);
  const double band_rays = double(std::min<uint64_t>(c.rays, kGpuBandRays));
  const double memory = gpu ? kGpuBaseBytes + band_rays * kGpuRayBytes + hits * 4.0 + bricks * kBrickBytes * kBrickCopies
                            : kBaseBytes + double(c.rays) * kCpuRayBytes + hits * kHitBytes +
                                  bricks * kBrickBytes * kBrickCopies;
  c.memory_bytes = uint64_t(memory + chunkTableBytes(setup.level) + double(setup.corners.size()) * 4.0);
  c.seconds = gpu ? kGpuStartSeconds + double(c.rays) * kGpuSecondsPerRay + hits * kGpuSecondsPerHit + bricks * kGpuSecondsPerBrick
                  : double(c.rays) * kCpuSecondsPerRay + hits * kCpuSecondsPerHit + bricks * kCpuSecondsPerBrick +
                        std::max(0.0, double(c.memory_bytes) - kCpuCacheBytes) * kCpuSecondsPerByteBeyondCache;
  return c;
}

VoxelizeCost estimateLabelImport(int level, double surface_faces, uint64_t source_voxels) {
  VoxelizeCost c;
  c.level = level;
  // The faces are counted voxel face by voxel face, so they are a staircase's own area already.
  c.surface_bricks = uint64_t(std::ceil(surface_faces / double(DS_BRICK_DIM * DS_BRICK_DIM)));
  const double bricks = double(c.surface_bricks), source = double(source_voxels);
  const double peak = std::max(source * kImportSourceBytes, source * kImportCodeBytes + bricks * kImportBytesPerBrick);
  c.memory_bytes = uint64_t(kBaseBytes + chunkTableBytes(level) + peak);
  c.seconds = bricks * kImportSecondsPerBrick + source * kImportSecondsPerSourceVoxel;
  return c;
}

VoxelizeCost estimateScanRead(uint64_t voxels, uint32_t stored_bytes) {
  VoxelizeCost c;
  c.scan_voxels = voxels;
  c.memory_bytes = uint64_t(kBaseBytes + double(voxels) * (kScanBytesPerVoxel + double(stored_bytes)));
  c.seconds = double(voxels) * kScanSecondsPerVoxel;
  return c;
}

std::string describeCost(const VoxelizeCost& c) {
  char time[32];
  if (c.seconds < 1.0) std::snprintf(time, sizeof time, "under a second");
  else if (c.seconds < 120.0) std::snprintf(time, sizeof time, "%.0f s", c.seconds);
  else std::snprintf(time, sizeof time, "%.0f min", c.seconds / 60.0);
  std::ostringstream out;
  if (c.level == 0) {
    out << "reading the scan (" << withThousands(c.scan_voxels) << " voxels): about " << gigabytesText(c.memory_bytes)
        << " of memory and " << time;
    return out.str();
  }
  const uint64_t side = uint64_t{1} << c.level;
  out << "level " << c.level << " (" << side << "^3 voxels): about " << withThousands(c.surface_bricks)
      << " dense bricks, " << gigabytesText(c.memory_bytes) << " of memory and " << time;
  return out.str();
}

Status checkAffordable(const VoxelizeCost& cost, uint64_t budget, bool force, const std::string& where) {
  if (force) return Ok{};
  if (cost.crossings_per_ray > kMaxCrossingsPerRay) {
    char crossings[32];
    std::snprintf(crossings, sizeof crossings, "%.0f", cost.crossings_per_ray);
    return makeError(where, std::string("the meshes cross each ray ") + crossings +
                                " times on average, where a tooth's layers cross it a few times: random or piled-up "
                                "triangles? " + describeCost(cost) + "; give --force to try it all the same");
  }
  if (budget == 0 || cost.memory_bytes <= budget) return Ok{};
  // A scan's read has no level to lower: its size is the file's.
  const char* advice = cost.level == 0 ? "read a smaller export of the scan (cropped to the tooth) or raise the budget"
                                       : "choose a lower --level (or a larger voxel)";
  return makeError(where, describeCost(cost) + ", beyond the memory budget of " + gigabytesText(budget) + " (" +
                              memoryBudgetOrigin() + "); " + advice + ", or give --force to try it all the same");
}

}  // namespace dentsim
