// Voxelization cost estimates from the surface's area and the rays' footprint, and the check against the machine's free memory.
#include "volume/voxelize_plan.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "volume/brick_layout.h"

namespace dentsim {
namespace {

// Rates and sizes behind the estimates. The rates were measured on this project's 2-core test
// machine (docs/RELIABILITY.md gives the runs); the sizes are what the code keeps.
constexpr double kBricksPerSurfaceBrickFace = 1.5;  // a sheet of random slope crosses |nx|+|ny|+|nz| ~ 1.5
constexpr double kBrickBytes = DS_BRICK_VOXELS;     // one byte a voxel
constexpr double kBrickCopies = 3.0;                // the pool, the volume built from it, the file's copy
constexpr double kCpuRayBytes = 56.0;               // a hit list and a merged list per ray, and its mask
constexpr double kHitBytes = 12.0;                  // a key, its copy when merged, allocator slack
constexpr double kGpuRayBytes = 16.0;               // counts, offsets, masks and donors per ray of a band
constexpr uint64_t kGpuBandRays = uint64_t{1} << 24;
constexpr double kBaseBytes = 64.0 * 1024 * 1024;    // the program, the meshes and the Vulkan device
constexpr double kCpuSecondsPerRay = 25e-9;
constexpr double kCpuSecondsPerHit = 120e-9;
constexpr double kCpuSecondsPerBrick = 40e-6;
constexpr double kGpuSecondsPerRay = 15e-9;
constexpr double kGpuSecondsPerHit = 60e-9;
constexpr double kGpuSecondsPerBrick = 20e-6;
constexpr double kImportSecondsPerBrick = 60e-6;    // 512 voxels of n^3 samples
constexpr double kImportSecondsPerSourceVoxel = 15e-9;
constexpr double kImportSourceBytes = 6.0;          // labels, codes, marks per source voxel

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

std::string gigabytes(uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2g GB", double(bytes) / 1e9);
  return buf;
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
  const double memory = gpu ? kBaseBytes + band_rays * kGpuRayBytes + hits * 4.0 + bricks * kBrickBytes * kBrickCopies
                            : kBaseBytes + double(c.rays) * kCpuRayBytes + hits * kHitBytes +
                                  bricks * kBrickBytes * kBrickCopies;
  c.memory_bytes = uint64_t(memory + chunkTableBytes(setup.level) + double(setup.corners.size()) * 4.0);
  c.seconds = gpu ? double(c.rays) * kGpuSecondsPerRay + hits * kGpuSecondsPerHit + bricks * kGpuSecondsPerBrick
                  : double(c.rays) * kCpuSecondsPerRay + hits * kCpuSecondsPerHit + bricks * kCpuSecondsPerBrick;
  return c;
}

VoxelizeCost estimateLabelImport(int level, double surface_faces, uint64_t source_voxels) {
  VoxelizeCost c;
  c.level = level;
  c.surface_bricks = bricksForFaces(surface_faces);
  // Sampled bricks: those the surface crosses and their neighbours in the chunks it crosses.
  const double bricks = double(c.surface_bricks);
  c.memory_bytes = uint64_t(kBaseBytes + double(source_voxels) * kImportSourceBytes + chunkTableBytes(level) +
                            bricks * kBrickBytes * kBrickCopies);
  c.seconds = bricks * kImportSecondsPerBrick + double(source_voxels) * kImportSecondsPerSourceVoxel;
  return c;
}

std::string describeCost(const VoxelizeCost& c) {
  const uint64_t side = uint64_t{1} << c.level;
  char time[32];
  if (c.seconds < 1.0) std::snprintf(time, sizeof time, "under a second");
  else if (c.seconds < 120.0) std::snprintf(time, sizeof time, "%.0f s", c.seconds);
  else std::snprintf(time, sizeof time, "%.0f min", c.seconds / 60.0);
  std::ostringstream out;
  out << "level " << c.level << " (" << side << "^3 voxels): about " << withThousands(c.surface_bricks)
      << " dense bricks, " << gigabytes(c.memory_bytes) << " of memory and " << time;
  return out.str();
}

uint64_t availableMemoryBytes() {
  // A lab PC shared with other programs, or a test, sets what counts as free.
  if (const char* limit = std::getenv("DENTSIM_MEMORY_LIMIT_MB"); limit && *limit) {
    char* end = nullptr;
    const unsigned long long mb = std::strtoull(limit, &end, 10);
    if (end && *end == '\0' && mb > 0) return uint64_t(mb) * 1024 * 1024;
  }
  std::ifstream in("/proc/meminfo");
  std::string key;
  uint64_t kib = 0;
  std::string unit;
  while (in >> key >> kib >> unit)
    if (key == "MemAvailable:") return kib * 1024;
  return 0;
}

Status checkAffordable(const VoxelizeCost& cost, uint64_t available, bool force, const std::string& where) {
  if (force) return Ok{};
  if (cost.crossings_per_ray > kMaxCrossingsPerRay) {
    char crossings[32];
    std::snprintf(crossings, sizeof crossings, "%.0f", cost.crossings_per_ray);
    return makeError(where, std::string("the meshes cross each ray ") + crossings +
                                " times on average, where a tooth's layers cross it a few times: random or piled-up "
                                "triangles? " + describeCost(cost) + "; give --force to try it all the same");
  }
  if (available == 0 || cost.memory_bytes <= available) return Ok{};
  return makeError(where, describeCost(cost) + ", but this machine has " + gigabytes(available) +
                              " free; choose a lower --level (or a larger voxel), or give --force to try it all the same");
}

}  // namespace dentsim
