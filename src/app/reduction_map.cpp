// The crown preparation's reduction map: the margin height it reads above, the paint from the measured reduction, the picture, and the refresh's one-at-a-time rule.
#include "app/reduction_map.h"

#include <array>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>

#include "eval/score_image.h"
#include "volume/half_fill.h"
#include "volume/loose_fragments.h"
#include "volume/tissue_table.h"

#ifdef __linux__
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>
#endif

namespace dentsim::app {
namespace {

// Calls fn(x, y, z, brick offset, original brick, prepared brick) for every voxel of the bricks in
// `box`; the prepared view is read only when a prepared volume is given.
template <class Fn>
void forEachVoxel(const BrickBox& box, const BrickVolume& original, const BrickVolume* prepared, Fn fn) {
  if (box.empty()) return;
  for (uint32_t bz = box.lo.z; bz <= box.hi.z; ++bz)
    for (uint32_t by = box.lo.y; by <= box.hi.y; ++by)
      for (uint32_t bx = box.lo.x; bx <= box.hi.x; ++bx) {
        const BrickCoord c{bx, by, bz};
        const BrickView o = original.brick(c);
        const BrickView p = prepared ? prepared->brick(c) : BrickView{};
        for (uint32_t z = 0; z < DS_BRICK_DIM; ++z)
          for (uint32_t y = 0; y < DS_BRICK_DIM; ++y)
            for (uint32_t x = 0; x < DS_BRICK_DIM; ++x)
              fn(bx * DS_BRICK_DIM + x, by * DS_BRICK_DIM + y, bz * DS_BRICK_DIM + z, layout::brickCoordToOffset(x, y, z), o, p);
      }
}

// A voxel centre's height along the unit `axis` from the grid origin [mm].
double centreHeightMm(uint32_t x, uint32_t y, uint32_t z, const Vec3& axis, double voxel_mm) {
  return dot(Vec3(x + 0.5, y + 0.5, z + 0.5), axis) * voxel_mm;
}

// The lowest centre height of an original tooth voxel the preparation has taken [mm]; none before the first cut.
std::optional<double> lowestCutMm(const ToothVolume& original, const ToothVolume& prepared, const Vec3& axis) {
  double lowest = std::numeric_limits<double>::infinity();
  forEachVoxel(tissueBricks(original.voxels), original.voxels, &prepared.voxels,
               [&](uint32_t x, uint32_t y, uint32_t z, uint32_t n, const BrickView& o, const BrickView& p) {
                 if (isToothTissue(voxelMaterial(o.at(n))) && !isToothTissue(voxelMaterial(p.at(n))))
                   lowest = std::min(lowest, centreHeightMm(x, y, z, axis, original.frame.voxel_mm));
               });
  if (!std::isfinite(lowest)) return std::nullopt;
  return lowest;
}

// A copy of the tooth without its neighbours (the map is about the prepared tooth alone, and the
// picture then fits it), and with `half_full` without its voxels under half full either, so that the
// map's own readings (the lowest cut, the paint's spread) see the surfaces the picture shows.
ToothVolume toothAlone(const ToothVolume& tooth, bool half_full) {
  ToothVolume out = tooth;
  const BrickBox box = tissueBricks(tooth.voxels);
  if (box.empty()) return out;
  auto thin = [half_full](Voxel v) {
    const Material m = voxelMaterial(v);
    return m == Material::Neighbour || (half_full && isToothTissue(m) && !isHalfFull(v));
  };
  std::array<Voxel, DS_BRICK_VOXELS> voxels;
  for (uint32_t bz = box.lo.z; bz <= box.hi.z; ++bz)
    for (uint32_t by = box.lo.y; by <= box.hi.y; ++by)
      for (uint32_t bx = box.lo.x; bx <= box.hi.x; ++bx) {
        const BrickCoord c{bx, by, bz};
        const BrickView b = tooth.voxels.brick(c);
        if (b.uniform) {
          if (thin(b.value)) out.voxels.setBrickUniform(c, makeVoxel(Material::Empty));
          continue;
        }
        bool any = false;
        for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
          voxels[n] = thin(b.voxels[n]) ? makeVoxel(Material::Empty) : b.voxels[n];
          any = any || voxels[n] != b.voxels[n];
        }
        if (any) out.voxels.setBrick(c, voxels.data());
      }
  return out;
}

// The worker gives way to the frame loop: a map a little late costs nothing, a late frame shows.
void yieldToTheFrameLoop() {
#ifdef __linux__
  // Linux keeps a nice value per thread: this lowers the worker alone (the haptic thread runs
  // real-time where it may, above both).
  (void)setpriority(PRIO_PROCESS, static_cast<id_t>(syscall(SYS_gettid)), 10);
#endif
}

std::string percent(double share) { return std::to_string(int(std::lround(share * 100.0))) + "%"; }

// A band's bound as a teacher writes it: 1.5, 2.0, 0.25 (two decimals at most, one at least).
std::string mm(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", v);
  std::string s = text;
  if (s.size() > 1 && s.back() == '0' && s[s.size() - 2] != '.') s.pop_back();
  return s;
}

}  // namespace

// ---- 1. one map ------------------------------------------------------------------------------------------

std::optional<double> cejHeightMm(const ToothVolume& original, const Vec3& axis) {
  const Vec3 unit = normalized(axis);
  double lowest = std::numeric_limits<double>::infinity();
  forEachVoxel(tissueBricks(original.voxels), original.voxels, nullptr,
               [&](uint32_t x, uint32_t y, uint32_t z, uint32_t n, const BrickView& o, const BrickView&) {
                 if (voxelMaterial(o.at(n)) == Material::Enamel)
                   lowest = std::min(lowest, centreHeightMm(x, y, z, unit, original.frame.voxel_mm));
               });
  if (!std::isfinite(lowest)) return std::nullopt;
  return lowest;
}

std::optional<double> reductionMapMarginMm(const CrownTask& crown, const Vec3& insertion_axis,
                                           const ToothVolume& original, const ToothVolume& prepared) {
  if (auto cej = cejHeightMm(original, insertion_axis)) return *cej + crown.margin_above_cej_hi_mm;
  // No enamel: from the lowest cut on, half a voxel down so that the samples level with it count.
  auto cut = lowestCutMm(original, prepared, normalized(insertion_axis));
  if (!cut) return std::nullopt;
  return *cut - 0.5 * original.frame.voxel_mm;
}

Result<ReductionMap> drawReductionMap(const Task& task, const ToothVolume& original, const ToothVolume& prepared) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::string where = "reduction map";
  if (task.kind != TaskKind::Crown) return makeError(where, "the task is not a crown preparation");
  const ToothVolume solid_original = toothAlone(original, true);
  ToothVolume solid_prepared = toothAlone(prepared, true);
  dropLooseFragments(solid_prepared.voxels);  // a sliver the bur cut free is not the wall (volume/loose_fragments.h)
  const auto margin = reductionMapMarginMm(task.crown, task.insertion_axis, solid_original, solid_prepared);
  if (!margin) return makeError(where, "the tooth has no enamel to find the CEJ by, and nothing is cut yet");
  const std::array<double, 3>& m = original.frame.tooth.mesial;
  auto reduction = measureReduction(solid_original.voxels, solid_prepared.voxels, original.frame.voxel_mm,
                                    task.insertion_axis, Vec3(m[0], m[1], m[2]), *margin, crownReductionBands(task.crown));
  if (!reduction) return reduction.error();
  const CutMarks paint = reductionPaint(*reduction, &solid_prepared.voxels);
  // Down the insertion axis at the occlusal table, then obliquely at the walls, fitted to the
  // prepared tooth alone (its neighbours left out).
  ScoreImageOptions options;
  options.oblique = true;
  options.view_dir = -normalized(task.insertion_axis);
  ReductionMap map;
  const ToothVolume shown_original = toothAlone(original, false), shown_prepared = toothAlone(prepared, false);
  map.picture = renderScoreImage(shown_original, shown_prepared, nullptr, nullptr, options, &paint).image;
  map.margin_mm = *margin;
  const CrownTask& c = task.crown;
  map.legend = "occlusal " + mm(c.occlusal_lo_mm) + "-" + mm(c.occlusal_hi_mm) + " mm, axial " + mm(c.axial_lo_mm) +
               "-" + mm(c.axial_hi_mm) + " mm";
  // The shares of the surface read, over every region.
  double samples = 0, under = 0, over = 0;
  auto count = [&](const ReductionStats& s) {
    samples += s.samples;
    under += s.under_share * s.samples;
    over += s.over_share * s.samples;
  };
  count(reduction->occlusal);
  for (const ReductionStats& s : reduction->axial) count(s);
  if (samples > 0)
    map.summary = percent((samples - under - over) / samples) + " within, " + percent(under / samples) + " under, " +
                  percent(over / samples) + " over";
  map.compute_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return map;
}

// ---- 2. refresh ------------------------------------------------------------------------------------------

void ReductionMapRefresh::start(Clock::time_point now, Job job) {
  assert(!running() && "one map at a time");
  stale_ = false;
  started_ = true;
  last_start_ = now;
  job_generation_ = generation_;
  future_ = std::async(std::launch::async, [run = std::move(job)] {
    yieldToTheFrameLoop();
    return run();
  });
}

std::optional<Result<ReductionMap>> ReductionMapRefresh::collect() {
  Result<ReductionMap> result = future_.get();  // leaves future_ invalid: nothing runs
  if (job_generation_ != generation_) return std::nullopt;
  return result;
}

std::optional<Result<ReductionMap>> ReductionMapRefresh::take() {
  if (!running() || future_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return std::nullopt;
  return collect();
}

std::optional<Result<ReductionMap>> ReductionMapRefresh::wait() {
  if (!running()) return std::nullopt;
  return collect();
}

}  // namespace dentsim::app
