// Meshing benchmark: Figure 15 rows, the bur path, normal errors, and their JSON, Markdown and SVG report.
//
// Contents
//   1. Injected pieces: the CPU reference runner and volume maker
//   2. Where the solid is: bounds, column tops, the surface part
//   3. Figure 15 rows
//   4. The bur path
//   5. Normal errors
//   6. The whole run
//   7. JSON
//   8. Markdown
//   9. SVG and files
#include "bench/mesh_bench.h"

#include <algorithm>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <optional>
#include <sstream>
#include <unordered_map>

#include "bench/svg_plot.h"
#include "bench/voxelize_bench.h"
#include "core/percentile.h"
#include "core/text_format.h"
#include "io/atomic_file.h"
#include "volume/surface_mesher.h"
#include "volume/volume_edit.h"

namespace dentsim::bench {
namespace {

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// The mesher's inside test: phi = fill / 31 over one half, every tissue counting.
bool solidVoxel(Voxel v) { return 2 * voxelFill(v) > DS_FILL_FULL; }

}  // namespace

// ---- 1. injected pieces ----------------------------------------------------------------------------

MeshRunner cpuReferenceRunner() {
  MeshRunner r;
  r.name = "CPU reference (meshVolumeCpu, one thread; its update re-meshes everything)";
  r.mesher = "reference";
  auto mesh = [](const ToothVolume& tooth, int normals) -> Result<MeshTiming> {
    const std::optional<NormalMode> mode = normalModeFromNeighbours(normals);
    if (!mode) return makeError("bench mesh", "no normal mode of " + std::to_string(normals) + " voxels");
    SurfaceOptions options;
    options.normals = *mode;
    const auto start = std::chrono::steady_clock::now();
    auto surface = meshVolumeCpu(tooth, options);
    if (!surface) return surface.error();
    MeshTiming t;
    t.ms = msSince(start);
    t.triangles = surface->triangleCount();
    return t;
  };
  r.full = mesh;
  r.update = [mesh](const ToothVolume& tooth, std::span<const BrickCoord>, int normals) { return mesh(tooth, normals); };
  return r;
}

VolumeMaker cpuVolumeMaker(std::vector<MeshLayer> layers, VoxelizeOptions options) {
  return [layers = std::move(layers), options](int level) { return voxelizeLayersCpu(layers, level, options); };
}

// ---- 2. where the solid is -------------------------------------------------------------------------
namespace {

// Inclusive voxel bounds of the solid voxels.
struct VoxelBox {
  std::array<uint32_t, 3> lo{UINT32_MAX, UINT32_MAX, UINT32_MAX};
  std::array<uint32_t, 3> hi{0, 0, 0};
  bool empty() const { return lo[0] > hi[0]; }
  void add(uint32_t x, uint32_t y, uint32_t z) {
    const uint32_t p[3] = {x, y, z};
    for (size_t a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], p[a]);
      hi[a] = std::max(hi[a], p[a]);
    }
  }
};

VoxelBox solidBounds(const BrickVolume& volume) {
  VoxelBox box;
  volume.forEachBrick([&](const BrickView& b) {
    const uint32_t x0 = b.coord.x * DS_BRICK_DIM, y0 = b.coord.y * DS_BRICK_DIM, z0 = b.coord.z * DS_BRICK_DIM;
    if (b.uniform) {
      if (!solidVoxel(b.value)) return;
      box.add(x0, y0, z0);
      box.add(x0 + DS_BRICK_DIM - 1, y0 + DS_BRICK_DIM - 1, z0 + DS_BRICK_DIM - 1);
      return;
    }
    for (uint32_t z = 0; z < DS_BRICK_DIM; ++z)
      for (uint32_t y = 0; y < DS_BRICK_DIM; ++y)
        for (uint32_t x = 0; x < DS_BRICK_DIM; ++x)
          if (solidVoxel(b.voxels[layout::brickCoordToOffset(x, y, z)])) box.add(x0 + x, y0 + y, z0 + z);
  });
  return box;
}

// Topmost solid voxel of column (x, y); nullopt when the column holds none. Tiles skip 8 voxels.
std::optional<uint32_t> columnTop(const BrickVolume& volume, uint32_t x, uint32_t y) {
  constexpr uint32_t m = DS_BRICK_DIM - 1;
  for (uint32_t bz = volume.brickDim(); bz-- > 0;) {
    const BrickView b = volume.brick({x >> DS_BRICK_LOG2, y >> DS_BRICK_LOG2, bz});
    if (b.uniform) {
      if (solidVoxel(b.value)) return bz * DS_BRICK_DIM + m;
      continue;
    }
    for (uint32_t z = DS_BRICK_DIM; z-- > 0;)
      if (solidVoxel(b.voxels[layout::brickCoordToOffset(x & m, y & m, z)])) return bz * DS_BRICK_DIM + z;
  }
  return std::nullopt;
}

// Height of the topmost crossing of phi = 0.5 in column (x, y) [voxel units, voxel i spans [i, i+1)]:
// between the top solid voxel's centre and the centre above it, linearly, as marching cubes puts it.
std::optional<double> surfaceHeight(const BrickVolume& volume, uint32_t x, uint32_t y) {
  const std::optional<uint32_t> top = columnTop(volume, x, y);
  if (!top) return std::nullopt;
  const double below = double(voxelFill(volume.voxel(x, y, *top))) / DS_FILL_FULL;
  const double above = *top + 1 < volume.dim() ? double(voxelFill(volume.voxel(x, y, *top + 1))) / DS_FILL_FULL : 0.0;
  return double(*top) + 0.5 + (below - 0.5) / (below - above);
}

}  // namespace

Result<SurfacePart> surfacePart(const BrickVolume& volume, int divisor) {
  assert(divisor >= 1);
  const VoxelBox box = solidBounds(volume);
  if (box.empty()) return makeError("mesh bench", "the volume holds no solid voxel, so no surface to re-mesh");
  SurfacePart part;
  // The centre column, or the first column holding solid on square rings around it.
  const int64_t cx = (int64_t(box.lo[0]) + box.hi[0]) / 2, cy = (int64_t(box.lo[1]) + box.hi[1]) / 2;
  const int64_t dim = volume.dim();
  bool found = false;
  for (int64_t r = 0; r < dim && !found; ++r)
    for (int64_t y = cy - r; y <= cy + r && !found; ++y)
      for (int64_t x = cx - r; x <= cx + r && !found; ++x) {
        const bool on_ring = std::max(std::abs(x - cx), std::abs(y - cy)) == r;
        if (!on_ring || x < 0 || y < 0 || x >= dim || y >= dim) continue;
        if (const auto top = columnTop(volume, uint32_t(x), uint32_t(y))) {
          part.anchor = {uint32_t(x), uint32_t(y), *top};
          found = true;
        }
      }
  assert(found);  // the bounds hold a solid voxel, so some column does

  const uint32_t bd = volume.brickDim();
  part.side_voxels = std::max(1u, volume.dim() / uint32_t(divisor));
  part.side_bricks = std::min(bd, (part.side_voxels + DS_BRICK_DIM - 1) / DS_BRICK_DIM);
  // The cube's centre as near the anchor voxel's centre as whole bricks allow, inside the grid.
  uint32_t lo[3];
  for (size_t a = 0; a < 3; ++a) {
    const double start = (part.anchor[a] + 0.5 - 0.5 * DS_BRICK_DIM * part.side_bricks) / DS_BRICK_DIM;
    lo[a] = uint32_t(std::clamp(std::floor(start + 0.5), 0.0, double(bd - part.side_bricks)));
  }
  part.lo = {lo[0], lo[1], lo[2]};
  for (uint32_t z = 0; z < part.side_bricks; ++z)
    for (uint32_t y = 0; y < part.side_bricks; ++y)
      for (uint32_t x = 0; x < part.side_bricks; ++x) part.bricks.push_back({lo[0] + x, lo[1] + y, lo[2] + z});
  return part;
}

// ---- 3. Figure 15 rows -----------------------------------------------------------------------------

Result<MeshLevelRow> measureMeshLevel(const ToothVolume& tooth, const MeshBenchSettings& settings,
                                      const MeshRunner& runner) {
  assert(settings.repeats >= 1);
  MeshLevelRow row;
  row.level = tooth.frame.level;
  row.voxel_mm = tooth.frame.voxel_mm;
  row.dense_bricks = tooth.voxels.stats().dense_bricks;
  auto part = surfacePart(tooth.voxels, settings.part_divisor);
  if (!part) return part.error();
  row.part = std::move(part).value();

  for (const int normals : settings.normal_modes) {
    ModeTiming m;
    m.normals = normals;
    // Full surface; the last full run is also the surface the part updates start from.
    if (settings.warmup)
      if (auto warm = runner.full(tooth, normals); !warm) return warm.error();
    std::vector<double> kernels;
    for (int i = 0; i < settings.repeats; ++i) {
      auto t = runner.full(tooth, normals);
      if (!t) return t.error();
      m.full_runs_ms.push_back(t->ms);
      kernels.push_back(t->kernel_ms);
      m.triangles = t->triangles;
      m.full_blocks = t->blocks_meshed;
    }
    m.full_ms = median(m.full_runs_ms);
    m.full_kernel_ms = median(kernels);

    // The part: its bricks named dirty on an unchanged volume, so every run does the same work.
    const std::span<const BrickCoord> dirty(row.part.bricks);
    if (settings.warmup)
      if (auto warm = runner.update(tooth, dirty, normals); !warm) return warm.error();
    kernels.clear();
    for (int i = 0; i < settings.repeats; ++i) {
      auto t = runner.update(tooth, dirty, normals);
      if (!t) return t.error();
      m.part_runs_ms.push_back(t->ms);
      kernels.push_back(t->kernel_ms);
      m.part_blocks = t->blocks_meshed;
    }
    m.part_ms = median(m.part_runs_ms);
    m.part_kernel_ms = median(kernels);
    row.modes.push_back(std::move(m));
  }

  if (settings.peers) {
    row.vtk = vtkFlyingEdges(tooth.voxels, Material::Empty, settings.repeats);
  } else {
    row.vtk.name = "VTK vtkFlyingEdges3D";
    row.vtk.skipped = "not run (--no-peers)";
  }
  if (row.vtk.available && row.vtk.ms > 0.0)
    for (ModeTiming& m : row.modes) m.vtk_ratio = m.full_ms / row.vtk.ms;
  return row;
}

// ---- 4. the bur path -------------------------------------------------------------------------------

Result<std::vector<Vec3d>> burPath(const ToothVolume& tooth, const BurPathSettings& s) {
  assert(s.frames >= 1 && s.fps > 0.0 && s.speed_mm_s > 0.0 && s.diameter_mm > 0.0);
  assert(s.span > 0.0 && s.span <= 1.0);
  const BrickVolume& volume = tooth.voxels;
  const VolumeFrame& f = tooth.frame;
  const double h = f.voxel_mm;
  const VoxelBox box = solidBounds(volume);
  if (box.empty()) return makeError("bur path", "the volume holds no solid voxel");

  // The line: the middle of the solid in y, the middle `span` of its extent in x.
  const uint32_t y = (box.lo[1] + box.hi[1]) / 2;
  const double x_lo = f.origin_mm[0] + box.lo[0] * h, x_hi = f.origin_mm[0] + (box.hi[0] + 1.0) * h;
  const double length = s.span * (x_hi - x_lo);
  const double x_start = 0.5 * (x_lo + x_hi) - 0.5 * length;

  // The original surface per column, read once as footprints need it [voxels]; -inf: no solid.
  const uint32_t dim = volume.dim();
  std::unordered_map<uint64_t, double> heights;
  auto height = [&](uint32_t x, uint32_t y_col) {
    const uint64_t key = uint64_t(y_col) * dim + x;
    if (const auto it = heights.find(key); it != heights.end()) return it->second;
    const double v = surfaceHeight(volume, x, y_col).value_or(-HUGE_VAL);
    heights.emplace(key, v);
    return v;
  };
  // Where the ball comes to rest on the original surface [voxels]: the highest centre over the
  // columns under its disc, each column's top touching the ball's lower half; none over empty columns.
  const double radius = 0.5 * s.diameter_mm, r = radius / h;
  auto restingZ = [&](double cx, double cy) -> std::optional<double> {
    std::optional<double> best;
    const auto lo_x = int64_t(std::floor(cx - r)), hi_x = int64_t(std::ceil(cx + r));
    const auto lo_y = int64_t(std::floor(cy - r)), hi_y = int64_t(std::ceil(cy + r));
    for (int64_t j = std::max<int64_t>(lo_y, 0); j <= std::min<int64_t>(hi_y, dim - 1); ++j)
      for (int64_t i = std::max<int64_t>(lo_x, 0); i <= std::min<int64_t>(hi_x, dim - 1); ++i) {
        const double dx = double(i) + 0.5 - cx, dy = double(j) + 0.5 - cy, d2 = dx * dx + dy * dy;
        if (d2 > r * r) continue;
        const double top = height(uint32_t(i), uint32_t(j));
        if (top == -HUGE_VAL) continue;
        const double z = top + std::sqrt(r * r - d2);
        if (!best || z > *best) best = z;
      }
    return best;
  };

  const double y_mm = f.origin_mm[1] + (y + 0.5) * h;
  std::vector<Vec3d> path;
  std::vector<std::optional<double>> rest;
  std::vector<int> passes;
  for (int k = 0; k < s.frames; ++k) {
    const double travelled = s.speed_mm_s * k / s.fps;
    const int pass = int(std::floor(travelled / length));
    const double along = travelled - pass * length;
    const double x = pass % 2 == 0 ? x_start + along : x_start + length - along;
    path.push_back({x, y_mm, 0.0});
    rest.push_back(restingZ((x - f.origin_mm[0]) / h, y + 0.5));
    passes.push_back(pass);
  }
  // Over a hole in the solid the ball keeps the height of the nearest frame that had ground under it.
  for (size_t k = 0; k < path.size(); ++k) {
    std::optional<double> z = rest[k];
    for (size_t d = 1; !z && d < path.size(); ++d) {
      if (k >= d && rest[k - d]) z = rest[k - d];
      else if (k + d < path.size() && rest[k + d]) z = rest[k + d];
    }
    if (!z) return makeError("bur path", "no solid under the path along y = " + std::to_string(y_mm) + " mm");
    path[k][2] = f.origin_mm[2] + *z * h - s.depth_mm * (passes[k] + 1);
  }
  return path;
}

Result<BurPathResult> measureBurPath(ToothVolume tooth, const BurPathSettings& settings, const MeshRunner& runner) {
  auto path = burPath(tooth, settings);
  if (!path) return path.error();
  BurPathResult r;
  r.settings = settings;
  r.voxel_mm = tooth.frame.voxel_mm;
  auto built = runner.full(tooth, settings.normals);
  if (!built) return built.error();
  uint64_t triangles = built->triangles;

  for (const Vec3d& centre : *path) {
    BurFrame fr;
    fr.centre_mm = centre;
    const auto start = std::chrono::steady_clock::now();
    const EditResult edit = carveBall(tooth.voxels, tooth.frame, centre, 0.5 * settings.diameter_mm);
    fr.carve_ms = msSince(start);
    fr.dirty_bricks = uint32_t(edit.dirty.size());
    fr.voxels_changed = edit.voxels_changed;
    fr.removed_mm3 = edit.removed_mm3;
    // A frame that changed nothing has nothing to re-mesh; the simulator would not call the mesher.
    if (!edit.dirty.empty()) {
      auto t = runner.update(tooth, edit.dirty, settings.normals);
      if (!t) return t.error();
      fr.update_ms = t->ms;
      fr.kernel_ms = t->kernel_ms;
      fr.blocks_meshed = t->blocks_meshed;
      triangles = t->triangles;
      ++r.frames_cut;
    }
    fr.triangles = triangles;
    r.frames.push_back(fr);
  }

  std::vector<double> update_ms;
  for (const BurFrame& fr : r.frames) {
    update_ms.push_back(fr.update_ms);
    r.mean_dirty_bricks += fr.dirty_bricks;
    r.max_dirty_bricks = std::max(r.max_dirty_bricks, double(fr.dirty_bricks));
    r.mean_blocks += double(fr.blocks_meshed);
    r.mean_carve_ms += fr.carve_ms;
    r.removed_mm3 += fr.removed_mm3;
  }
  const double n = double(r.frames.size());
  r.mean_dirty_bricks /= n;
  r.mean_blocks /= n;
  r.mean_carve_ms /= n;
  r.p50_ms = percentile(update_ms, 50.0);
  r.p95_ms = percentile(update_ms, 95.0);
  r.max_ms = percentile(update_ms, 100.0);
  r.meets_target = r.p95_ms < settings.target_p95_ms;
  return r;
}

// ---- 5. normal errors ------------------------------------------------------------------------------

Result<NormalErrorRow> measureNormalError(const ToothVolume& tooth, const AnalyticSolid& solid, int normals) {
  const std::optional<NormalMode> mode = normalModeFromNeighbours(normals);
  if (!mode) return makeError("bench mesh", "no normal mode of " + std::to_string(normals) + " voxels");
  SurfaceOptions options;
  options.normals = *mode;
  auto mesh = meshVolumeCpu(tooth, options);
  if (!mesh) return mesh.error();
  NormalErrorRow row;
  row.solid = solid.describe();
  row.level = tooth.frame.level;
  row.normals = normals;
  row.vertices = mesh->positions.size();
  row.triangles = mesh->triangleCount();
  if (mesh->positions.empty()) return makeError("normal errors", row.solid + ": the mesh is empty");
  std::vector<double> angles;
  angles.reserve(mesh->positions.size());
  for (size_t i = 0; i < mesh->positions.size(); ++i) {
    Vec3d p;
    for (size_t a = 0; a < 3; ++a) p[a] = (double(mesh->positions[i][a]) - tooth.frame.origin_mm[a]) / tooth.frame.voxel_mm;
    const Vec3d truth = solid.normal(p);
    double dot = 0.0;
    for (size_t a = 0; a < 3; ++a) dot += truth[a] * double(mesh->normals[i][a]);
    angles.push_back(std::acos(std::clamp(dot, -1.0, 1.0)) * 180.0 / std::numbers::pi);
  }
  double sum = 0.0;
  for (double a : angles) sum += a;
  row.mean_deg = sum / double(angles.size());
  row.p95_deg = percentile(angles, 95.0);
  row.max_deg = percentile(std::move(angles), 100.0);
  return row;
}

Result<std::vector<NormalErrorRow>> measureNormalErrors(const NormalsSettings& settings) {
  std::vector<NormalErrorRow> rows;
  for (AnalyticSolid (*make)(int) : {&sphereForLevel, &torusForLevel})
    for (const int level : settings.levels) {
      const AnalyticSolid solid = make(level);
      const ToothVolume tooth = analyticTooth(solid, level, Material::Enamel, settings.samples);
      for (const int normals : settings.normal_modes) {
        auto row = measureNormalError(tooth, solid, normals);
        if (!row) return row.error();
        rows.push_back(std::move(row).value());
      }
    }
  return rows;
}

// ---- 6. the whole run ------------------------------------------------------------------------------
namespace {

// 1234567 -> "1,234,567", as docs/PERFORMANCE.md writes counts.
std::string grouped(uint64_t v) {
  const std::string digits = std::to_string(v);
  std::string out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string levelLine(const MeshLevelRow& row) {
  std::ostringstream o;
  o << "level " << row.level << " (" << formatted("%.4f", row.voxel_mm) << " mm voxels, part of " << row.part.bricks.size()
    << " bricks):";
  for (const ModeTiming& m : row.modes)
    o << " " << m.normals << " normals full " << formatted("%.1f", m.full_ms) << " ms (" << grouped(m.triangles)
      << " triangles), part " << formatted("%.2f", m.part_ms) << " ms;";
  if (row.vtk.available)
    o << " " << row.vtk.name << " " << formatted("%.1f", row.vtk.ms) << " ms (" << grouped(row.vtk.triangles) << " triangles)";
  else
    o << " " << row.vtk.name << ": " << row.vtk.skipped;
  return o.str();
}

std::string burLine(const BurPathResult& b) {
  std::ostringstream o;
  o << "bur path: " << b.frames.size() << " frames at level " << b.settings.level << " with " << b.settings.normals
    << " normals: re-mesh p50 " << formatted("%.2f", b.p50_ms) << " ms, p95 " << formatted("%.2f", b.p95_ms) << " ms (target "
    << formatted("%g", b.settings.target_p95_ms) << " ms: " << (b.meets_target ? "met" : "missed") << "), max "
    << formatted("%.2f", b.max_ms) << " ms; " << formatted("%.1f", b.mean_dirty_bricks) << " dirty bricks and "
    << formatted("%.1f", b.mean_blocks) << " blocks per frame";
  return o.str();
}

}  // namespace

Result<MeshReport> runMeshBench(const MeshBenchSettings& settings, const VolumeMaker& make_volume,
                                const MeshRunner& runner, const std::function<void(const std::string&)>& log) {
  auto say = [&](const std::string& line) {
    if (log) log(line);
  };
  MeshReport report;
  report.mesher = runner.mesher.empty() ? "?" : runner.mesher;
  std::optional<ToothVolume> bur_tooth;
  for (const int level : settings.levels) {
    auto tooth = make_volume(level);
    if (!tooth) return tooth.error();
    auto row = measureMeshLevel(*tooth, settings, runner);
    if (!row) return row.error();
    say(levelLine(*row));
    report.levels.push_back(std::move(row).value());
    if (settings.bur && level == settings.bur_path.level) bur_tooth = std::move(tooth).value();
  }
  if (settings.bur) {
    if (!bur_tooth) {
      auto tooth = make_volume(settings.bur_path.level);
      if (!tooth) return tooth.error();
      bur_tooth = std::move(tooth).value();
    }
    auto bur = measureBurPath(std::move(*bur_tooth), settings.bur_path, runner);
    if (!bur) return bur.error();
    report.bur = std::move(bur).value();
    report.has_bur = true;
    say(burLine(report.bur));
  }
  if (settings.normal_errors) {
    auto rows = measureNormalErrors(settings.normals);
    if (!rows) return rows.error();
    report.normals = std::move(rows).value();
    for (const NormalErrorRow& r : report.normals)
      say(r.solid + " level " + std::to_string(r.level) + ", " + std::to_string(r.normals) + " normals: mean " +
          formatted("%.3f", r.mean_deg) + " deg, p95 " + formatted("%.3f", r.p95_deg) + " deg");
  }
  return report;
}

// ---- 7. JSON ---------------------------------------------------------------------------------------
namespace {

nlohmann::json vtkJson(const PeerMesh& p) {
  return {{"available", p.available}, {"name", p.name},           {"skipped", p.skipped},
          {"threads", p.threads},     {"image_bytes", p.image_bytes}, {"image_ms", p.image_ms},
          {"ms", p.ms},               {"runs_ms", p.runs_ms},     {"triangles", p.triangles},
          {"points", p.points}};
}

nlohmann::json brickJson(const BrickCoord& c) { return nlohmann::json::array({c.x, c.y, c.z}); }

// The level-10 goal: dentsim's full re-mesh faster than Flying Edges on the same voxels, per mode.
nlohmann::json vtkGoalJson(const MeshReport& report) {
  for (const MeshLevelRow& row : report.levels) {
    if (row.level != 10 || !row.vtk.available) continue;
    nlohmann::json per_mode = nlohmann::json::object();
    for (const ModeTiming& m : row.modes) per_mode[std::to_string(m.normals)] = m.full_ms < row.vtk.ms;
    return per_mode;
  }
  return nullptr;
}

}  // namespace

nlohmann::json meshReportJson(const MeshReportInfo& info, const MeshReport& report) {
  const MeshBenchSettings& s = info.settings;
  nlohmann::json levels = nlohmann::json::array();
  for (const MeshLevelRow& row : report.levels) {
    nlohmann::json modes = nlohmann::json::array();
    for (const ModeTiming& m : row.modes)
      modes.push_back({{"normals", m.normals},
                       {"full", {{"ms", m.full_ms},
                                 {"runs_ms", m.full_runs_ms},
                                 {"kernel_ms", m.full_kernel_ms},
                                 {"triangles", m.triangles},
                                 {"blocks", m.full_blocks}}},
                       {"part", {{"ms", m.part_ms},
                                 {"runs_ms", m.part_runs_ms},
                                 {"kernel_ms", m.part_kernel_ms},
                                 {"blocks", m.part_blocks}}},
                       {"ratio_over_vtk", m.vtk_ratio}});
    levels.push_back({{"level", row.level},
                      {"voxel_mm", row.voxel_mm},
                      {"dense_bricks", row.dense_bricks},
                      {"part", {{"anchor_voxel", row.part.anchor},
                                {"side_voxels", row.part.side_voxels},
                                {"side_bricks", row.part.side_bricks},
                                {"lo_brick", brickJson(row.part.lo)},
                                {"bricks", row.part.bricks.size()}}},
                      {"modes", modes},
                      {"vtk", vtkJson(row.vtk)}});
  }

  nlohmann::json bur = nullptr;
  if (report.has_bur) {
    const BurPathResult& b = report.bur;
    nlohmann::json frames = nlohmann::json::array();
    for (const BurFrame& f : b.frames)
      frames.push_back({{"centre_mm", f.centre_mm},
                        {"carve_ms", f.carve_ms},
                        {"update_ms", f.update_ms},
                        {"kernel_ms", f.kernel_ms},
                        {"dirty_bricks", f.dirty_bricks},
                        {"blocks", f.blocks_meshed},
                        {"voxels_changed", f.voxels_changed},
                        {"removed_mm3", f.removed_mm3},
                        {"triangles", f.triangles}});
    bur = {{"level", b.settings.level},
           {"voxel_mm", b.voxel_mm},
           {"normals", b.settings.normals},
           {"frames", b.settings.frames},
           {"fps", b.settings.fps},
           {"speed_mm_s", b.settings.speed_mm_s},
           {"diameter_mm", b.settings.diameter_mm},
           {"depth_mm", b.settings.depth_mm},
           {"span", b.settings.span},
           {"target_p95_ms", b.settings.target_p95_ms},
           {"frames_cut", b.frames_cut},
           {"p50_ms", b.p50_ms},
           {"p95_ms", b.p95_ms},
           {"max_ms", b.max_ms},
           {"mean_dirty_bricks", b.mean_dirty_bricks},
           {"max_dirty_bricks", b.max_dirty_bricks},
           {"mean_blocks", b.mean_blocks},
           {"mean_carve_ms", b.mean_carve_ms},
           {"removed_mm3", b.removed_mm3},
           {"meets_target", b.meets_target},
           {"per_frame", frames}};
  }

  nlohmann::json normals = nlohmann::json::array();
  for (const NormalErrorRow& r : report.normals)
    normals.push_back({{"solid", r.solid},
                       {"level", r.level},
                       {"normals", r.normals},
                       {"vertices", r.vertices},
                       {"triangles", r.triangles},
                       {"mean_deg", r.mean_deg},
                       {"p95_deg", r.p95_deg},
                       {"max_deg", r.max_deg}});

  return {{"benchmark", "mesh"},
          {"model", info.model},
          {"command", info.command},
          {"runner", info.runner},
          {"mesher", report.mesher},
          {"machine", {{"cpu", info.cpu}, {"cpu_threads", info.cpu_threads}, {"device", info.device}}},
          {"settings", {{"levels", s.levels},
                        {"normal_modes", s.normal_modes},
                        {"repeats", s.repeats},
                        {"warmup_runs", s.warmup ? 1 : 0},
                        {"statistic", "median"},
                        {"part_divisor", s.part_divisor},
                        {"peers", s.peers},
                        {"normals_levels", s.normals.levels},
                        {"coverage_samples", s.normals.samples}}},
          {"figure15", levels},
          {"bur_path", bur},
          {"normal_errors", normals},
          {"goals", {{"bur_p95_under_ms", s.bur_path.target_p95_ms},
                     {"bur_p95_met", report.has_bur ? nlohmann::json(report.bur.meets_target) : nlohmann::json()},
                     {"level10_full_faster_than_vtk", vtkGoalJson(report)}}}};
}

// ---- 8. Markdown -----------------------------------------------------------------------------------
namespace {

void figure15Markdown(std::ostringstream& o, const MeshReport& report) {
  o << "### Re-meshing time (paper Figure 15)\n\n"
    << "| mesher | level | voxel [mm] | normals | full [ms] | GPU kernels [ms] | part [ms] | part kernels [ms] | "
       "part bricks | triangles | VTK FE [ms] | dentsim / VTK |\n|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  // Kernel times exist for the compute kernel only; the CPU meshers have none to show.
  const bool kernels = report.mesher == "gpu";
  for (const MeshLevelRow& row : report.levels)
    for (const ModeTiming& m : row.modes)
      o << "| " << report.mesher << " | " << row.level << " | " << formatted("%.4f", row.voxel_mm) << " | " << m.normals << " | "
        << formatted("%.1f", m.full_ms) << " | " << (kernels ? formatted("%.1f", m.full_kernel_ms) : "n/a") << " | "
        << formatted("%.2f", m.part_ms) << " | " << (kernels ? formatted("%.2f", m.part_kernel_ms) : "n/a") << " | " << row.part.bricks.size() << " | " << grouped(m.triangles) << " | "
        << (row.vtk.available ? formatted("%.1f", row.vtk.ms) : "n/a") << " | "
        << (row.vtk.available ? formatted("%.2f", m.vtk_ratio) : "n/a") << " |\n";

  o << "\nVTK Flying Edges per level: one surface with its own normals, on the same voxels.\n\n"
    << "| level | VTK FE [ms] | image copy [ms] | image [MiB] | triangles | points | note |\n"
       "|---|---|---|---|---|---|---|\n";
  for (const MeshLevelRow& row : report.levels) {
    const PeerMesh& v = row.vtk;
    o << "| " << row.level << " | " << (v.available ? formatted("%.1f", v.ms) : "n/a") << " | "
      << (v.available ? formatted("%.1f", v.image_ms) : "n/a") << " | " << formatted("%.0f", double(v.image_bytes) / (1 << 20))
      << " | " << (v.available ? grouped(v.triangles) : "n/a") << " | " << (v.available ? grouped(v.points) : "n/a")
      << " | " << (v.available ? "" : v.skipped) << " |\n";
  }
}

void burMarkdown(std::ostringstream& o, const std::string& mesher, const BurPathResult& b) {
  const BurPathSettings& p = b.settings;
  o << "### One frame of drilling: re-mesh of the dirty bricks\n\n"
    << "A " << formatted("%g", p.diameter_mm) << " mm ball moving at " << formatted("%g", p.speed_mm_s) << " mm/s, "
    << formatted("%g", p.fps) << " frames/s (" << formatted("%.3f", p.speed_mm_s / p.fps) << " mm a frame), back and forth along x "
    << "over the middle " << formatted("%g", p.span * 100) << "% of the tooth through its centre in y, resting on the "
    << "original surface and sunk " << formatted("%g", p.depth_mm) << " mm into it per pass; level " << p.level << " ("
    << formatted("%.4f", b.voxel_mm) << " mm voxels), " << p.normals << " normals. Each frame: carveBall on the CPU "
    << "bricks, then an update of the bricks it changed. Frames that changed nothing count as 0 ms.\n\n"
    << "| mesher | frames | frames cut | p50 [ms] | p95 [ms] | max [ms] | target p95 [ms] | met | dirty bricks / "
       "frame (mean, max) | blocks / frame | carve [ms] | removed [mm^3] |\n"
       "|---|---|---|---|---|---|---|---|---|---|---|---|\n"
    << "| " << mesher << " | " << b.frames.size() << " | " << b.frames_cut << " | " << formatted("%.2f", b.p50_ms) << " | "
    << formatted("%.2f", b.p95_ms) << " | " << formatted("%.2f", b.max_ms) << " | " << formatted("%g", p.target_p95_ms) << " | "
    << (b.meets_target ? "yes" : "no") << " | " << formatted("%.1f", b.mean_dirty_bricks) << ", "
    << formatted("%.0f", b.max_dirty_bricks) << " | " << formatted("%.1f", b.mean_blocks) << " | " << formatted("%.3f", b.mean_carve_ms)
    << " | " << formatted("%.3f", b.removed_mm3) << " |\n";
}

void normalsMarkdown(std::ostringstream& o, const NormalsSettings& s, const std::vector<NormalErrorRow>& rows) {
  o << "### Normal accuracy (CPU reference mesher)\n\n"
    << "Angle between each vertex normal and the analytic normal at the vertex, for solids voxelized by coverage ("
    << s.samples << "^3 samples per voxel, fill rounded to 1/31); sizes in voxels. Mean / 95th percentile [deg].\n\n"
    << "| solid | level | vertices |";
  for (int n : s.normal_modes) o << " " << n << " [deg] |";
  o << " ordered |\n|---|---|---|";
  for (size_t i = 0; i < s.normal_modes.size(); ++i) o << "---|";
  o << "---|\n";
  // Rows come grouped by solid and level, one per mode in settings order; "ordered": each wider
  // neighbourhood has the lower mean error.
  for (size_t i = 0; i < rows.size();) {
    size_t j = i;
    while (j < rows.size() && rows[j].solid == rows[i].solid && rows[j].level == rows[i].level) ++j;
    o << "| " << rows[i].solid << " | " << rows[i].level << " | " << grouped(rows[i].vertices) << " |";
    bool ordered = true;
    for (size_t k = i; k < j; ++k) {
      o << " " << formatted("%.3f", rows[k].mean_deg) << " / " << formatted("%.3f", rows[k].p95_deg) << " |";
      if (k > i) ordered = ordered && rows[k].mean_deg < rows[k - 1].mean_deg;
    }
    o << " " << (ordered ? "yes" : "no") << " |\n";
    i = j;
  }
}

}  // namespace

std::string meshReportMarkdown(const MeshReportInfo& info, const MeshReport& report) {
  std::ostringstream o;
  const MeshBenchSettings& s = info.settings;
  std::string peer = "VTK not run";
  int peer_threads = 0;
  for (const MeshLevelRow& row : report.levels)
    if (row.vtk.available) {
      peer = row.vtk.name;
      peer_threads = row.vtk.threads;
      break;
    } else if (!row.vtk.skipped.empty()) {
      peer = row.vtk.name + ": " + row.vtk.skipped;
    }
  o << "Model: " << info.model << ". dentsim: " << info.runner << " on " << info.device << "; " << peer;
  if (peer_threads > 0) o << " on " << peer_threads << " threads";
  o << "; CPU " << info.cpu << ", " << info.cpu_threads << " hardware threads. Each time is the median of "
    << s.repeats << (s.repeats == 1 ? " run" : " runs") << (s.warmup ? ", after one untimed run" : "")
    << ", by the host clock. Full: the whole surface meshed from the volume. Part: an update naming dirty the bricks "
       "of a cube of side dim/"
    << s.part_divisor
    << " voxels (whole bricks) around the topmost solid voxel of the column through the centre of the tooth's "
       "bounds, on an unchanged volume. VTK: vtkFlyingEdges3D on the voxels copied into a dense 8-bit image "
       "(fill 0..31, contour 15.5 = phi 0.5, gradient normals), the filter's Update() alone; copying the image "
       "is listed apart.\n\n";
  if (!info.command.empty()) o << "Command: `" << info.command << "`\n\n";
  if (!report.levels.empty()) figure15Markdown(o, report);
  if (report.has_bur) {
    o << "\n";
    burMarkdown(o, report.mesher, report.bur);
  }
  if (!report.normals.empty()) {
    o << "\n";
    normalsMarkdown(o, s.normals, report.normals);
  }
  return o.str();
}

// ---- 9. SVG and files ------------------------------------------------------------------------------

std::string meshReportSvg(const MeshReport& report) {
  std::vector<int> modes;
  for (const MeshLevelRow& row : report.levels)
    for (const ModeTiming& m : row.modes)
      if (std::find(modes.begin(), modes.end(), m.normals) == modes.end()) modes.push_back(m.normals);
  std::vector<PlotSeries> series;
  for (size_t i = 0; i < modes.size(); ++i) {
    PlotSeries full{"full, " + std::to_string(modes[i]) + " normals", {}, int(i), ""};
    PlotSeries part{"part, " + std::to_string(modes[i]) + " normals", {}, int(i), "7,4"};
    for (const MeshLevelRow& row : report.levels)
      for (const ModeTiming& m : row.modes) {
        if (m.normals != modes[i]) continue;
        full.points.emplace_back(double(row.level), m.full_ms);
        part.points.emplace_back(double(row.level), m.part_ms);
      }
    series.push_back(std::move(full));
    series.push_back(std::move(part));
  }
  PlotSeries vtk{"VTK Flying Edges", {}, int(modes.size()), "2,3"};
  for (const MeshLevelRow& row : report.levels)
    if (row.vtk.available) vtk.points.emplace_back(double(row.level), row.vtk.ms);
  if (!vtk.points.empty()) series.push_back(std::move(vtk));
  return svgLinePlot("Re-meshing the molar: full surface and a 1/32^3 part", "octree level (grid 2^L per side)",
                     "time [ms] (log)", series, /*log_y=*/true);
}

std::string burPathSvg(const BurPathResult& bur) {
  // The distribution rather than the time line: a dozen x ticks read better than one per frame.
  std::vector<double> update_ms, carve_ms;
  for (const BurFrame& f : bur.frames) {
    update_ms.push_back(f.update_ms);
    carve_ms.push_back(f.carve_ms);
  }
  PlotSeries remesh{"re-mesh", {}, 0, ""};
  PlotSeries carve{"carve (CPU)", {}, 2, "7,4"};
  PlotSeries target{"target p95", {}, 1, "2,3"};
  if (!update_ms.empty())
    for (double p : {0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 90.0, 95.0, 100.0}) {
      remesh.points.emplace_back(p, percentile(update_ms, p));
      carve.points.emplace_back(p, percentile(carve_ms, p));
    }
  target.points = {{0.0, bur.settings.target_p95_ms}, {100.0, bur.settings.target_p95_ms}};
  return svgLinePlot("Per-frame re-mesh along the bur path, level " + std::to_string(bur.settings.level) + ", " +
                         std::to_string(bur.settings.normals) + " normals",
                     "percentile of frames", "time [ms]", {remesh, carve, target}, /*log_y=*/false);
}

Status writeMeshReport(const std::string& dir, const MeshReportInfo& info, const MeshReport& report) {
  std::vector<std::pair<std::string, std::string>> files{
      {"mesh.json", meshReportJson(info, report).dump(2) + "\n"},
      {"mesh.md", meshReportMarkdown(info, report)},
      {"mesh.svg", meshReportSvg(report)}};
  if (report.has_bur) files.emplace_back("mesh_bur.svg", burPathSvg(report.bur));
  for (const auto& [name, text] : files) {
    const auto* bytes = reinterpret_cast<const uint8_t*>(text.data());
    if (auto s = writeFileAtomic(dir + "/" + name, std::span<const uint8_t>(bytes, text.size())); !s) return s;
  }
  return Ok{};
}

}  // namespace dentsim::bench
