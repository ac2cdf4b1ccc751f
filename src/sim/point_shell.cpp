// buildPointShell: dense surface samples of a tool mesh binned into spacing-sized cubes, one point per cube.
#include "sim/point_shell.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <unordered_map>
#include <utility>

namespace dentsim {

namespace {

constexpr size_t kMaxPoints = 2'000'000;

// What one spacing-sized cube collects from the samples that fall in it.
struct Bin {
  Vec3 weighted_position;  // sum of area * position
  Vec3 weighted_normal;    // sum of area * outward unit normal
  double area = 0.0;       // sum of sample areas [mm^2]
};

Vec3 toVec(const Vec3f& p) { return {double(p[0]), double(p[1]), double(p[2])}; }

int64_t cell(double v, double size) { return int64_t(std::floor(v / size)); }

// Splits a triangle at its longest edge until every edge is at most max_edge, then calls emit with
// each piece's centroid and area. The pieces tile the triangle, so their areas sum to its area.
template <class Emit>
void subdivide(const Vec3& a, const Vec3& b, const Vec3& c, double max_edge, int depth, const Emit& emit) {
  const double ab = norm(b - a), bc = norm(c - b), ca = norm(a - c);
  const double longest = std::max(ab, std::max(bc, ca));
  if (longest <= max_edge || depth > 40) {
    emit((a + b + c) / 3.0, 0.5 * norm(cross(b - a, c - a)));
    return;
  }
  if (longest == ab) {
    const Vec3 m = (a + b) * 0.5;
    subdivide(a, m, c, max_edge, depth + 1, emit);
    subdivide(m, b, c, max_edge, depth + 1, emit);
  } else if (longest == bc) {
    const Vec3 m = (b + c) * 0.5;
    subdivide(a, b, m, max_edge, depth + 1, emit);
    subdivide(a, m, c, max_edge, depth + 1, emit);
  } else {
    const Vec3 m = (c + a) * 0.5;
    subdivide(a, b, m, max_edge, depth + 1, emit);
    subdivide(m, b, c, max_edge, depth + 1, emit);
  }
}

}  // namespace

size_t PointShell::cuttingCount() const { return size_t(std::count(cutting.begin(), cutting.end(), uint8_t{1})); }

Result<PointShell> buildPointShell(const TriangleMesh& mesh, const PointShellOptions& options) {
  if (mesh.triangles.empty()) return makeError("point shell", "the tool mesh has no triangles");
  for (double s : {options.head_spacing_mm, options.shank_spacing_mm})
    if (!(s > 0 && s <= 10)) return makeError("point shell", "spacing " + std::to_string(s) + " mm is not in (0, 10]");
  if (!(options.cluster_mm > 0) || !std::isfinite(options.cutting_length_mm))
    return makeError("point shell", "cluster size must be positive and the cutting length finite");
  const Bounds3 bounds = mesh.bounds();
  for (double v : {bounds.lo[0], bounds.lo[1], bounds.lo[2], bounds.hi[0], bounds.hi[1], bounds.hi[2]})
    if (!std::isfinite(v)) return makeError("point shell", "the tool mesh has a non-finite vertex");

  // Estimate the count before sampling, so a tiny spacing on a large mesh fails fast.
  const double area = [&] {
    double a = 0;
    for (const auto& t : mesh.triangles)
      a += 0.5 * norm(cross(toVec(mesh.positions[t[1]]) - toVec(mesh.positions[t[0]]),
                            toVec(mesh.positions[t[2]]) - toVec(mesh.positions[t[0]])));
    return a;
  }();
  const bool has_head = options.cutting_length_mm > 0;
  const double finest = has_head ? std::min(options.head_spacing_mm, options.shank_spacing_mm) : options.shank_spacing_mm;
  if (area / (finest * finest) > double(kMaxPoints))
    return makeError("point shell", "the shell would exceed " + std::to_string(kMaxPoints) + " points; use a coarser spacing");

  PointShell shell;
  shell.head_spacing_mm = options.head_spacing_mm;
  shell.shank_spacing_mm = options.shank_spacing_mm;
  shell.tip_z_mm = bounds.lo[2];
  const double head_top = bounds.lo[2] + options.cutting_length_mm;

  // Bins keyed by (cluster cube, head or not, spacing cube), hashed while sampling, then sorted so
  // that points come cluster by cluster in a fixed order.
  struct Key {
    int64_t c[3];  // cluster cube
    int64_t head;  // 1 for the cutting head
    int64_t s[3];  // spacing cube
    bool operator==(const Key&) const = default;
    bool operator<(const Key& o) const {
      return std::tie(c[0], c[1], c[2], head, s[0], s[1], s[2]) <
             std::tie(o.c[0], o.c[1], o.c[2], o.head, o.s[0], o.s[1], o.s[2]);
    }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      uint64_t h = 0x9e3779b97f4a7c15ull;
      for (int64_t v : {k.c[0], k.c[1], k.c[2], k.head, k.s[0], k.s[1], k.s[2]})
        h = (h ^ uint64_t(v)) * 0x100000001b3ull + (h >> 29);
      return size_t(h);
    }
  };
  std::unordered_map<Key, Bin, KeyHash> bins;
  bins.reserve(size_t(area / (finest * finest)) + 16);
  for (const auto& t : mesh.triangles) {
    const Vec3 a = toVec(mesh.positions[t[0]]), b = toVec(mesh.positions[t[1]]), c = toVec(mesh.positions[t[2]]);
    const Vec3 n = normalized(cross(b - a, c - a));
    if (norm(n) == 0) continue;  // degenerate: no area, no direction
    // Pieces well below the spacing, so that each cube's centroid sits on the surface it covers; a
    // triangle reaching into the head is cut at the head's spacing.
    const bool reaches_head = has_head && std::min(a.z, std::min(b.z, c.z)) <= head_top;
    const double max_edge = 0.25 * (reaches_head ? options.head_spacing_mm : options.shank_spacing_mm);
    subdivide(a, b, c, max_edge, 0, [&](const Vec3& p, double piece_area) {
      const int64_t head = has_head && p.z <= head_top ? 1 : 0;
      const double s = head ? options.head_spacing_mm : options.shank_spacing_mm;
      const Key key{{cell(p.x, options.cluster_mm), cell(p.y, options.cluster_mm), cell(p.z, options.cluster_mm)},
                    head,
                    {cell(p.x, s), cell(p.y, s), cell(p.z, s)}};
      Bin& bin = bins[key];
      bin.weighted_position += p * piece_area;
      bin.weighted_normal += n * piece_area;
      bin.area += piece_area;
    });
  }
  std::vector<std::pair<Key, Bin>> sorted(bins.begin(), bins.end());
  std::sort(sorted.begin(), sorted.end(), [](const auto& x, const auto& y) { return x.first < y.first; });

  shell.positions.reserve(sorted.size());
  const Key* current = nullptr;
  for (const auto& [key, bin] : sorted) {
    if (bin.area <= 0) continue;
    const Vec3 outward = normalized(bin.weighted_normal);
    if (norm(outward) == 0) continue;  // opposite faces cancelled inside one cube: no usable normal
    const bool same_cluster = current != nullptr && current->c[0] == key.c[0] && current->c[1] == key.c[1] &&
                              current->c[2] == key.c[2];
    if (!same_cluster) shell.clusters.push_back(ShellCluster{uint32_t(shell.positions.size()), 0, {}, 0.0});
    current = &key;
    ++shell.clusters.back().count;
    shell.positions.push_back(bin.weighted_position / bin.area);
    shell.inward.push_back(-outward);
    shell.area_mm2.push_back(bin.area);
    shell.cutting.push_back(uint8_t(key.head));
    shell.total_area_mm2 += bin.area;
  }
  // Bounding spheres: the box centre and the farthest point from it.
  for (ShellCluster& c : shell.clusters) {
    Bounds3 b;
    for (uint32_t i = c.first; i < c.first + c.count; ++i) b.add(Vec3d{shell.positions[i].x, shell.positions[i].y, shell.positions[i].z});
    c.centre = Vec3{0.5 * (b.lo[0] + b.hi[0]), 0.5 * (b.lo[1] + b.hi[1]), 0.5 * (b.lo[2] + b.hi[2])};
    for (uint32_t i = c.first; i < c.first + c.count; ++i) c.radius = std::max(c.radius, norm(shell.positions[i] - c.centre));
  }
  return shell;
}

}  // namespace dentsim
