// Peer libraries measured beside dentsim in the same run; each is compiled in only when installed.
#pragma once

#include <cstdint>
#include <string>

#include "volume/brick_volume.h"

namespace dentsim::bench {

// Memory of an OpenVDB tree holding the same voxels' labels (uint8, 5-4-3 tree, pruned to tiles).
struct PeerMemory {
  bool available = false;   // false when dentsim was built without OpenVDB
  std::string name;         // "OpenVDB 10.0.1 uint8 label tree"
  uint64_t bytes = 0;       // Tree::memUsage() [B]
  uint64_t leaf_nodes = 0;  // leaves after pruning
  double build_s = 0.0;     // time to fill and prune [s]
};

PeerMemory openvdbLabelTreeMemory(const BrickVolume& volume);

}  // namespace dentsim::bench
