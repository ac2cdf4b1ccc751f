// Probing a tooth from above: the tissue's box, the surface's height in a column, and where a round bur comes to rest.
#include "sim/surface_probe.h"

#include <numbers>

namespace dentsim {

TissueBox tissueBox(const BrickVolume& volume, const VolumeFrame& frame) { return brickBoxMm(tissueBricks(volume), frame); }

TissueBox brickBoxMm(const BrickBox& b, const VolumeFrame& frame) {
  TissueBox box;
  if (b.empty()) return box;
  const double brick_mm = frame.voxel_mm * DS_BRICK_DIM;
  const uint32_t lo[3] = {b.lo.x, b.lo.y, b.lo.z}, hi[3] = {b.hi.x, b.hi.y, b.hi.z};
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = frame.origin_mm[size_t(a)] + double(lo[a]) * brick_mm;
    box.hi[a] = frame.origin_mm[size_t(a)] + double(hi[a] + 1) * brick_mm;
  }
  return box;
}

SurfaceProbe::SurfaceProbe(const BrickVolume& volume, const VolumeFrame& frame, const TissueBox& box)
    : field_(volume, frame), top_mm_(box.hi.z + frame.voxel_mm), bottom_mm_(box.lo.z - frame.voxel_mm) {}

std::optional<double> SurfaceProbe::surface(double x, double y) {
  const double step = field_.voxelMm();
  auto inside = [&](double z) { return field_.sample(field_.toVoxel({x, y, z})).phi > 0; };
  if (inside(top_mm_)) return top_mm_;
  const auto steps = int64_t(std::ceil((top_mm_ - bottom_mm_) / step));
  for (int64_t i = 1; i <= steps; ++i) {
    double below = top_mm_ - double(i) * step;
    if (!inside(below)) continue;
    double above = below + step;
    for (int k = 0; k < 12; ++k) {  // to 1/4096 voxel
      const double mid = 0.5 * (above + below);
      (inside(mid) ? below : above) = mid;
    }
    return 0.5 * (above + below);
  }
  return std::nullopt;
}

std::optional<double> SurfaceProbe::restingTip(double x, double y, double r) {
  constexpr double kRings[] = {0.0, 0.35, 0.7, 0.95};  // ring radius / r
  constexpr int kSpokes = 12;
  std::optional<double> best;
  for (double ring : kRings) {
    const double rho = ring * r;
    const int spokes = ring == 0.0 ? 1 : kSpokes;
    const double sag = r - std::sqrt(r * r - rho * rho);
    for (int k = 0; k < spokes; ++k) {
      const double angle = 2.0 * std::numbers::pi * double(k) / kSpokes;
      const std::optional<double> h = surface(x + rho * std::cos(angle), y + rho * std::sin(angle));
      if (h && (!best || *h - sag > *best)) best = *h - sag;
    }
  }
  return best;
}

std::optional<Vec3> lowestRestingTip(SurfaceProbe& probe, double x, double y, double r, double search_mm, double grid_mm) {
  const auto n = int(std::floor(search_mm / grid_mm));
  std::optional<Vec3> best;
  for (int j = -n; j <= n; ++j)
    for (int i = -n; i <= n; ++i) {
      if (i * i + j * j > n * n) continue;
      const double px = x + grid_mm * i, py = y + grid_mm * j;
      const std::optional<double> z = probe.restingTip(px, py, r);
      if (z && (!best || *z < best->z)) best = Vec3{px, py, *z};
    }
  return best;
}

std::optional<double> restingTipHeight(const BrickVolume& volume, const VolumeFrame& frame, double x_mm, double y_mm,
                                       double radius_mm) {
  const TissueBox box = tissueBox(volume, frame);
  if (box.empty()) return std::nullopt;
  SurfaceProbe probe(volume, frame, box);
  return probe.restingTip(x_mm, y_mm, radius_mm);
}

}  // namespace dentsim
