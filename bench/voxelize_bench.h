// The voxelization benchmark (the paper's Figure 10 and Table 1): dentsim's voxelizer against OpenVDB's meshToVolume.
//
// Contents
//   1. The model: tissue layers decimated to a share of their triangles
//   2. One measurement: a model in one grid, dentsim and the peer, repeated, medians
//   3. The report: JSON, Markdown and an SVG plot of time against triangles per level
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/mesh_decimate.h"
#include "bench/peers.h"
#include "core/result.h"
#include "core/triangle_mesh.h"
#include "core/volume_frame.h"
#include "volume/brick_volume.h"
#include "volume/mesh_voxelizer.h"

namespace dentsim::bench {

// ---- 1. the model ------------------------------------------------------------------------------

// One tissue surface after decimation.
struct BenchLayer {
  std::string name;                    // "enamel"
  Material material = Material::Dentin;
  TriangleMesh mesh;                   // the decimated surface [mm]
  DecimateInfo decimation;             // counts, method and open edges of `mesh`
  double mesh_mm3 = 0.0;               // volume the decimated surface encloses [mm^3]
};

// Every layer of a model decimated to the same share of its triangles.
struct DecimatedModel {
  double fraction = 1.0;               // share of each layer's triangles kept, (0, 1]
  std::vector<BenchLayer> layers;

  uint64_t triangles() const;          // over all layers
  std::vector<MeshLayer> meshLayers() const;  // views for the voxelizer; valid while this lives
};

DecimatedModel decimateModel(const std::vector<MeshLayer>& layers, double fraction);

// ---- 2. one measurement ------------------------------------------------------------------------

// One run of dentsim's voxelizer on all layers at once, timed by the host clock.
struct DentsimRun {
  double ms = 0.0;            // ray set-up + voxelization + bricks mirrored to the CPU [ms]
  double kernel_ms = 0.0;     // GPU kernel time from timestamps [ms]; 0 where not measured
  uint64_t hits = 0;          // ray-surface crossings
  uint64_t dense_bricks = 0;  // dense bricks of the result
  MaterialTotals totals;      // voxels and fill per material of the result
};

// Runs dentsim's voxelizer once: gpuVoxelizer (bench/gpu_runners.h) in the command, a fake in tests.
using DentsimVoxelizer = std::function<Result<DentsimRun>(const std::vector<MeshLayer>& layers,
                                                          const VolumeFrame& frame)>;

struct VoxelizeBenchSettings {
  int repeats = 3;       // timed runs per system; the median is reported
  bool warmup = true;    // one untimed dentsim run first (pipeline compilation, first allocations)
  bool peers = true;     // run OpenVDB too (when built in)
};

// One tissue in one row.
struct TissueRow {
  std::string name;              // layer name
  Material material = Material::Dentin;
  uint64_t triangles = 0;        // after decimation
  std::string decimation;        // DecimateInfo::method
  uint64_t open_edges = 0;       // of the decimated surface
  double deviation_mm = 0.0;     // meshoptimizer's geometric error of the decimation [mm]
  double mesh_mm3 = 0.0;         // volume the decimated surface encloses [mm^3]
  double dentsim_mm3 = 0.0;      // dentsim voxels of this material, fill-weighted [mm^3]; a voxel
                                 // holds one material, so an inner layer's volume is not counted here
  double openvdb_mm3 = 0.0;      // OpenVDB interior of this surface alone, filled variant [mm^3]
  double openvdb_band_mm3 = 0.0; // the same from the narrow-band variant's signs [mm^3]
  double openvdb_ms = 0.0;       // median meshToVolume time of this layer, filled variant [ms]
};

// One OpenVDB variant in one row.
struct PeerTiming {
  bool available = false;        // it ran
  std::string name;              // what it is, or why it did not run
  int threads = 0;               // TBB threads it could use
  std::vector<double> runs_ms;   // (repeats) sum over layers per run [ms]
  double ms = 0.0;               // median [ms]
  double ratio = 0.0;            // ms / dentsim's median; 0 when it did not run
};

struct VoxelizeRow {
  int level = 0;                      // octree level L: grid 2^L per side
  double voxel_mm = 0.0;              // voxel edge [mm], the same for both systems
  double fraction = 1.0;              // share of triangles kept
  uint64_t triangles = 0;             // over all layers
  int repeats = 0;                    // timed runs per system
  std::vector<double> dentsim_runs_ms;  // (repeats) [ms]
  double dentsim_ms = 0.0;            // median [ms]
  double dentsim_kernel_ms = 0.0;     // median of kernel time [ms]
  uint64_t hits = 0;                  // ray-surface crossings
  uint64_t dense_bricks = 0;          // of dentsim's result
  PeerTiming openvdb;                 // interior filled: the like-for-like peer
  PeerTiming openvdb_band;            // narrow band only, interior by sign: OpenVDB's usual level set
  std::vector<TissueRow> tissues;     // per layer
};

// Voxelizes `model` in `frame` with dentsim (warm-up, then `repeats` runs) and both OpenVDB
// variants (each layer on its own, `repeats` runs each). Errors are dentsim's.
Result<VoxelizeRow> measureVoxelize(const DecimatedModel& model, const VolumeFrame& frame,
                                    const VoxelizeBenchSettings& settings, const DentsimVoxelizer& dentsim);

// Every level of `levels` (a grid fitted to `bounds`, so a level has one voxel size for every
// share) times every share of `percents` [%] of the layers' triangles. `log` gets one line per row.
// Errors are measureVoxelize's and the grid's.
Result<std::vector<VoxelizeRow>> runVoxelizeBench(const std::vector<MeshLayer>& layers, const Bounds3& bounds,
                                                  const std::vector<int>& levels, const std::vector<double>& percents,
                                                  const VoxelizeBenchSettings& settings, const DentsimVoxelizer& dentsim,
                                                  const std::function<void(const std::string&)>& log = {});

// Median of a non-empty list (the mean of the middle two for an even count).
double median(std::vector<double> values);

// ---- 3. the report -----------------------------------------------------------------------------

// Where and how the rows were measured, printed above the table and stored in the JSON.
struct VoxelizeReportInfo {
  std::string model;          // "built-in four-layer molar"
  std::string command;        // the command line
  std::string cpu;            // CPU model
  int cpu_threads = 0;        // hardware threads of the machine
  std::string device;         // Vulkan device and driver that ran dentsim
  int subsamples = 0;         // VoxelizeOptions::subsamples
  VoxelizeBenchSettings settings;
};

nlohmann::json voxelizeReportJson(const VoxelizeReportInfo& info, const std::vector<VoxelizeRow>& rows);
std::string voxelizeReportMarkdown(const VoxelizeReportInfo& info, const std::vector<VoxelizeRow>& rows);
std::string voxelizeRowsSvg(const std::vector<VoxelizeRow>& rows);
// Writes voxelize.json, voxelize.md and voxelize.svg into `dir`, each atomically. Errors name the file.
Status writeVoxelizeReport(const std::string& dir, const VoxelizeReportInfo& info, const std::vector<VoxelizeRow>& rows);

}  // namespace dentsim::bench
