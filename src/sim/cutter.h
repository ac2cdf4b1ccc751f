// Cutter: removes tissue under a bur's cutting head at the rate hardness x cutting ability x turbine speed x time.
//
// The voxels under the head are those within `reach` of a cutting point in contact, or of the
// segment from that point out to the tissue surface. The contacts take turns: each step takes the
// voxels of the next contacts in the list, from where the last step stopped, until those voxels
// hold twice the fill its demand needs at the hardest tissue among them. The step removes
//   demand = removal_rate * ability * speed * dt          [mm^3 at hardness 1]
// spread over those voxels in proportion to each one's fill times its tissue's hardness, so that
//   removed = demand * (fill-weighted mean hardness of the voxels taken),
// and no voxel loses more than half its fill in one step. The turn sweeps the whole contact in a
// few tens of steps; a step touches a few dozen voxels in enamel, not every voxel under the head.
// With one tissue that is exactly removal_rate * hardness * ability * speed * dt, however many
// voxels the head touches; in mixed contact the softer tissue goes faster. A voxel's fill is 5
// bits, so the fractional part of each voxel's share is rounded up or down at random, with a hash
// of the voxel and the step as the dice: unbiased, allocation-free and the same on every replay.
//
// Every changed voxel is written to the volume at once and pushed to the EditChannel. A step that
// could overflow the channel or the volume's reserved bricks is not cut at all (counted as
// deferred), so the two copies of the voxels never disagree.
#pragma once

#include <array>

#include <cstdint>
#include <span>
#include <vector>

#include "core/volume_frame.h"
#include "sim/contact.h"
#include "sim/edit_channel.h"
#include "sim/sim_params.h"
#include "sim/voxel_field.h"
#include "volume/brick_volume.h"

namespace dentsim {

struct CutStep {
  uint32_t candidates = 0;        // tissue voxels under the head
  uint32_t voxels_changed = 0;    // voxels whose byte changed (edits pushed)
  double demand_mm3 = 0.0;        // removal_rate * ability * speed * dt [mm^3]
  double expected_mm3 = 0.0;      // demand * mean hardness: what the step should remove [mm^3]
  double removed_mm3 = 0.0;       // what it did remove, from the fill change [mm^3]
  // The same by tissue, indexed by Material (Empty unused): what the sound engine colours the cut by.
  std::array<double, DS_MATERIAL_COUNT> removed_by_material_mm3{};
  bool deferred = false;          // not cut: no room in the channel or the volume's reserve

  // Sums another step's cut into this one (a haptic step that ran several queued cut jobs).
  CutStep& operator+=(const CutStep& o) {
    candidates += o.candidates;
    voxels_changed += o.voxels_changed;
    demand_mm3 += o.demand_mm3;
    expected_mm3 += o.expected_mm3;
    removed_mm3 += o.removed_mm3;
    for (size_t m = 0; m < removed_by_material_mm3.size(); ++m) removed_by_material_mm3[m] += o.removed_by_material_mm3[m];
    deferred = deferred || o.deferred;
    return *this;
  }
};

class Cutter {
 public:
  // Preallocates for up to max_candidates voxels a step; cut() never allocates. A step takes at most
  // max_voxels_per_step voxels: a bounded time however deep the head is buried.
  explicit Cutter(size_t max_candidates = 1 << 16, size_t max_voxels_per_step = 2048);

  // One step of cutting by the contacts flagged `cutting`. speed in [0,1], dt [s]. edits may be null
  // (nothing mirrors this volume). `step` seeds the rounding. field must read `volume`; every voxel
  // written is passed on to it (VoxelField::written).
  CutStep cut(BrickVolume& volume, VoxelField& field, std::span<const ContactPoint> contacts, const SimParams& params,
              double ability, double speed, double dt, uint64_t step, EditChannel* edits);

 private:
  struct Candidate {
    uint32_t x, y, z;  // the voxel
    Voxel value;       // its byte before the cut
  };
  // The bitmap that keeps a step from taking a voxel twice covers a window of this many voxels a
  // side around the first contact taking its turn (256 KiB; a 1 mm head is 48 voxels at level 10).
  // Only the words a step set are cleared for the next.
  static constexpr uint64_t kMarkSide = 128;
  static constexpr uint64_t kMarkBits = kMarkSide * kMarkSide * kMarkSide;
  static constexpr size_t kMaxTouched = 16384;  // beyond this, the next step clears the whole bitmap

  // What gather() took: the candidates' fill, and their fill times hardness [fill units].
  struct Taken {
    double fill = 0, hard_fill = 0;
  };
  // Fills candidates_: the tissue voxels the contacts taking their turn this step reach, until their
  // fill reaches fill_needed [fill units at hardness 1] times the largest hardness among them.
  Taken gather(VoxelField& field, std::span<const ContactPoint> contacts, const SimParams& params, double fill_needed);
  void touch(size_t word);  // a word of the marks went from zero to non-zero
  void clearMarks();
  // Whether the volume's reserve holds every brick and index block the candidates could open.
  bool roomForBricks(const BrickVolume& volume);
  // Takes the step's removal from the candidates (their fill summing to fill_sum) and records it in out.
  CutStep remove(BrickVolume& volume, VoxelField& field, const SimParams& params, uint64_t step, EditChannel* edits,
                 double fill_sum, CutStep out);

  size_t max_voxels_;
  size_t turn_ = 0;                    // the contact (by its place in the list) whose turn is next
  std::vector<Candidate> candidates_;
  std::vector<uint64_t> marks_;        // (kMarkBits / 64) the voxels already taken this step
  std::vector<size_t> touched_;        // (kMaxTouched) words of marks_ set this step
  bool marks_overflow_ = false;        // touched_ was full: clear all of marks_
  std::vector<uint64_t> brick_keys_;   // distinct bricks a step touches (tile ones need reserve)
};

}  // namespace dentsim
