// Standing a tooth crown up: the nearest quarter turn, the voxel permutation that applies it, the tissue boxes and the occlusal centre.
#include "volume/tooth_frame.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "volume/crown_estimate.h"
#include "volume/tissue_table.h"

namespace dentsim {
namespace {

bool isTissue(Voxel v) { return voxelMaterial(v) != Material::Empty && voxelFill(v) > 0; }
// The treated tooth's own tissue: its frame is measured on it, not on a neighbour beside it.
bool isToothVoxel(Voxel v) { return isToothTissue(voxelMaterial(v)) && voxelFill(v) > 0; }

// The source axis that simulation axis r takes, and its sign.
struct TurnRow {
  int from = 0;
  int sign = 1;
};
std::array<TurnRow, 3> rowsOf(const QuarterTurn& t) {
  std::array<TurnRow, 3> rows{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (t[3 * r + c] != 0) rows[r] = {c, t[3 * r + c]};
  return rows;
}

QuarterTurn compose(const QuarterTurn& a, const QuarterTurn& b) {  // a after b
  QuarterTurn m{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      int s = 0;
      for (int k = 0; k < 3; ++k) s += a[3 * r + k] * b[3 * k + c];
      m[3 * r + c] = int8_t(s);
    }
  return m;
}

// Every signed permutation with determinant +1: the 24 rotations of the cube.
std::vector<QuarterTurn> allQuarterTurns() {
  std::vector<QuarterTurn> out;
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& p : perms)
    for (int signs = 0; signs < 8; ++signs) {
      QuarterTurn t{};
      for (int r = 0; r < 3; ++r) t[3 * r + p[r]] = int8_t((signs >> r) & 1 ? -1 : 1);
      const int det = t[0] * (t[4] * t[8] - t[5] * t[7]) - t[1] * (t[3] * t[8] - t[5] * t[6]) + t[2] * (t[3] * t[7] - t[4] * t[6]);
      if (det == 1) out.push_back(t);
    }
  return out;
}

Vec3 toVec(const std::array<double, 3>& a) { return {a[0], a[1], a[2]}; }
std::array<double, 3> toArray(const Vec3& v) { return {v.x, v.y, v.z}; }

// `v` with its part along the unit `axis` taken out, normalized; none when little is left.
std::optional<Vec3> perpendicular(const Vec3& v, const Vec3& axis) {
  const Vec3 p = v - axis * dot(v, axis);
  if (!(norm(p) > 1e-6)) return std::nullopt;
  return normalized(p);
}

Result<Vec3> givenAxis(const Vec3& v, const char* what) {
  if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) || !(norm(v) > 1e-9))
    return makeError(what, "the axis needs three finite numbers, not all zero");
  return normalized(v);
}

}  // namespace

Vec3 turned(const QuarterTurn& t, const Vec3& v) {
  Vec3 out;
  for (int r = 0; r < 3; ++r) out[r] = t[3 * r] * v.x + t[3 * r + 1] * v.y + t[3 * r + 2] * v.z;
  return out;
}

QuarterTurn inverseTurn(const QuarterTurn& t) {
  return {t[0], t[3], t[6], t[1], t[4], t[7], t[2], t[5], t[8]};
}

Vec3 sourcePointMm(const VolumeFrame& f, const Vec3& p) {
  if (!f.tooth.turned()) return p;
  const double half = 0.5 * double(f.dim()) * f.voxel_mm;
  const Vec3 centre{f.origin_mm[0] + half, f.origin_mm[1] + half, f.origin_mm[2] + half};
  return turned(inverseTurn(f.tooth.turn), p - centre) + centre;
}

Vec3 sourceDirection(const VolumeFrame& f, const Vec3& d) { return turned(inverseTurn(f.tooth.turn), d); }

QuarterTurn nearestQuarterTurn(const Vec3& crown, const std::optional<Vec3>& mesial) {
  QuarterTurn best = kNoTurn;
  double best_crown = -2.0, best_next = -1e9;
  for (const QuarterTurn& t : allQuarterTurns()) {
    const double up = turned(t, crown).z;
    // Second choice: mesial toward -x, or the smallest turn (the largest trace).
    const double next = mesial ? -turned(t, *mesial).x : double(t[0] + t[4] + t[8]);
    if (up > best_crown + 1e-9 || (std::abs(up - best_crown) <= 1e-9 && next > best_next)) {
      best = t;
      best_crown = up;
      best_next = next;
    }
  }
  return best;
}

void turnTooth(ToothVolume& tooth, const QuarterTurn& turn) {
  if (turn == kNoTurn) return;
  const BrickVolume& from = tooth.voxels;
  const auto rows = rowsOf(turn);
  const uint32_t bricks = from.brickDim();
  BrickVolume to(from.level());
  std::array<Voxel, DS_BRICK_VOXELS> moved{};
  from.forEachBrick([&](const BrickView& b) {
    if (b.uniform && voxelMaterial(b.value) == Material::Empty && voxelFill(b.value) == 0) return;
    const uint32_t src[3] = {b.coord.x, b.coord.y, b.coord.z};
    uint32_t dst[3];
    for (int r = 0; r < 3; ++r) dst[r] = rows[r].sign > 0 ? src[rows[r].from] : bricks - 1 - src[rows[r].from];
    const BrickCoord c{dst[0], dst[1], dst[2]};
    if (b.uniform) {
      to.setBrickUniform(c, b.value);
      return;
    }
    for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
      const uint32_t l[3] = {n & 7u, (n >> 3) & 7u, n >> 6};
      uint32_t m[3];
      for (int r = 0; r < 3; ++r) m[r] = rows[r].sign > 0 ? l[rows[r].from] : 7u - l[rows[r].from];
      moved[m[0] + 8u * m[1] + 64u * m[2]] = b.voxels[n];
    }
    to.setBrick(c, moved.data());
  });
  tooth.voxels = std::move(to);

  VolumeFrame& f = tooth.frame;
  const int64_t dim = f.dim();
  // Voxel index: new[r] = sign * (old[from] - centre) + centre, centre = (dim - 1) / 2 on each axis.
  // The scanner matrix takes old indices; old[from_r] = sign_r * (new[r] - centre) + centre.
  std::array<double, 12> s = f.scanner_from_grid;
  const double centre = 0.5 * double(dim - 1);
  for (int row = 0; row < 3; ++row) {
    double shift = s[4 * row + 3];
    std::array<double, 3> lin{};
    for (int r = 0; r < 3; ++r) {
      const double a = s[4 * row + rows[r].from];
      lin[r] = a * rows[r].sign;
      shift += a * (centre - rows[r].sign * centre);
    }
    for (int r = 0; r < 3; ++r) f.scanner_from_grid[4 * row + r] = lin[r];
    f.scanner_from_grid[4 * row + 3] = shift;
  }
  if (f.hasSource()) {
    const auto offset = f.source_offset, dims = f.source_dims;
    for (int r = 0; r < 3; ++r) {
      const int c = rows[r].from;
      f.source_dims[r] = dims[c];
      f.source_offset[r] = rows[r].sign > 0 ? offset[c] : int32_t(dim - (int64_t(offset[c]) + dims[c]));
    }
  }
  ToothAxes& t = f.tooth;
  t.crown = toArray(turned(turn, toVec(t.crown)));
  t.mesial = toArray(turned(turn, toVec(t.mesial)));
  t.buccal = toArray(turned(turn, toVec(t.buccal)));
  if (t.has_occlusal_centre) {
    const double side = double(dim) * f.voxel_mm;
    Vec3 c = toVec(t.occlusal_centre_mm) - Vec3{f.origin_mm[0], f.origin_mm[1], f.origin_mm[2]} - Vec3{1, 1, 1} * (0.5 * side);
    c = turned(turn, c) + Vec3{f.origin_mm[0], f.origin_mm[1], f.origin_mm[2]} + Vec3{1, 1, 1} * (0.5 * side);
    t.occlusal_centre_mm = toArray(c);
  }
  t.turn = compose(turn, t.turn);
}

std::array<VoxelBox, DS_MATERIAL_COUNT> tissueVoxelBoxes(const BrickVolume& volume) {
  std::array<VoxelBox, DS_MATERIAL_COUNT> boxes{};
  const auto grow = [&](size_t m, int64_t x0, int64_t y0, int64_t z0, int64_t x1, int64_t y1, int64_t z1) {
    for (size_t k : {size_t{0}, m}) {
      if (k == 0 && !isToothTissue(Material(m))) continue;  // a neighbour has its own box, not the tooth's
      VoxelBox& b = boxes[k];
      b.lo = {std::min(b.lo[0], x0), std::min(b.lo[1], y0), std::min(b.lo[2], z0)};
      b.hi = {std::max(b.hi[0], x1), std::max(b.hi[1], y1), std::max(b.hi[2], z1)};
    }
  };
  volume.forEachBrick([&](const BrickView& b) {
    const int64_t x = int64_t(b.coord.x) * DS_BRICK_DIM, y = int64_t(b.coord.y) * DS_BRICK_DIM,
                  z = int64_t(b.coord.z) * DS_BRICK_DIM;
    if (b.uniform) {
      if (isTissue(b.value))
        grow(size_t(voxelMaterial(b.value)), x, y, z, x + DS_BRICK_DIM - 1, y + DS_BRICK_DIM - 1, z + DS_BRICK_DIM - 1);
      return;
    }
    for (uint32_t n = 0; n < DS_BRICK_VOXELS; ++n) {
      const Voxel v = b.voxels[n];
      if (!isTissue(v)) continue;
      const int64_t vx = x + (n & 7u), vy = y + ((n >> 3) & 7u), vz = z + (n >> 6);
      grow(size_t(voxelMaterial(v)), vx, vy, vz, vx, vy, vz);
    }
  });
  return boxes;
}

BrickBox toothBricks(const BrickVolume& volume) {
  BrickBox box;
  volume.forEachBrick([&](const BrickView& b) {
    if (b.uniform && voxelFill(b.value) == 0) return;
    bool neighbour = false, tooth = false;
    for (uint32_t n = 0; n < (b.uniform ? 1u : DS_BRICK_VOXELS) && !tooth; ++n) {
      const Voxel v = b.at(n);
      if (voxelFill(v) == 0) continue;
      if (voxelMaterial(v) == Material::Neighbour) neighbour = true;
      else tooth = true;
    }
    if (neighbour && !tooth) return;
    box.lo = {std::min(box.lo.x, b.coord.x), std::min(box.lo.y, b.coord.y), std::min(box.lo.z, b.coord.z)};
    box.hi = {std::max(box.hi.x, b.coord.x), std::max(box.hi.y, b.coord.y), std::max(box.hi.z, b.coord.z)};
  });
  return box;
}

std::optional<Vec3> occlusalCentreMm(const ToothVolume& tooth) {
  const VoxelBox box = tissueVoxelBoxes(tooth.voxels)[0];
  if (box.empty()) return std::nullopt;
  const int64_t cx = (box.lo[0] + box.hi[0]) / 2, cy = (box.lo[1] + box.hi[1]) / 2;
  int64_t top = box.hi[2];
  for (int64_t z = box.hi[2]; z >= box.lo[2]; --z)
    if (isToothVoxel(tooth.voxels.voxel(uint32_t(cx), uint32_t(cy), uint32_t(z)))) {
      top = z;
      break;
    }
  const VolumeFrame& f = tooth.frame;
  return Vec3{f.origin_mm[0] + (double(cx) + 0.5) * f.voxel_mm, f.origin_mm[1] + (double(cy) + 0.5) * f.voxel_mm,
              f.origin_mm[2] + double(top + 1) * f.voxel_mm};
}

Status standToothUp(ToothVolume& tooth, const ToothAxesHint& hint) {
  Vec3 crown{0, 0, 1};
  AxisSource crown_source = AxisSource::Assumed;
  if (hint.crown) {
    auto c = givenAxis(*hint.crown, "--crown-axis");
    if (!c) return c.error();
    crown = *c;
    crown_source = AxisSource::Given;
  } else if (const CrownEstimate e = estimateCrown(tooth.voxels); e.from_enamel) {
    crown = e.axis;
    crown_source = AxisSource::Found;
  }
  std::optional<Vec3> mesial, buccal;
  if (hint.mesial) {
    auto m = givenAxis(*hint.mesial, "--mesial-axis");
    if (!m) return m.error();
    mesial = perpendicular(*m, crown);
    if (!mesial) return makeError("--mesial-axis", "lies along the crown axis");
  }
  if (hint.buccal) {
    auto b = givenAxis(*hint.buccal, "--buccal-axis");
    if (!b) return b.error();
    buccal = perpendicular(*b, crown);
    if (buccal && mesial) buccal = perpendicular(*buccal, *mesial);
    if (!buccal) return makeError("--buccal-axis", "lies along the crown axis or the mesial axis");
  }
  const QuarterTurn turn = hint.turn ? nearestQuarterTurn(crown, mesial) : kNoTurn;
  turnTooth(tooth, turn);

  ToothAxes& t = tooth.frame.tooth;
  const Vec3 c = turned(turn, crown);
  // Unknown sides keep the convention, made perpendicular to the crown: mesial -x, buccal = crown x mesial.
  Vec3 m = mesial ? turned(turn, *mesial) : Vec3{};
  Vec3 b = buccal ? turned(turn, *buccal) : Vec3{};
  if (!mesial) m = buccal ? normalized(cross(b, c)) : perpendicular(Vec3{-1, 0, 0}, c).value_or(Vec3{0, 1, 0});
  if (!buccal) b = normalized(cross(c, m));
  t.crown = toArray(c);
  t.mesial = toArray(m);
  t.buccal = toArray(b);
  t.crown_source = crown_source;
  t.mesial_source = mesial ? AxisSource::Given : AxisSource::Assumed;
  t.buccal_source = buccal ? AxisSource::Given : AxisSource::Assumed;
  const std::optional<Vec3> centre = occlusalCentreMm(tooth);
  t.has_occlusal_centre = centre.has_value();
  if (centre) t.occlusal_centre_mm = toArray(*centre);
  return Ok{};
}

void setConventionalAxes(ToothVolume& tooth) {
  ToothAxes& t = tooth.frame.tooth;
  t = ToothAxes{};
  t.crown_source = t.mesial_source = t.buccal_source = AxisSource::Given;
  const std::optional<Vec3> centre = occlusalCentreMm(tooth);
  t.has_occlusal_centre = centre.has_value();
  if (centre) t.occlusal_centre_mm = toArray(*centre);
}

Vec3 toothOcclusalCentreMm(const ToothVolume& tooth) {
  const ToothAxes& t = tooth.frame.tooth;
  if (t.has_occlusal_centre) return toVec(t.occlusal_centre_mm);
  const VolumeFrame& f = tooth.frame;
  return occlusalCentreMm(tooth).value_or(Vec3{f.origin_mm[0], f.origin_mm[1], f.origin_mm[2]} +
                                          Vec3{1, 1, 1} * (0.5 * double(f.dim()) * f.voxel_mm));
}

}  // namespace dentsim
