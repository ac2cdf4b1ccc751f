// The brick-memory benchmark: our bytes and octree node counts beside the paper's Table 3 and an OpenVDB label tree.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/peers.h"
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

nlohmann::json memoryRowsJson(const std::vector<MemoryRow>& rows);
std::string memoryRowsTable(const std::vector<MemoryRow>& rows);  // Markdown
std::string memoryRowsSvg(const std::vector<MemoryRow>& rows);

}  // namespace dentsim::bench
