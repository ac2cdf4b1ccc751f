// The meshing benchmark (the paper's Figure 15, issue 4): re-meshing time per level and normal mode, a bur's per-frame re-mesh, normal accuracy, VTK beside it.
//
// dentsim's mesher comes in as callables (MeshRunner), so the command passes the GPU mesher
// (gpuMeshRunner, bench/gpu_runners.h) and tests the CPU reference; tooth volumes come in the same
// way (VolumeMaker). Nothing here needs a GPU.
//
// Contents
//   1. What is injected: the mesher and the volumes
//   2. Figure 15: full surface and a 1/32^3 part per level and normal mode, VTK Flying Edges per level
//   3. The bur path: a ball carving along the occlusal surface, one re-mesh per frame
//   4. Normal accuracy on a voxelized sphere and torus (CPU reference)
//   5. The whole run and its report: JSON, Markdown, SVG
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/analytic_solid.h"
#include "bench/peers.h"
#include "core/result.h"
#include "core/triangle_mesh.h"
#include "volume/brick_volume.h"
#include "volume/mesh_voxelizer.h"

namespace dentsim::bench {

// ---- 1. what is injected ---------------------------------------------------------------------------

// One call of dentsim's mesher, timed by the host clock.
struct MeshTiming {
  double ms = 0.0;             // wall time of the call, results ready for drawing [ms]
  double kernel_ms = 0.0;      // GPU kernel time from timestamps [ms]; 0 where not measured
  uint64_t triangles = 0;      // triangles of the whole surface after the call
  uint64_t blocks_meshed = 0;  // cell blocks the call meshed; 0 where the mesher does not say
};

// dentsim's mesher. `update` may assume that `full` ran last on the same volume with the same mode,
// and that since then the voxels changed inside `dirty` only (sorted (z, y, x), unique): the GPU
// mesher keeps its surface between calls. normals: 8, 64 or 216.
struct MeshRunner {
  std::string name;    // what runs: "GPU mesher on <device>", "CPU reference (meshVolumeCpu)"
  std::string mesher;  // the tables' short label: "gpu", "cpu" (GpuSurface's two meshers), "reference"
  std::function<Result<MeshTiming>(const ToothVolume& tooth, int normals)> full;
  std::function<Result<MeshTiming>(const ToothVolume& tooth, std::span<const BrickCoord> dirty, int normals)> update;
};

// The CPU reference as a runner: full is meshVolumeCpu; update meshes the whole volume again with
// it too (a stand-in until an incremental CPU path exists), so its part times are full times.
MeshRunner cpuReferenceRunner();

// The tooth at one level: the command voxelizes the built-in molar on the GPU (layersVolumeMaker in
// bench/gpu_runners.h), tests build small solids.
using VolumeMaker = std::function<Result<ToothVolume>(int level)>;

// A VolumeMaker that voxelizes `layers` with the CPU reference into a grid fitted to their bounds
// (fitGridToLevel, 2 empty voxels of margin). The meshes must outlive the maker.
VolumeMaker cpuVolumeMaker(std::vector<MeshLayer> layers, VoxelizeOptions options = {});

// ---- 2. Figure 15 ----------------------------------------------------------------------------------

// The "1/32^3 part of the space": the bricks of a cube of side dim/32 voxels (brick-aligned, at
// least one brick) around a point on the surface, chosen as follows. The column through the centre
// of the solid's bounds in x and y (or, if it holds no solid, the first that does on square rings of
// growing size around it, lowest y then x first) gives its topmost solid voxel: the anchor, on the
// occlusal surface of a tooth whose crown points to +z. The cube's centre is as near the anchor
// voxel's centre as whole bricks allow (a one-brick part is the anchor's brick), inside the grid.
struct SurfacePart {
  std::array<uint32_t, 3> anchor{};  // anchor voxel (x, y, z)
  uint32_t side_voxels = 0;          // dim / divisor before rounding up to whole bricks
  uint32_t side_bricks = 0;          // bricks per side of the cube
  BrickCoord lo;                     // lowest brick of the cube
  std::vector<BrickCoord> bricks;    // (side_bricks^3) the cube's bricks, sorted (z, y, x)
};

// Errors: a volume without solid voxels (fill over one half).
Result<SurfacePart> surfacePart(const BrickVolume& volume, int divisor = 32);

struct MeshBenchSettings;

// One normal mode at one level.
struct ModeTiming {
  int normals = 0;                    // 8, 64 or 216
  std::vector<double> full_runs_ms;   // (repeats) [ms]
  double full_ms = 0.0;               // median [ms]
  double full_kernel_ms = 0.0;        // median of kernel times [ms]
  uint64_t triangles = 0;             // of the full surface
  uint64_t full_blocks = 0;           // blocks a full mesh meshes
  std::vector<double> part_runs_ms;   // (repeats) update of the part's bricks [ms]
  double part_ms = 0.0;               // median [ms]
  double part_kernel_ms = 0.0;        // median of kernel times [ms]
  uint64_t part_blocks = 0;           // blocks the part's update meshes
  double vtk_ratio = 0.0;             // full_ms / VTK's median; 0 when VTK did not run
};

struct MeshLevelRow {
  int level = 0;                 // octree level: grid 2^L per side
  double voxel_mm = 0.0;         // voxel edge [mm]
  uint64_t dense_bricks = 0;     // of the tooth
  SurfacePart part;              // what the part updates re-mesh
  std::vector<ModeTiming> modes; // per normal mode, in settings order
  PeerMesh vtk;                  // Flying Edges on the same voxels, once per level (its own normals)
};

// For each normal mode: full() once untimed (warm-up) when asked, `repeats` timed full() runs, then
// update() of the part's bricks likewise. Then VTK `repeats` times. Errors are the runner's.
Result<MeshLevelRow> measureMeshLevel(const ToothVolume& tooth, const MeshBenchSettings& settings,
                                      const MeshRunner& runner);

// ---- 3. the bur path -------------------------------------------------------------------------------

// A round bur (a ball) sweeping the occlusal surface at constant speed, one carve and one re-mesh per
// displayed frame. The path runs along x through the centre of the solid's bounds in y, back and forth
// over the middle `span` of the solid's x extent. Each frame the ball first comes to rest from above
// on the original surface (each column's topmost crossing of phi = 0.5), then sinks `depth` into it;
// each further pass over the line sinks another `depth`, so every pass cuts fresh material.
struct BurPathSettings {
  int level = 10;               // octree level of the tooth
  int normals = 216;            // normal mode of the re-mesh
  int frames = 120;             // frames carved and re-meshed
  double fps = 60.0;            // frames per second [1/s]
  double speed_mm_s = 5.0;      // bur speed along the path [mm/s]
  double diameter_mm = 1.0;     // ball diameter [mm]
  double depth_mm = 0.3;        // depth the ball sinks below the surface per pass [mm]
  double span = 0.6;            // share of the solid's x extent the path covers, (0, 1]
  double target_p95_ms = 8.0;   // the goal for the 95th percentile of the re-mesh [ms]
};

// The ball centre of every frame [mm] in the tooth's frame. Errors: no solid under the line.
Result<std::vector<Vec3d>> burPath(const ToothVolume& tooth, const BurPathSettings& settings);

struct BurFrame {
  Vec3d centre_mm{};             // ball centre [mm]
  double carve_ms = 0.0;         // carveBall on the CPU bricks [ms]
  double update_ms = 0.0;        // the runner's update [ms]; 0 when nothing changed
  double kernel_ms = 0.0;        // its GPU kernel time [ms]
  uint32_t dirty_bricks = 0;     // bricks the carve changed
  uint64_t blocks_meshed = 0;    // blocks the update meshed
  uint64_t voxels_changed = 0;   // voxels the carve changed
  double removed_mm3 = 0.0;      // solid the carve removed [mm^3]
  uint64_t triangles = 0;        // of the surface after the update
};

struct BurPathResult {
  BurPathSettings settings;
  double voxel_mm = 0.0;          // voxel edge of the tooth [mm]
  std::vector<BurFrame> frames;   // (settings.frames)
  int frames_cut = 0;             // frames that changed a voxel (the others re-mesh nothing)
  double p50_ms = 0.0, p95_ms = 0.0, max_ms = 0.0;  // of update_ms over all frames [ms]
  double mean_dirty_bricks = 0.0; // per frame
  double max_dirty_bricks = 0.0;  // per frame
  double mean_blocks = 0.0;       // blocks meshed per frame
  double mean_carve_ms = 0.0;     // [ms]
  double removed_mm3 = 0.0;       // over the path [mm^3]
  bool meets_target = false;      // p95_ms < settings.target_p95_ms
};

// Builds the surface once (full, untimed), then carves and updates frame by frame. `tooth` is taken
// by value: the carving changes the copy only. Errors are the runner's and burPath's.
Result<BurPathResult> measureBurPath(ToothVolume tooth, const BurPathSettings& settings, const MeshRunner& runner);

// ---- 4. normal accuracy ----------------------------------------------------------------------------

struct NormalsSettings {
  std::vector<int> levels{7, 8, 9};            // grids of the voxelized solids
  std::vector<int> normal_modes{8, 64, 216};
  int samples = 8;                             // coverage samples per voxel side (fillCoverage)
};

// Angle between meshVolumeCpu's vertex normals and the solid's analytic normal at each vertex.
struct NormalErrorRow {
  std::string solid;        // AnalyticSolid::describe()
  int level = 0;
  int normals = 0;          // 8, 64 or 216
  uint64_t vertices = 0;
  uint64_t triangles = 0;
  double mean_deg = 0.0;    // [deg]
  double p95_deg = 0.0;     // nearest rank [deg]
  double max_deg = 0.0;     // [deg]
};

// The row of one solid, voxelized in `tooth` (voxel units = tooth's voxels), for one mode.
Result<NormalErrorRow> measureNormalError(const ToothVolume& tooth, const AnalyticSolid& solid, int normals);
// Every level and mode for sphereForLevel and torusForLevel, exact-coverage fill.
Result<std::vector<NormalErrorRow>> measureNormalErrors(const NormalsSettings& settings);

// ---- 5. the whole run and its report ---------------------------------------------------------------

struct MeshBenchSettings {
  std::vector<int> levels{8, 9, 10};           // Figure 15 levels
  std::vector<int> normal_modes{8, 64, 216};
  int repeats = 5;                             // timed runs per measurement; the median is reported
  bool warmup = true;                          // one untimed run before each series
  bool peers = true;                           // run VTK
  int part_divisor = 32;                       // the part's cube side is dim / part_divisor
  bool bur = true;                             // run the bur path
  BurPathSettings bur_path;
  bool normal_errors = true;                   // run the normal accuracy table
  NormalsSettings normals;
};

struct MeshReport {
  std::string mesher;  // MeshRunner::mesher of the run
  std::vector<MeshLevelRow> levels;
  bool has_bur = false;
  BurPathResult bur;
  std::vector<NormalErrorRow> normals;
};

// Where and how it was measured, printed above the tables and stored in the JSON.
struct MeshReportInfo {
  std::string model;        // "built-in four-layer molar"
  std::string command;      // the command line
  std::string cpu;          // CPU model
  int cpu_threads = 0;      // hardware threads
  std::string device;       // Vulkan device and driver, or "none"
  std::string runner;       // MeshRunner::name
  MeshBenchSettings settings;
};

// Runs everything the settings ask for: each Figure 15 level with a tooth from `make_volume`
// (the bur path reuses its level's tooth when that level is measured), then the bur path, then the
// normal errors. `log` receives one line per measurement as it finishes.
Result<MeshReport> runMeshBench(const MeshBenchSettings& settings, const VolumeMaker& make_volume,
                                const MeshRunner& runner,
                                const std::function<void(const std::string&)>& log = {});

nlohmann::json meshReportJson(const MeshReportInfo& info, const MeshReport& report);
std::string meshReportMarkdown(const MeshReportInfo& info, const MeshReport& report);
// Time against level, one colour per normal mode: full solid, part dashed, VTK its own dotted series.
std::string meshReportSvg(const MeshReport& report);
// Re-mesh time of each bur frame, with the target as a flat line.
std::string burPathSvg(const BurPathResult& bur);

// Writes mesh.json, mesh.md, mesh.svg and (with a bur path) mesh_bur.svg into `dir`, each atomically.
// Errors name the file.
Status writeMeshReport(const std::string& dir, const MeshReportInfo& info, const MeshReport& report);

}  // namespace dentsim::bench
