// The score picture: brick occupancy, orthographic ray casting with brick skipping, shading, PNG encoding.
//
// Contents
//   1. Colours and the fog's strength
//   2. Occupancy: which bricks a ray must enter
//   3. Views: camera basis and fit
//   4. One ray
//   5. renderScoreImage
#include "eval/score_image.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "volume/tissue_table.h"
#include "volume/half_fill.h"

namespace dentsim {

std::array<double, 2> ScoreView::pixelOf(const Vec3& p) const {
  return {x0 + width * 0.5 + (dot(p, right) - u_centre) / voxels_per_pixel,
          height * 0.5 - (dot(p, up) - v_centre) / voxels_per_pixel};
}

namespace {

// ---- 1. colours ----------------------------------------------------------------------------------

struct Rgb {
  double r, g, b;  // [0, 1]
};
Rgb mix(const Rgb& a, const Rgb& b, double t) { return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t}; }

constexpr Rgb kBackground{0.16, 0.17, 0.20};
constexpr Rgb kRed{0.90, 0.10, 0.08};
constexpr Rgb kUndercut{0.12, 0.32, 0.95};
constexpr Rgb kPaintRgb[6]{{0, 0, 0}, {0.18, 0.78, 0.26}, kRed, kUndercut, {0.98, 0.84, 0.10}, {0.86, 0.16, 0.82}};  // by kPaint* code
constexpr double kUndercutTint = 0.8;   // blend toward blue of a fully under-cut hit voxel
constexpr double kRedFog = 0.6;         // opacity of one full red voxel: one voxel of error shows

// The tissue table's score_rgb; grey for the spare codes.
Rgb tissueColour(uint32_t material) {
  const TissueRow* row = findTissue(Material(material));
  if (!row) return {0.7, 0.7, 0.7};
  return {row->score_rgb[0], row->score_rgb[1], row->score_rgb[2]};
}

// A neighbour is never under-cut: what the ideal took of an adjacent tooth is not the student's to take.
uint32_t undercutOf(Voxel initial, Voxel final_, Voxel ideal) {
  const uint32_t fi = isToothTissue(voxelMaterial(initial)) ? voxelFill(initial) : 0u;
  const uint32_t r = std::min(voxelFill(final_), fi), k = std::min(voxelFill(ideal), fi);
  return r > k ? r - k : 0u;
}

// ---- 2. occupancy --------------------------------------------------------------------------------

struct Volumes {
  const BrickVolume& initial;
  const BrickVolume& final_;
  const BrickVolume* ideal;
  const CutMarks* red;
  const CutMarks* paint;
};

// One byte per brick: 1 when a ray must look inside (surface or red there); and their bounds.
struct Occupancy {
  uint32_t brick_dim = 0;
  std::vector<uint8_t> occupied;         // (brick_dim^3), x fastest
  std::array<double, 3> lo{}, hi{};      // bounds of the occupied bricks [voxels]
  bool any = false;
  bool at(uint32_t bx, uint32_t by, uint32_t bz) const {
    return occupied[bx + size_t(brick_dim) * (by + size_t(brick_dim) * bz)] != 0;
  }
};

Occupancy occupancy(const Volumes& v) {
  Occupancy o;
  o.brick_dim = v.final_.brickDim();
  o.occupied.assign(size_t(o.brick_dim) * o.brick_dim * o.brick_dim, 0);
  std::array<uint32_t, 3> lo{o.brick_dim, o.brick_dim, o.brick_dim}, hi{0, 0, 0};
  for (uint32_t bz = 0; bz < o.brick_dim; ++bz)
    for (uint32_t by = 0; by < o.brick_dim; ++by)
      for (uint32_t bx = 0; bx < o.brick_dim; ++bx) {
        const BrickCoord c{bx, by, bz};
        const BrickView f = v.final_.brick(c);
        bool occ = false;
        if (f.uniform) occ = isHalfFull(f.value);
        for (uint32_t n = 0; !f.uniform && !occ && n < DS_BRICK_VOXELS; ++n) occ = isHalfFull(f.voxels[n]);
        if (!occ && v.red) occ = v.red->brickHasMarks(c);
        if (!occ) continue;
        o.occupied[bx + size_t(o.brick_dim) * (by + size_t(o.brick_dim) * bz)] = 1;
        const std::array<uint32_t, 3> b{bx, by, bz};
        for (size_t a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], b[a]);
          hi[a] = std::max(hi[a], b[a] + 1);
        }
        o.any = true;
      }
  for (size_t a = 0; a < 3; ++a) {
    o.lo[a] = o.any ? double(lo[a] * DS_BRICK_DIM) : 0.0;
    o.hi[a] = o.any ? double(hi[a] * DS_BRICK_DIM) : double(v.final_.dim());
  }
  return o;
}

// ---- 3. views ------------------------------------------------------------------------------------

// The box the views fit [voxels]: the occupied bricks, or the painted ones with half their extent
// again on each side (at least two bricks), so that a small cavity fills the view with its rim in sight.
struct FitBox {
  std::array<double, 3> lo{}, hi{};
};
FitBox fitBox(const Occupancy& occ, const CutMarks* paint, bool fit_paint) {
  FitBox fit{occ.lo, occ.hi};
  if (!fit_paint || !paint || paint->empty()) return fit;
  std::array<uint32_t, 3> lo{occ.brick_dim, occ.brick_dim, occ.brick_dim}, hi{0, 0, 0};
  for (uint32_t bz = 0; bz < occ.brick_dim; ++bz)
    for (uint32_t by = 0; by < occ.brick_dim; ++by)
      for (uint32_t bx = 0; bx < occ.brick_dim; ++bx) {
        if (!paint->brickHasMarks({bx, by, bz})) continue;
        const std::array<uint32_t, 3> b{bx, by, bz};
        for (size_t a = 0; a < 3; ++a) {
          lo[a] = std::min(lo[a], b[a]);
          hi[a] = std::max(hi[a], b[a] + 1);
        }
      }
  for (size_t a = 0; a < 3; ++a) {
    const double l = double(lo[a] * DS_BRICK_DIM), h = double(hi[a] * DS_BRICK_DIM);
    const double pad = std::max(0.5 * (h - l), 2.0 * DS_BRICK_DIM);
    fit.lo[a] = l - pad;
    fit.hi[a] = h + pad;
  }
  return fit;
}

ScoreView makeView(const Vec3& dir, const FitBox& occ, int x0, int width, int height) {
  ScoreView view;
  view.dir = normalized(dir);
  // Up is +z in the image unless the camera looks (nearly) along z; then lingual (+y) is up.
  const Vec3 up_hint = std::abs(view.dir.z) > 0.9 ? Vec3{0, 1, 0} : Vec3{0, 0, 1};
  view.right = normalized(cross(view.dir, up_hint));
  view.up = cross(view.right, view.dir);
  double umin = std::numeric_limits<double>::max(), umax = -umin, vmin = umin, vmax = -umin;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p{(corner & 1) ? occ.hi[0] : occ.lo[0], (corner & 2) ? occ.hi[1] : occ.lo[1],
                 (corner & 4) ? occ.hi[2] : occ.lo[2]};
    umin = std::min(umin, dot(p, view.right));
    umax = std::max(umax, dot(p, view.right));
    vmin = std::min(vmin, dot(p, view.up));
    vmax = std::max(vmax, dot(p, view.up));
  }
  constexpr double kMargin = 0.92;  // of the view the tooth may fill
  view.voxels_per_pixel = std::max((umax - umin) / (width * kMargin), (vmax - vmin) / (height * kMargin));
  view.u_centre = 0.5 * (umin + umax);
  view.v_centre = 0.5 * (vmin + vmax);
  view.x0 = x0;
  view.width = width;
  view.height = height;
  return view;
}

// ---- 4. one ray ----------------------------------------------------------------------------------

class RayCaster {
 public:
  RayCaster(const Volumes& v, const Occupancy& occ) : v_(v), occ_(occ), dim_(int64_t(v.final_.dim())) {}

  Rgb cast(const Vec3& origin, const Vec3& d, const Vec3& light) const {
    // Enter and leave the occupied bounds (slab test).
    double t0 = 0.0, t1 = std::numeric_limits<double>::max();
    for (int a = 0; a < 3; ++a) {
      if (d[a] == 0.0) {
        if (origin[a] < occ_.lo[size_t(a)] || origin[a] > occ_.hi[size_t(a)]) return kBackground;
        continue;
      }
      double ta = (occ_.lo[size_t(a)] - origin[a]) / d[a], tb = (occ_.hi[size_t(a)] - origin[a]) / d[a];
      if (ta > tb) std::swap(ta, tb);
      t0 = std::max(t0, ta);
      t1 = std::min(t1, tb);
    }
    double fog = 0.0;  // opacity of the red fog gathered so far
    constexpr double kNudge = 1e-7;  // into the next cell [voxels]
    double t = t0;
    while (t < t1) {
      const Vec3 p = origin + d * (t + kNudge);
      std::array<int64_t, 3> ix{};
      for (int a = 0; a < 3; ++a) ix[size_t(a)] = std::clamp(int64_t(std::floor(p[a])), int64_t{0}, dim_ - 1);
      const auto bx = uint32_t(ix[0] >> DS_BRICK_LOG2), by = uint32_t(ix[1] >> DS_BRICK_LOG2),
                 bz = uint32_t(ix[2] >> DS_BRICK_LOG2);
      const double brick_exit = exitT(origin, d, {bx, by, bz});
      if (!occ_.at(bx, by, bz)) {
        t = std::max(brick_exit, t + kNudge);
        continue;
      }
      // Voxel DDA inside the brick.
      const double t_enter = t;
      const BrickCoord c{bx, by, bz};
      const BrickView vi = v_.initial.brick(c), vf = v_.final_.brick(c);
      const BrickView vk = v_.ideal ? v_.ideal->brick(c) : vi;
      std::array<double, 3> t_max{}, t_delta{};
      std::array<int64_t, 3> step{};
      for (size_t a = 0; a < 3; ++a) {
        const double da = d[int(a)];
        step[a] = da > 0 ? 1 : (da < 0 ? -1 : 0);
        t_delta[a] = da != 0 ? 1.0 / std::abs(da) : std::numeric_limits<double>::infinity();
        t_max[a] = da > 0   ? (double(ix[a] + 1) - origin[int(a)]) / da
                   : da < 0 ? (double(ix[a]) - origin[int(a)]) / da
                            : std::numeric_limits<double>::infinity();
      }
      for (;;) {
        const uint32_t n = layout::brickCoordToOffset(uint32_t(ix[0] & 7), uint32_t(ix[1] & 7), uint32_t(ix[2] & 7));
        const Voxel f = vf.at(n);
        if (isHalfFull(f)) {
          const uint32_t paint = v_.paint ? v_.paint->at(uint32_t(ix[0]), uint32_t(ix[1]), uint32_t(ix[2])) : 0u;
          const Rgb surface = shade(ix, f, v_.ideal ? undercutOf(vi.at(n), f, vk.at(n)) : 0u, paint, d, light);
          return mix(surface, kRed, fog);
        }
        if (v_.red) {
          const uint32_t red = v_.red->at(uint32_t(ix[0]), uint32_t(ix[1]), uint32_t(ix[2]));
          if (red > 0) fog = 1.0 - (1.0 - fog) * (1.0 - kRedFog * red / DS_FILL_FULL);
        }
        const size_t a = t_max[0] < t_max[1] ? (t_max[0] < t_max[2] ? 0 : 2) : (t_max[1] < t_max[2] ? 1 : 2);
        t = t_max[a];
        ix[a] += step[a];
        t_max[a] += t_delta[a];
        if (t >= t1 || ix[a] < 0 || ix[a] >= dim_ || (ix[a] >> DS_BRICK_LOG2) != int64_t(a == 0 ? bx : a == 1 ? by : bz))
          break;
      }
      t = std::max(t, t_enter + kNudge);  // rounding must never stall the march
    }
    return mix(kBackground, kRed, fog);
  }

 private:
  // Where the ray leaves brick b.
  static double exitT(const Vec3& origin, const Vec3& d, std::array<uint32_t, 3> b) {
    double t = std::numeric_limits<double>::max();
    for (int a = 0; a < 3; ++a) {
      const double lo = double(b[size_t(a)] * DS_BRICK_DIM), hi = lo + DS_BRICK_DIM;
      if (d[a] > 0) t = std::min(t, (hi - origin[a]) / d[a]);
      if (d[a] < 0) t = std::min(t, (lo - origin[a]) / d[a]);
    }
    return t;
  }

  double fillAt(int64_t x, int64_t y, int64_t z) const {
    if (x < 0 || y < 0 || z < 0 || x >= dim_ || y >= dim_ || z >= dim_) return 0.0;
    return voxelFill(v_.final_.voxel(uint32_t(x), uint32_t(y), uint32_t(z)));
  }

  // Lambert in the paint's colour, else the tissue's tinted by the under-cut; the normal points down the fill gradient.
  Rgb shade(const std::array<int64_t, 3>& ix, Voxel f, uint32_t undercut, uint32_t paint, const Vec3& d,
            const Vec3& light) const {
    const int64_t x = ix[0], y = ix[1], z = ix[2];
    Vec3 normal{fillAt(x - 1, y, z) - fillAt(x + 1, y, z), fillAt(x, y - 1, z) - fillAt(x, y + 1, z),
                fillAt(x, y, z - 1) - fillAt(x, y, z + 1)};
    normal = norm(normal) > 0 ? normalized(normal) : -d;  // inside a flat wall: face the camera
    const double lambert = std::max(0.0, dot(normal, light));
    Rgb base = tissueColour(layout::voxelMaterial(f));
    base = mix(base, kUndercut, kUndercutTint * undercut / DS_FILL_FULL);
    if (paint >= kPaintGreen && paint <= kPaintMagenta) base = kPaintRgb[paint];
    const double s = 0.28 + 0.72 * lambert;
    return {base.r * s, base.g * s, base.b * s};
  }

  const Volumes& v_;
  const Occupancy& occ_;
  int64_t dim_;
};

uint8_t toByte(double c) { return uint8_t(std::lround(std::clamp(c, 0.0, 1.0) * 255.0)); }

void renderView(const RayCaster& caster, const ScoreView& view, const Occupancy& occ, RgbImage* image) {
  // Rays start outside the occupied bounds: half their diagonal back from the centre's depth.
  const Vec3 lo{occ.lo[0], occ.lo[1], occ.lo[2]}, hi{occ.hi[0], occ.hi[1], occ.hi[2]};
  const double depth = dot((lo + hi) * 0.5, view.dir) - norm(hi - lo) - 1.0;
  // A light over the viewer's left shoulder, so that walls facing the camera are not flat.
  const Vec3 light = normalized(-view.dir + view.up * 0.35 - view.right * 0.25);
  for (int py = 0; py < view.height; ++py)
    for (int px = 0; px < view.width; ++px) {
      const double u = view.u_centre + (px + 0.5 - view.width * 0.5) * view.voxels_per_pixel;
      const double v = view.v_centre - (py + 0.5 - view.height * 0.5) * view.voxels_per_pixel;
      const Vec3 origin = view.right * u + view.up * v + view.dir * depth;
      const Rgb c = occ.any ? caster.cast(origin, view.dir, light) : kBackground;
      const size_t o = (size_t(py) * size_t(image->width) + size_t(view.x0 + px)) * 3;
      image->rgb[o] = toByte(c.r);
      image->rgb[o + 1] = toByte(c.g);
      image->rgb[o + 2] = toByte(c.b);
    }
}

}  // namespace

// ---- 5. renderScoreImage, PNG --------------------------------------------------------------------

ScoreImage renderScoreImage(const ToothVolume& initial, const ToothVolume& final_, const ToothVolume* ideal,
                            const CutMarks* red, const ScoreImageOptions& options, const CutMarks* paint) {
  assert(initial.voxels.level() == final_.voxels.level());
  assert(!ideal || ideal->voxels.level() == initial.voxels.level());
  ScoreImage out;
  out.image.width = std::clamp(options.width, 16, 8192);
  out.image.height = std::clamp(options.height, 16, 8192);
  out.image.rgb.assign(size_t(out.image.width) * size_t(out.image.height) * 3, 0);
  const Volumes volumes{initial.voxels, final_.voxels, ideal ? &ideal->voxels : nullptr, red, paint};
  const Occupancy occ = occupancy(volumes);
  const FitBox fit = fitBox(occ, paint, options.fit_paint);
  const RayCaster caster(volumes, occ);
  // The oblique view looks from mesial-buccal and above (buccal is -y, mesial -x in the molar's frame).
  const Vec3 oblique_dir = normalized(Vec3{0.45, 1.0, -1.1});
  const int half = out.image.width / 2;
  if (options.oblique) {
    out.views.push_back(makeView(options.view_dir, fit, 0, half, out.image.height));
    out.views.push_back(makeView(oblique_dir, fit, half, out.image.width - half, out.image.height));
  } else {
    out.views.push_back(makeView(options.view_dir, fit, 0, out.image.width, out.image.height));
  }
  for (const ScoreView& view : out.views) renderView(caster, view, occ, &out.image);
  return out;
}

}  // namespace dentsim
