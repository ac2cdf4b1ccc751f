// Which way a tooth's crown faces, estimated from its tissues: from the centroid of the whole tooth toward the centroid of its enamel.
//
// Enamel covers the crown and nothing else, so its centroid lies crownward of the tooth's, whose
// roots pull it the other way. Scoring uses the estimate to flag an exercise that cannot be right
// (an ideal cavity on the roots, a bur axis pointing at the roots); a tooth without enamel (a
// one-layer STL) or with the enamel centred on the tooth keeps today's convention, crown up (+z).
#pragma once

#include "core/rigid.h"
#include "volume/brick_volume.h"

namespace dentsim {

struct CrownEstimate {
  Vec3 axis{0, 0, 1};        // unit, grid axes: from the roots toward the crown
  bool from_enamel = false;  // false: no usable enamel, +z assumed
  double lo = 0.0;           // the tissue's extent along the axis: min and max of dot(p, axis) over
  double hi = 0.0;           //   the corners of bricks holding the tooth's tissue [voxels]
  // The crown half is where dot(p, axis) >= middle() (p a voxel centre [voxels]).
  double middle() const { return 0.5 * (lo + hi); }
};

// The estimate for `volume`. The enamel counts when its centroid lies at least one voxel from the
// tooth's (fill-weighted, every tissue of the tooth). Neighbour voxels (an adjacent tooth) count for
// nothing: the centroids and the extent are the treated tooth's.
CrownEstimate estimateCrown(const BrickVolume& volume);

}  // namespace dentsim
