// The brick-memory benchmark: our bytes and octree node counts beside the paper's Table 3 and an OpenVDB label tree.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/peers.h"
#include "core/interrupter.h"
#include "core/result.h"
#include "volume/brick_volume.h"
#include "volume/octree_stats.h"

namespace dentsim::bench {

struct MemoryRow {
  std::string tooth;        // data set name ("tooth_2")
  int level = 0;            // octree level L
  double voxel_mm = 0.0;    // voxel edge [mm]
  double build_s = 0.0;     // import time of this volume [s]
  BrickStats stats;         // our bricks and bytes
  OctreeCounts octree;      // the paper's node counts for the same voxels
  PeerMemory openvdb;       // the peer, same voxels
  double paper_mb = 0.0;    // the paper's Table 3 at this level [MB]; 0 when it gives none
};

// The paper's Table 3 (memory of its octree for a tooth) [MB]: levels 8, 9, 10.
double paperTable3Mb(int level);

MemoryRow measureMemory(const std::string& tooth, const ToothVolume& volume, double build_s);

// The CT teeth of the real tooth data, each fitted into each octree level.
struct CtMemorySettings {
  std::string data_dir;                                  // real tooth data (../shared/data)
  std::vector<std::string> teeth{"tooth_2", "tooth_3"};  // CT teeth in data_dir/ct
  std::vector<int> levels{8, 9, 10};                     // octree levels to fit each tooth into
};

// Imports data_dir/ct/<tooth>.nii.gz at each level (the data README's labels and pitch) and
// measures it; `progress` sees each import, `log` gets one line per row. Errors: a tooth that
// cannot be read or imported.
Result<std::vector<MemoryRow>> measureCtTeeth(const CtMemorySettings& settings, Interrupter& progress,
                                              const std::function<void(const std::string&)>& log = {});

nlohmann::json memoryRowsJson(const std::vector<MemoryRow>& rows);
std::string memoryRowsTable(const std::vector<MemoryRow>& rows);  // Markdown
std::string memoryRowsSvg(const std::vector<MemoryRow>& rows);
// Writes memory.json, memory.md and memory.svg into `dir`, each atomically. Errors name the file.
Status writeMemoryReport(const std::string& dir, const std::vector<MemoryRow>& rows);

}  // namespace dentsim::bench
