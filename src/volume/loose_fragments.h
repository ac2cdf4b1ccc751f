// Pieces of tooth cut free of the tooth: found as 6-connected pieces of solid tooth (half fill) apart from the largest, and cleared.
//
// A bur that passes inside a thin wall it cannot reach (a proximal wall's enamel at a contact, where
// the bur must keep clear of the neighbour) leaves the wall's outer shell standing, joined to
// nothing. In the mouth such a sliver falls away or is flicked off with a hand instrument; a
// measure that reads it as tooth sees the wall unprepared and an undercut beneath it. The tooth is
// the largest piece (the one with its root); every other piece of solid tooth is loose.
#pragma once

#include <cstdint>

#include "volume/brick_volume.h"

namespace dentsim {

struct LooseFragments {
  uint64_t pieces = 0;   // loose pieces found
  uint64_t voxels = 0;   // their solid voxels, all cleared
  uint64_t largest = 0;  // voxels in the largest loose piece
};

// Clears every solid tooth voxel (volume/half_fill.h) that is not 6-connected to the largest piece
// of solid tooth, setting it empty; voxels below half fill, neighbours and empty space are left as
// they are. A volume with no tooth, or one piece, is unchanged.
LooseFragments dropLooseFragments(BrickVolume& volume);

}  // namespace dentsim
