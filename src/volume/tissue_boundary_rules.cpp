// The rules on a segmented tooth's output box that undo the scanner's blur at tissue boundaries: classes, partial volume, edges, open caries.
#include "volume/tissue_boundary_rules.h"

#include "volume/voxel_grid_ops.h"

#include <algorithm>
#include <utility>

namespace dentsim {

using namespace tooth_cell;

namespace {

// Sets bit `dst` on every cell within r cells (box distance) of a cell where pred(cell) holds,
// through kScratchA (dilated) and kScratchB (its ping-pong plane); both scratch bits end clear.
template <class Pred>
void dilateInto(std::vector<uint8_t>& cells, const std::array<int32_t, 3>& d, int r, uint8_t dst, Pred&& pred) {
  for (uint8_t& c : cells) c = uint8_t((c & ~(kScratchA | kScratchB)) | (pred(c) ? kScratchA : 0));
  dilateBit(cells, d, r, kScratchA, kScratchB);
  for (uint8_t& c : cells) c = uint8_t((c & ~kScratchA) | ((c & kScratchA) ? dst : 0));
}

}  // namespace

void markOutside(std::vector<uint8_t>& cells, const std::array<int32_t, 3>& d, std::deque<uint64_t>& queue) {
  for (uint8_t& c : cells) c = uint8_t(c & ~kOutside);
  floodFromBorder(
      d, queue,
      [&](uint64_t o) {
        if (classOf(cells[o]) != 0 || (cells[o] & kOutside)) return false;
        cells[o] |= kOutside;
        return true;
      },
      [](double) { return true; });
}

// Classes of the tooth's cells (marked kToothMark) by value, and each class's mean value; class 0's
// mean is over the empty cells below the hard threshold (cut-away hard tissue is in no mean).
ClassMeans classify(ToothBoxCells& box, const ToothThresholds& thr) {
  std::array<double, 4> sum{}, cnt{};
  const double dentin_floor = thr.dentinFloor();
  for (uint64_t o = 0; o < box.cells.size(); ++o) {
    const float v = box.value(o);
    uint8_t cls = 0;
    if (box.cells[o] == kToothMark)
      cls = v >= thr.enamel ? kEnamel : v >= dentin_floor ? kDentin : kCaries;
    else if (!(v < thr.hard))
      continue;
    box.cells[o] = cls;
    sum[cls] += double(v);
    cnt[cls] += 1;
  }
  ClassMeans means;
  const double fallback[4] = {thr.hard, thr.hard, dentin_floor, thr.enamel};
  for (size_t c = 0; c < 4; ++c) means.mean[c] = cnt[c] > 0 ? sum[c] / cnt[c] : fallback[c];
  return means;
}

// The partial-volume rule (docs/PATIENT_SCANS.md); decisions from the classes before any change, applied
// at once. Returns the voxels reassigned.
uint64_t applyPartialVolume(ToothBoxCells& box, int w, bool caries, const ClassMeans& means, std::deque<uint64_t>& queue) {
  std::vector<uint8_t>& cells = box.cells;
  // Only the outside counts as the darker class: enamel never faces the pulp, and noise specks
  // of enamel near the pulp wall must not pull dentin into enamel.
  markOutside(cells, box.d, queue);
  dilateInto(cells, box.d, w, kNearEmpty, [](uint8_t c) { return (c & kOutside) != 0; });
  dilateInto(cells, box.d, w, kNearEnamel, [](uint8_t c) { return classOf(c) == kEnamel; });
  if (caries) dilateInto(cells, box.d, w, kNearHard, [](uint8_t c) { return classOf(c) >= kDentin; });
  std::vector<std::pair<uint64_t, uint8_t>> changes;
  for (uint64_t o = 0; o < cells.size(); ++o) {
    const uint8_t c = cells[o], cls = classOf(c);
    if (!(c & kNearEmpty)) continue;
    uint8_t bright = 0;
    if (cls == kDentin && (c & kNearEnamel)) bright = kEnamel;
    if (cls == kCaries && (c & kNearHard)) bright = (c & kNearEnamel) ? kEnamel : kDentin;
    if (bright == 0) continue;
    changes.emplace_back(o, double(box.value(o)) > means.midpoint(0, bright) ? bright : uint8_t(0));
  }
  for (const auto& [o, cls] : changes) cells[o] = uint8_t((cells[o] & ~kClassMask) | cls);
  for (uint8_t& c : cells) c = classOf(c);
  return changes.size();
}

// Mean value of the empty space facing the tooth: [0] the outside, [1] enclosed space; `fallback`
// where there is none. Cut-away hard tissue (value >= hard) is in neither.
std::array<double, 2> darkMeans(const ToothBoxCells& box, double hard, double fallback) {
  double sum[2] = {0, 0}, cnt[2] = {0, 0};
  for (uint64_t o = 0; o < box.cells.size(); ++o) {
    if (classOf(box.cells[o]) != 0) continue;
    const float v = box.value(o);
    if (!(v < hard)) continue;  // cut-away hard tissue and non-finite values
    const int side = (box.cells[o] & kOutside) ? 0 : 1;
    sum[side] += double(v);
    cnt[side] += 1;
  }
  std::array<double, 2> out{fallback, fallback};
  for (size_t side = 0; side < 2; ++side)
    if (cnt[side] > 0) out[side] = sum[side] / cnt[side];
  return out;
}

// Edges: a tooth voxel facing empty space is kept when its value is at least half-way from the
// mean of that space to its class's mean, peeled up to `layers` times. One global cut is half-way
// between air and dentin, which leaves a rim of dentin in the pulp, whose soft tissue is far
// brighter than air. Needs kOutside marked; returns the voxels emptied.
uint64_t applyEdgeRule(ToothBoxCells& box, int layers, const std::array<double, 2>& dark, const ClassMeans& means) {
  std::vector<uint8_t>& cells = box.cells;
  uint64_t emptied = 0;
  for (int pass = 0; pass < layers; ++pass) {
    std::vector<std::pair<uint64_t, uint8_t>> changes;
    for (uint64_t o = 0; o < cells.size(); ++o) {
      const uint8_t cls = classOf(cells[o]);
      if (cls == 0) continue;
      bool faces_out = false, faces_in = false;
      forEachFaceNeighbour(o, box.d, [&](uint64_t j) {
        if (classOf(cells[j]) != 0) return;
        if (cells[j] & kOutside) faces_out = true;
        else faces_in = true;
      });
      if (!faces_out && !faces_in) continue;
      if (double(box.value(o)) < 0.5 * (dark[faces_in ? 1 : 0] + means.mean[cls]))
        changes.emplace_back(o, faces_out ? kOutside : uint8_t(0));
    }
    if (changes.empty()) break;
    for (const auto& [o, mark] : changes) cells[o] = mark;
    emptied += changes.size();
  }
  return emptied;
}

// Caries: 6-connected pieces of caries within w of the outside (open to the surface) and holding a
// voxel whose six neighbours are all caries (thicker than an edge rim) stay; the rest become dentin
// above the midpoint of the dentin mean and the mean of the space they lie by, else empty. Needs
// kOutside marked; returns the caries voxels rejected.
uint64_t keepOpenCaries(ToothBoxCells& box, int w, const std::array<double, 2>& dark, const ClassMeans& means,
                        std::deque<uint64_t>& queue) {
  std::vector<uint8_t>& cells = box.cells;
  dilateInto(cells, box.d, w, kNearEmpty, [](uint8_t c) { return (c & kOutside) != 0; });
  uint64_t rejected = 0;
  std::vector<uint64_t> piece;
  for (uint64_t s = 0; s < cells.size(); ++s) {
    if (classOf(cells[s]) != kCaries || (cells[s] & kScratchA)) continue;
    piece.clear();
    bool open = false, thick = false;
    cells[s] |= kScratchA;
    queue.push_back(s);
    while (!queue.empty()) {
      const uint64_t o = queue.front();
      queue.pop_front();
      piece.push_back(o);
      open = open || (cells[o] & kNearEmpty);
      int caries_faces = 0;
      forEachFaceNeighbour(o, box.d, [&](uint64_t j) {
        if (classOf(cells[j]) != kCaries) return;
        ++caries_faces;
        if (!(cells[j] & kScratchA)) {
          cells[j] |= kScratchA;
          queue.push_back(j);
        }
      });
      thick = thick || caries_faces == 6;
    }
    if (open && thick) continue;
    const double split = 0.5 * (dark[open ? 0 : 1] + means.mean[kDentin]);
    for (uint64_t o : piece) {
      const uint8_t cls = double(box.value(o)) > split ? kDentin : 0;
      cells[o] = uint8_t((cells[o] & ~kClassMask) | cls);
    }
    rejected += piece.size();
  }
  for (uint8_t& c : cells) c = classOf(c);
  return rejected;
}

}  // namespace dentsim
