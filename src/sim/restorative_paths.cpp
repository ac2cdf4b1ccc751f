// The restorative preparations: landmarks found in the volume, and the class II, class V and access outlines turned into pocket columns.
#include "sim/restorative_paths.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "sim/scripted_paths.h"

namespace dentsim {

// ---- 1. landmarks ------------------------------------------------------------------------------------------

std::optional<double> cejAlong(TissueRay& ray, const Vec3& start, const Vec3& dir, double z_from, double z_to,
                               double step_mm, double reach_mm) {
  std::optional<double> last_enamel;
  for (double z = z_from; z >= z_to; z -= step_mm) {
    const auto hit = ray.first(start + Vec3{0, 0, z}, dir, reach_mm);
    if (hit && hit->material == Material::Enamel) {
      last_enamel = z;
    } else if (last_enamel) {
      return *last_enamel - 0.5 * step_mm;
    }
  }
  return std::nullopt;
}

namespace {

// The columns of a grid of step g whose (u, v) satisfy `inside`, each with its floor, over the box
// |u| <= half_u, |v| <= half_v; the floor function returns nullopt to leave a column out.
template <typename Floor>
std::vector<PocketColumn> gridColumns(double g, double half_u, double half_v, const Floor& floor_at) {
  std::vector<PocketColumn> out;
  const auto nu = int64_t(std::floor(half_u / g + 1e-9)), nv = int64_t(std::floor(half_v / g + 1e-9));
  for (int64_t j = -nv; j <= nv; ++j)
    for (int64_t i = -nu; i <= nu; ++i) {
      const double u = double(i) * g, v = double(j) * g;
      if (const std::optional<double> f = floor_at(u, v)) out.push_back({u, v, *f});
    }
  return out;
}

// The treated tooth alone: `volume` with its neighbour voxels emptied, or none when it has none.
// Landmarks are the tooth's own: a ray from mesial must find the molar's surface and CEJ, not stop
// on the premolar in contact with it.
std::optional<BrickVolume> withoutNeighbours(const BrickVolume& volume) {
  std::optional<BrickVolume> alone;
  volume.forEachBrick([&](const BrickView& b) {
    if (b.uniform && voxelMaterial(b.value) != Material::Neighbour) return;
    std::array<Voxel, DS_BRICK_VOXELS> voxels;
    bool any = false;
    for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
      const bool neighbour = voxelMaterial(b.at(i)) == Material::Neighbour;
      voxels[i] = neighbour ? makeVoxel(Material::Empty) : b.at(i);
      any = any || neighbour;
    }
    if (!any) return;
    if (!alone) alone.emplace(volume);
    alone->setBrick(b.coord, voxels.data());
  });
  return alone;
}

// The most distal face [mm] of the neighbour voxels (Material::Neighbour, any fill) whose centres
// lie mesial of x_max, within half_y of y0 and between z_lo and z_hi; none when there are none.
std::optional<double> mesialNeighbourFace(const BrickVolume& volume, const VolumeFrame& frame, double x_max, double y0,
                                          double half_y, double z_lo, double z_hi) {
  const double v = frame.voxel_mm;
  std::optional<double> face;
  volume.forEachBrick([&](const BrickView& b) {
    if (b.uniform && (voxelMaterial(b.value) != Material::Neighbour || voxelFill(b.value) == 0)) return;
    for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
      const Voxel vox = b.at(i);
      if (voxelMaterial(vox) != Material::Neighbour || voxelFill(vox) == 0) continue;
      const double x = frame.origin_mm[0] + (b.coord.x * DS_BRICK_DIM + (i & 7u) + 0.5) * v;
      const double y = frame.origin_mm[1] + (b.coord.y * DS_BRICK_DIM + ((i >> 3) & 7u) + 0.5) * v;
      const double z = frame.origin_mm[2] + (b.coord.z * DS_BRICK_DIM + (i >> 6) + 0.5) * v;
      if (x >= x_max || std::abs(y - y0) > half_y || z < z_lo || z > z_hi) continue;
      face = std::max(face.value_or(-HUGE_VAL), x + 0.5 * v);
    }
  });
  return face;
}

}  // namespace

// ---- 2. class II mesio-occlusal ------------------------------------------------------------------------------

Result<Class2Path> class2CavityPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                                    const std::string& bur, const Class2Settings& s) {
  const std::string where = "class II path";
  if (!(s.isthmus_width_mm > 0) || !(s.occlusal_depth_mm > 0) || s.distal_reach_mm < 0 || !(s.box_width_mm > 0) ||
      !(s.box_depth_mm > 0) || s.gingival_above_cej_mm < 0 || !(s.widen >= 1) || !(s.fossa_grid_mm > 0) ||
      s.fossa_search_mm < 0 || !(s.neighbour_clearance_mm >= 0))
    return makeError(where, "widths, depths and grid must be > 0, reach, search, clearance and height above the CEJ >= 0, "
                            "widen >= 1");
  auto head = burHead(bur);
  if (!head) return makeError(where, head.message());
  const double r = head->radius_mm;
  if (!(s.isthmus_width_mm * s.widen > 2 * r) || !(s.box_width_mm * s.widen > 2 * r) || !(s.box_depth_mm * s.widen > r))
    return makeError(where, "the outline is narrower than the bur " + bur);
  // Landmarks on the tooth alone; the pocket is paced on the whole volume, neighbours and all.
  const std::optional<BrickVolume> alone = withoutNeighbours(volume);
  const BrickVolume& tooth = alone ? *alone : volume;
  const TissueBox box = toothBox(tooth, frame);
  if (box.empty()) return makeError(where, "the volume holds no tissue");
  SurfaceProbe probe(tooth, frame, box);
  TissueRay ray(tooth, frame);
  const Vec3 centre = box.centre();

  Class2Path out;
  const std::optional<Vec3> fossa = lowestRestingTip(probe, centre.x, centre.y, r, s.fossa_search_mm, s.fossa_grid_mm);
  if (!fossa) return makeError(where, "no tissue under the bur near the crown's centre");
  out.fossa_mm = *fossa;
  out.fossa_surface_z = probe.surface(fossa->x, fossa->y).value_or(fossa->z);
  out.occlusal_floor_z = out.fossa_surface_z - s.occlusal_depth_mm;

  // The mesial surface, seen from mesial along the fossa's y: where its enamel ends is the CEJ.
  const double step = 0.5 * frame.voxel_mm, reach = box.hi.x - box.lo.x + 2.0;
  const Vec3 mesial_start{box.lo.x - 1.0, fossa->y, 0.0}, toward_distal{1, 0, 0};
  const std::optional<double> cej = cejAlong(ray, mesial_start, toward_distal, out.fossa_surface_z, box.lo.z, step, reach);
  if (!cej) return makeError(where, "no enamel ending on the mesial surface: where is the CEJ?");
  out.mesial_cej_z = *cej;
  out.gingival_floor_z = *cej + s.gingival_above_cej_mm;
  if (!(out.gingival_floor_z < out.occlusal_floor_z))
    return makeError(where, "the gingival floor would lie above the occlusal floor");
  const auto at_floor = ray.first(mesial_start + Vec3{0, 0, out.gingival_floor_z}, toward_distal, reach);
  if (!at_floor) return makeError(where, "no mesial surface at the gingival floor's height");
  out.mesial_surface_x = at_floor->point.x;
  out.axial_wall_x = out.mesial_surface_x + s.box_depth_mm * s.widen;
  out.box_half_width_mm = 0.5 * s.box_width_mm * s.widen;

  // The most mesial tissue across the box, floor to fossa height: the box must open all of it.
  double outermost = out.mesial_surface_x;
  for (double z = out.gingival_floor_z; z <= out.fossa_surface_z + 2.0; z += step)
    for (double dy : {-out.box_half_width_mm, 0.0, out.box_half_width_mm})
      if (auto hit = ray.first(mesial_start + Vec3{0, dy, z}, toward_distal, reach)) outermost = std::min(outermost, hit->point.x);

  // Columns in a frame on the fossa's (x, y): the box's tips from outside that surface to the axial
  // wall less the bur; the occlusal part's from there to past the fossa.
  const double g = s.pocket.grid_mm;
  const double box_u0 = outermost - fossa->x;
  double box_u1 = out.axial_wall_x - r - fossa->x;
  const double box_v = out.box_half_width_mm - r;
  const double isthmus_v = 0.5 * s.isthmus_width_mm * s.widen - r;
  const double distal_u = s.distal_reach_mm + (s.widen - 1.0) * s.isthmus_width_mm;
  // The box's first column: one past the mesial surface, or, beside a neighbour, the first whose bur
  // keeps the clearance from it (over the bur's whole reach across the box and down to the floor).
  // Beside a neighbour the grid moves along x by `shift` [mm] to put a column on that limit, and the
  // box keeps at least that one row, however close the limit comes to the axial wall.
  double first_u = box_u0 - g, shift = 0.0;
  out.neighbour_x = mesialNeighbourFace(volume, frame, fossa->x, fossa->y, out.box_half_width_mm,
                                        out.gingival_floor_z, box.hi.z);
  if (out.neighbour_x) {
    out.bur_mesial_limit_x = *out.neighbour_x + s.neighbour_clearance_mm - (s.widen - 1.0) * s.box_depth_mm;
    first_u = std::max(first_u, out.bur_mesial_limit_x + r - fossa->x);
    shift = first_u - g * std::round(first_u / g);
    box_u1 = std::max(box_u1, first_u);
  }
  const double half_u = std::max(out.neighbour_x ? -first_u + std::abs(shift) : -box_u0, distal_u + std::abs(shift)) + g;
  const double half_v = std::max(box_v, isthmus_v) + g;
  const AxisFrame axis = AxisFrame::along({fossa->x + shift, fossa->y, 0.0}, {0, 0, 1}, {1, 0, 0});
  const double tol = out.neighbour_x ? 1e-9 : 0.0;  // a shifted column on the limit is on it
  const auto columns = gridColumns(g, half_u, half_v, [&](double grid_u, double v) -> std::optional<double> {
    const double u = grid_u + shift;  // from the fossa [mm]
    if (u >= first_u - tol && u <= box_u1 + tol && std::abs(v) <= box_v + 1e-9) return out.gingival_floor_z;
    if (u >= box_u1 - 1e-9 && u <= distal_u && std::abs(v) <= isthmus_v + 1e-9) return out.occlusal_floor_z;
    return std::nullopt;
  });
  auto cut = pocketPath(volume, frame, params, bur, axis, columns, s.pocket);
  if (!cut) return makeError(where, cut.message());
  out.cut = std::move(*cut);
  return out;
}

// ---- 3. class V cervical -----------------------------------------------------------------------------------------

Result<Class5Path> class5CavityPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                                    const std::string& bur, const Class5Settings& s) {
  const std::string where = "class V path";
  if (!(s.width_mm > 0) || !(s.height_mm > 0) || s.above_cej_mm < 0 || !(s.depth_mm > 0) || !(s.widen >= 1) ||
      !finite(s.axis))
    return makeError(where, "width, height and depth must be > 0, the height above the CEJ >= 0, widen >= 1");
  auto head = burHead(bur);
  if (!head) return makeError(where, head.message());
  const double r = head->radius_mm;
  if (!(s.width_mm * s.widen > 2 * r) || !(s.height_mm * s.widen > 2 * r))
    return makeError(where, "the outline is narrower than the bur " + bur);
  const TissueBox box = toothBox(volume, frame);
  if (box.empty()) return makeError(where, "the volume holds no tissue");
  SurfaceProbe probe(volume, frame, box);
  TissueRay ray(volume, frame);
  const Vec3 centre = box.centre();

  // The crown's mesiodistal centre is the fossa's; the buccal CEJ lies under it.
  const std::optional<Vec3> fossa = lowestRestingTip(probe, centre.x, centre.y, r, s.fossa_search_mm, s.fossa_grid_mm);
  if (!fossa) return makeError(where, "no tissue under the bur near the crown's centre");
  const double step = 0.5 * frame.voxel_mm, reach = box.hi.y - box.lo.y + 2.0;
  const Vec3 buccal_start{fossa->x, box.lo.y - 1.0, 0.0}, toward_lingual{0, 1, 0};
  const std::optional<double> cej = cejAlong(ray, buccal_start, toward_lingual, fossa->z, box.lo.z, step, reach);
  if (!cej) return makeError(where, "no enamel ending on the buccal surface: where is the CEJ?");

  Class5Path out;
  out.buccal_cej_z = *cej;
  const double half_height = 0.5 * s.height_mm;  // the expert's; the over-cut grows about the same centre
  const double z_c = *cej + s.above_cej_mm + half_height;
  auto surfaceAt = [&](double x, double z) { return ray.first(Vec3{x, buccal_start.y, z}, toward_lingual, reach); };
  const auto c = surfaceAt(fossa->x, z_c);
  if (!c) return makeError(where, "no buccal surface at the outline's centre");
  out.centre_mm = c->point;
  // The normal from the surface's slope across and along the crown, 0.4 mm each way.
  const auto xm = surfaceAt(fossa->x - 0.4, z_c), xp = surfaceAt(fossa->x + 0.4, z_c);
  const auto zm = surfaceAt(fossa->x, z_c - 0.4), zp = surfaceAt(fossa->x, z_c + 0.4);
  if (!xm || !xp || !zm || !zp) return makeError(where, "the buccal surface ends beside the outline's centre");
  Vec3 n = normalized(cross(zp->point - zm->point, xp->point - xm->point));
  if (n.y > 0) n = -n;
  out.normal = n;
  out.axis = norm(s.axis) > 0 ? normalized(s.axis) : n;
  if (!(out.axis.y < 0)) return makeError(where, "the bur's axis must point buccally (-y)");

  // An oval of tip positions across the axis, each column's floor depth_mm under its own surface.
  const AxisFrame axis = AxisFrame::along(out.centre_mm, out.axis, {1, 0, 0});
  const double a = 0.5 * s.width_mm * s.widen - r, b = 0.5 * s.height_mm * s.widen - r;
  const double outside = 3.0;  // start the column's ray this far out along the axis [mm]
  const auto columns = gridColumns(s.pocket.grid_mm, a, b, [&](double u, double v) -> std::optional<double> {
    if ((u / a) * (u / a) + (v / b) * (v / b) > 1.0 + 1e-9) return std::nullopt;
    const auto hit = ray.first(axis.at(u, v, outside), -axis.axis, outside + 3.0);
    if (!hit) return std::nullopt;
    return outside - hit->distance_mm - s.depth_mm;
  });
  auto cut = pocketPath(volume, frame, params, bur, axis, columns, s.pocket);
  if (!cut) return makeError(where, cut.message());
  out.cut = std::move(*cut);
  return out;
}

// ---- 4. endodontic access ------------------------------------------------------------------------------------------

namespace {

// Calls f(x, y, z) for every pulp voxel (fill > 0), voxel indices.
template <typename F>
void forEachPulpVoxel(const BrickVolume& volume, F&& f) {
  volume.forEachBrick([&](const BrickView& b) {
    const uint32_t bx = b.coord.x * DS_BRICK_DIM, by = b.coord.y * DS_BRICK_DIM, bz = b.coord.z * DS_BRICK_DIM;
    for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
      const Voxel v = b.uniform ? b.value : b.voxels[i];
      if (voxelMaterial(v) != Material::Pulp || voxelFill(v) == 0) {
        if (b.uniform) return;
        continue;
      }
      f(bx + (i & 7u), by + ((i >> 3) & 7u), bz + (i >> 6));
    }
  });
}

}  // namespace

Result<AccessPath> accessCavityPath(const BrickVolume& volume, const VolumeFrame& frame, const SimParams& params,
                                    const std::string& bur, const AccessSettings& s) {
  const std::string where = "access path";
  if (!(s.horn_depth_mm > 0) || !(s.outline_share > 0) || s.into_pulp_mm < 0 || !(s.widen >= 1))
    return makeError(where, "horn depth and outline share must be > 0, the depth into the pulp >= 0, widen >= 1");
  auto head = burHead(bur);
  if (!head) return makeError(where, head.message());
  const double r = head->radius_mm, v = frame.voxel_mm;
  auto centreOf = [&](uint32_t x, uint32_t y, uint32_t z) {
    return Vec3{frame.origin_mm[0] + (x + 0.5) * v, frame.origin_mm[1] + (y + 0.5) * v, frame.origin_mm[2] + (z + 0.5) * v};
  };

  // The pulp's top, then the box of the horns under it.
  AccessPath out;
  bool any = false;
  forEachPulpVoxel(volume, [&](uint32_t x, uint32_t y, uint32_t z) {
    out.pulp_top_z = any ? std::max(out.pulp_top_z, centreOf(x, y, z).z) : centreOf(x, y, z).z;
    any = true;
  });
  if (!any) return makeError(where, "the volume holds no pulp");
  out.horns_lo_mm = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
  out.horns_hi_mm = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  forEachPulpVoxel(volume, [&](uint32_t x, uint32_t y, uint32_t z) {
    const Vec3 c = centreOf(x, y, z);
    if (c.z < out.pulp_top_z - s.horn_depth_mm) return;
    for (int a = 0; a < 3; ++a) {
      out.horns_lo_mm[a] = std::min(out.horns_lo_mm[a], c[a] - 0.5 * v);
      out.horns_hi_mm[a] = std::max(out.horns_hi_mm[a], c[a] + 0.5 * v);
    }
  });
  out.centre_mm = {0.5 * (out.horns_lo_mm.x + out.horns_hi_mm.x), 0.5 * (out.horns_lo_mm.y + out.horns_hi_mm.y), 0.0};
  out.half_x_mm = 0.5 * (out.horns_hi_mm.x - out.horns_lo_mm.x) * s.outline_share * s.widen;
  out.half_y_mm = 0.5 * (out.horns_hi_mm.y - out.horns_lo_mm.y) * s.outline_share * s.widen;
  const double a = out.half_x_mm - r, b = out.half_y_mm - r;
  if (!(a > 0) || !(b > 0)) return makeError(where, "the horns lie closer together than the bur " + bur + " is wide");

  // In each column of the oval, the first pulp under the surface: the floor is into_pulp_mm below it.
  const AxisFrame axis = AxisFrame::along(out.centre_mm, {0, 0, 1}, {1, 0, 0});
  const double top = toothBox(volume, frame).hi.z;
  auto firstPulp = [&](double x, double y) -> std::optional<double> {
    const double fx = (x - frame.origin_mm[0]) / v, fy = (y - frame.origin_mm[1]) / v;
    if (fx < 0 || fy < 0 || fx >= volume.dim() || fy >= volume.dim()) return std::nullopt;
    const auto ix = uint32_t(fx), iy = uint32_t(fy);
    const auto z0 = int64_t(std::floor((std::min(top, frame.origin_mm[2] + volume.dim() * v) - frame.origin_mm[2]) / v)) - 1;
    const auto z1 = int64_t(std::floor((out.pulp_top_z - s.horn_depth_mm - 1.0 - frame.origin_mm[2]) / v));
    for (int64_t z = z0; z >= std::max<int64_t>(z1, 0); --z) {
      const Voxel vox = volume.voxel(ix, iy, uint32_t(z));
      if (voxelMaterial(vox) == Material::Pulp && voxelFill(vox) >= DS_FILL_FULL / 2 + 1) return centreOf(ix, iy, uint32_t(z)).z + 0.5 * v;
    }
    return std::nullopt;
  };
  std::vector<PocketColumn> columns = gridColumns(s.pocket.grid_mm, a, b, [&](double u, double w) -> std::optional<double> {
    if ((u / a) * (u / a) + (w / b) * (w / b) > 1.0 + 1e-9) return std::nullopt;
    const std::optional<double> pulp = firstPulp(out.centre_mm.x + u, out.centre_mm.y + w);
    return pulp ? std::optional<double>(*pulp - s.into_pulp_mm) : std::optional<double>(HUGE_VAL);
  });
  // Columns over no pulp: the highest floor of the rest, a shelf over the chamber's edge.
  double shelf = -HUGE_VAL;
  out.lowest_floor_z = HUGE_VAL;
  for (const PocketColumn& c : columns)
    if (c.floor_h != HUGE_VAL) {
      shelf = std::max(shelf, c.floor_h);
      out.lowest_floor_z = std::min(out.lowest_floor_z, c.floor_h);
    }
  if (shelf == -HUGE_VAL) return makeError(where, "no pulp under the outline");
  for (PocketColumn& c : columns)
    if (c.floor_h == HUGE_VAL) c.floor_h = shelf;
  auto cut = pocketPath(volume, frame, params, bur, axis, columns, s.pocket);
  if (!cut) return makeError(where, cut.message());
  out.cut = std::move(*cut);
  return out;
}

}  // namespace dentsim
