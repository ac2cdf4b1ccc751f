// The steps from STL layers, a label volume or a scan to a tooth volume in its frame (volume/tooth_builder.h).
//
// Contents
//   1. Shared helpers
//   2. buildToothFromMeshes (and the pulp from a scan of the same tooth)
//   3. buildToothFromLabels
//   4. buildToothFromScan and buildToothFromGreyImage
#include "volume/tooth_builder.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <utility>
#include <vector>

#include "core/text_escape.h"
#include "io/grey_volume_file.h"
#include "io/mesh_units.h"
#include "io/obj_file.h"
#include "io/ply_file.h"
#include "io/stl_file.h"
#include "volume/tooth_sanity.h"

namespace dentsim {
namespace {

// ---- 1. Shared helpers ------------------------------------------------------------------------
void warnVia(const ToothBuildHooks& hooks, const std::string& line) {
  if (hooks.warn) hooks.warn(line);
}

Interrupter& progressOf(const ToothBuildHooks& hooks) { return hooks.progress ? *hooks.progress : nullInterrupter(); }

// A grey value with its unit, as the scan's lines print it.
std::string greyValue(double v, GreyUnit unit) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.6g %s", v, greyUnitName(unit));
  return buf;
}

// ---- 2. Meshes --------------------------------------------------------------------------------
struct LoadedLayer {
  std::string path;
  Material material = Material::Dentin;
  TriangleMesh mesh;
  double volume_mm3 = 0.0;
};

struct ReadMesh {
  TriangleMesh mesh;      // welded, in the file's units
  MeshTopology topology;
};

// An indexed mesh welded as the STL reader welds its own, and its topology.
ReadMesh welded(TriangleMesh mesh) {
  ReadMesh read{std::move(mesh), {}};
  weldVertices(read.mesh);
  read.topology = analyzeTopology(read.mesh);
  return read;
}

// A closed surface from an STL, or a PLY or OBJ when the name says so (a tooth library's or a CBCT
// segmentation's export).
Result<ReadMesh> readMeshFile(const std::string& path) {
  std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : std::string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".ply") {
    auto ply = readPly(path);
    if (!ply) return ply.error();
    return welded(std::move(ply->mesh));
  }
  if (ext == ".obj") {
    auto obj = readObj(path);
    if (!obj) return obj.error();
    return welded(std::move(obj->mesh));
  }
  auto stl = readStl(path);
  if (!stl) return stl.error();
  return ReadMesh{std::move(stl->mesh), stl->info.topology};
}

// Reads one layer and converts it to mm. What is wrong with the mesh is a warning, since the
// voxelizer copes (a leaky ray borrows from a closed one); only an unreadable file is an error.
Result<LoadedLayer> loadLayer(const MeshLayerSource& source, double mm_per_unit, const ToothBuildHooks& hooks) {
  auto read = readMeshFile(source.path);
  if (!read) return read.error();
  LoadedLayer layer{source.path, source.material, std::move(read->mesh), 0.0};
  layer.mesh.scale(mm_per_unit);
  const MeshTopology& topo = read->topology;
  const std::string shown = shownPath(source.path);  // a file name in a warning could drive the terminal
  if (topo.open_edges > 0)
    warnVia(hooks, shown + ": " + std::to_string(topo.open_edges) +
                       " open edges (holes); rays through a hole borrow the layer from the nearest ray that is closed");
  if (topo.nonmanifold_edges > 0)
    warnVia(hooks, shown + ": " + std::to_string(topo.nonmanifold_edges) + " non-manifold edges");
  if (!topo.consistent())
    warnVia(hooks, shown + ": " + std::to_string(topo.flipped_edges) +
                       " edges with inconsistent winding; the inside is taken by winding number");
  else if (topo.signed_volume_mm3 < 0.0)
    warnVia(hooks, shown + ": the mesh is inside out (negative volume); it is filled all the same");
  if (std::string w = toothExtentWarning(layer.mesh.bounds(), source.path); !w.empty())
    warnVia(hooks, escapeControl(w, w.size()));
  layer.volume_mm3 = std::abs(layer.mesh.signedVolume());
  return layer;
}

// True when the bounds lie within the frame's grid box (to a thousandth of a voxel).
bool gridHolds(const VolumeFrame& f, const Bounds3& bounds) {
  const double side = double(f.dim()) * f.voxel_mm;
  const double slack = 1e-3 * f.voxel_mm;
  for (int a = 0; a < 3; ++a)
    if (bounds.lo[a] < f.origin_mm[a] - slack || bounds.hi[a] > f.origin_mm[a] + side + slack) return false;
  return true;
}

// The reference grid was turned to stand its tooth up: the meshes turn the same way about its
// centre, so they land where its voxels did. Returns the turned meshes' bounds.
Bounds3 turnLikeReference(const VolumeFrame& reference, std::vector<LoadedLayer>& loaded) {
  const double half = 0.5 * double(reference.dim()) * reference.voxel_mm;
  const Vec3 centre{reference.origin_mm[0] + half, reference.origin_mm[1] + half, reference.origin_mm[2] + half};
  Bounds3 bounds;
  for (LoadedLayer& l : loaded) {
    for (Vec3f& p : l.mesh.positions) {
      const Vec3 q = turned(reference.tooth.turn, Vec3{p[0], p[1], p[2]} - centre) + centre;
      p = Vec3f{float(q.x), float(q.y), float(q.z)};
    }
    bounds.add(l.mesh.bounds());
  }
  return bounds;
}


// The plan of a voxelization followed by synthesis: the synthesis runs after the rays are freed, so
// the peak is the larger of the two, and the times add.
VoxelizeCost withSynthesis(VoxelizeCost cost, const Bounds3& tooth, double voxel_mm) {
  double voxels = 1.0;
  for (int a = 0; a < 3; ++a) voxels *= std::ceil((tooth.hi[a] - tooth.lo[a]) / voxel_mm) + 2.0;
  cost.memory_bytes = std::max(cost.memory_bytes, uint64_t(voxels * kLayerSynthBytesPerBoxVoxel));
  cost.seconds += voxels * kLayerSynthSecondsPerBoxVoxel;
  return cost;
}

// All neighbours as one mesh: one layer for the voxelizer, whose four priority slots are the
// treated tooth's tissues. It is voxelized as enamel and relabelled in addNeighbours.
TriangleMesh joinedMesh(const std::vector<LoadedLayer>& meshes) {
  TriangleMesh all;
  for (const LoadedLayer& l : meshes) {
    const uint32_t base = uint32_t(all.positions.size());
    all.positions.insert(all.positions.end(), l.mesh.positions.begin(), l.mesh.positions.end());
    for (const auto& t : l.mesh.triangles) all.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  }
  return all;
}

// The synthesizer's report into the tooth: its provenance and its lines, for `info` and the window.
void recordSynthesis(ToothVolume& tooth, const LayerSynthReport& synth) {
  tooth.layers = LayerSource::Synthesized;
  tooth.synthesized_type = uint8_t(synth.type);
  for (size_t i = 0; i < synth.lines.size(); ++i)
    tooth.source_note += (i || !tooth.source_note.empty() ? "\n" : "") + synth.lines[i];
}

// ---- Pulp from a scan of the same tooth ----------------------------------------------------------
// The scan named by pulp_from: a folder is a DICOM series, a file NIfTI or NRRD. A file's read is
// planned as voxelize plans a scan's; the DICOM reader asks again in its checking child, where a plan
// line would print twice, so it keeps to its own budget.
Result<GreyImage> readPulpScan(const std::string& path, const ToothBuildHooks& hooks) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return readDicomSeries(path, DicomReadOptions{}, progressOf(hooks));
  ScanReadApproval approve;
  if (hooks.approve)
    approve = [&hooks](uint64_t voxels, uint32_t stored_bytes) { return hooks.approve(estimateScanRead(voxels, stored_bytes)); };
  return readGreyVolume(path, greyBudgetBytes(), approve);
}

// The box of the scan's voxels, to their outer faces, in its world mm.
Bounds3 scanExtent(const GreyImage& scan) {
  const auto& m = scan.scanner_from_voxel;
  Bounds3 box;
  for (int c = 0; c < 8; ++c) {
    const double i = (c & 1) ? scan.dims[0] - 0.5 : -0.5, j = (c & 2) ? scan.dims[1] - 0.5 : -0.5,
                 k = (c & 4) ? scan.dims[2] - 0.5 : -0.5;
    Vec3d p{};
    for (size_t r = 0; r < 3; ++r) p[r] = m[4 * r] * i + m[4 * r + 1] * j + m[4 * r + 2] * k + m[4 * r + 3];
    box.add(p);
  }
  return box;
}

std::string boxText(const Bounds3& b) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%.3g..%.3g, %.3g..%.3g, %.3g..%.3g mm", b.lo[0], b.hi[0], b.lo[1], b.hi[1], b.lo[2],
                b.hi[2]);
  return buf;
}

// The scan's grey value at a world point [mm]: its voxel index through the inverse of its affine,
// trilinear between voxel centres, clamped at the edges (the tooth lies inside, checked before).
class ScanSampler {
 public:
  explicit ScanSampler(const GreyImage& scan) : scan_(scan) {
    const auto& m = scan.scanner_from_voxel;
    const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], k = m[10];
    const double det = a * (e * k - f * h) - b * (d * k - f * g) + c * (d * h - e * g);
    ok_ = std::isfinite(det) && std::abs(det) > 1e-12;
    if (!ok_) return;
    inv_ = {(e * k - f * h) / det, (c * h - b * k) / det, (b * f - c * e) / det,
            (f * g - d * k) / det, (a * k - c * g) / det, (c * d - a * f) / det,
            (d * h - e * g) / det, (b * g - a * h) / det, (a * e - b * d) / det};
    for (size_t r = 0; r < 3; ++r) t_[r] = m[4 * r + 3];
  }
  bool ok() const { return ok_; }
  float at(const Vec3d& mm) const {
    std::array<double, 3> idx{}, frac{};
    std::array<int64_t, 3> i0{}, i1{};
    for (size_t r = 0; r < 3; ++r) {
      double v = 0.0;
      for (size_t c = 0; c < 3; ++c) v += inv_[3 * r + c] * (mm[c] - t_[c]);
      idx[r] = std::clamp(v, 0.0, double(scan_.dims[r] - 1));
      i0[r] = int64_t(std::floor(idx[r]));
      i1[r] = std::min<int64_t>(i0[r] + 1, scan_.dims[r] - 1);
      frac[r] = idx[r] - double(i0[r]);
    }
    double sum = 0.0;
    for (int c = 0; c < 8; ++c) {
      const double w = ((c & 1) ? frac[0] : 1 - frac[0]) * ((c & 2) ? frac[1] : 1 - frac[1]) * ((c & 4) ? frac[2] : 1 - frac[2]);
      if (w == 0.0) continue;
      sum += w * scan_.values[scan_.index((c & 1) ? i1[0] : i0[0], (c & 2) ? i1[1] : i0[1], (c & 4) ? i1[2] : i0[2])];
    }
    return float(sum);
  }

 private:
  const GreyImage& scan_;
  std::array<double, 9> inv_{};
  std::array<double, 3> t_{};
  bool ok_ = false;
};

double median(std::vector<float>& values) {
  const auto mid = values.begin() + std::ptrdiff_t(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return double(*mid);
}

// The synthesized pulp replaced by the scan's: the tooth's voxels (enamel left out: it stays
// synthesized) more than kScanPulpDepthVoxels inside the tooth and darker than midway between the
// dentin's grey and the surroundings' become pulp; the rest of the synthesized pulp becomes dentin.
// The grid is the surface's, not yet turned: a voxel's centre in mm is its scanner_from_grid.
Result<ScanPulpReport> pulpFromScan(BrickVolume& volume, const VolumeFrame& frame, const GreyImage& scan,
                                    const std::string& path) {
  const ScanSampler sampler(scan);
  if (!sampler.ok()) return makeError(path, "the scan's voxel axes are degenerate (a zero or flat affine)");
  const VoxelBox tooth_box = tissueVoxelBoxes(volume)[0];
  if (tooth_box.empty()) return makeError(path, "no tooth voxels to take the pulp into");
  // A dense local box one voxel wider than the tooth, so that the voxels around it are in it.
  std::array<int64_t, 3> lo{}, n{};
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max<int64_t>(tooth_box.lo[a] - 1, 0);
    n[a] = std::min<int64_t>(tooth_box.hi[a] + 1, volume.dim() - 1) - lo[a] + 1;
  }
  const auto at = [&](int64_t x, int64_t y, int64_t z) { return size_t(x + n[0] * (y + n[1] * z)); };
  std::vector<uint8_t> inside(size_t(n[0] * n[1] * n[2]), 0);
  for (int64_t z = 0; z < n[2]; ++z)
    for (int64_t y = 0; y < n[1]; ++y)
      for (int64_t x = 0; x < n[0]; ++x) {
        const Material m = voxelMaterial(volume.voxel(uint32_t(lo[0] + x), uint32_t(lo[1] + y), uint32_t(lo[2] + z)));
        inside[at(x, y, z)] = m != Material::Empty && m != Material::Neighbour;
      }
  const auto held = [&](const std::vector<uint8_t>& mask, int64_t x, int64_t y, int64_t z) {
    return x >= 0 && y >= 0 && z >= 0 && x < n[0] && y < n[1] && z < n[2] && mask[at(x, y, z)];
  };
  const auto allNeighbours = [&](const std::vector<uint8_t>& mask, int64_t x, int64_t y, int64_t z) {
    return held(mask, x - 1, y, z) && held(mask, x + 1, y, z) && held(mask, x, y - 1, z) && held(mask, x, y + 1, z) &&
           held(mask, x, y, z - 1) && held(mask, x, y, z + 1);
  };
  // Deep: eroded kScanPulpDepthVoxels times (6-connected).
  std::vector<uint8_t> deep = inside;
  for (int pass = 0; pass < kScanPulpDepthVoxels; ++pass) {
    std::vector<uint8_t> next(deep.size(), 0);
    for (int64_t z = 0; z < n[2]; ++z)
      for (int64_t y = 0; y < n[1]; ++y)
        for (int64_t x = 0; x < n[0]; ++x) next[at(x, y, z)] = deep[at(x, y, z)] && allNeighbours(deep, x, y, z);
    deep.swap(next);
  }
  const auto centreMm = [&](int64_t x, int64_t y, int64_t z) {
    const auto& f = frame.scanner_from_grid;
    const double g[3] = {double(lo[0] + x), double(lo[1] + y), double(lo[2] + z)};
    Vec3d p{};
    for (size_t r = 0; r < 3; ++r) p[r] = f[4 * r] * g[0] + f[4 * r + 1] * g[1] + f[4 * r + 2] * g[2] + f[4 * r + 3];
    return p;
  };
  // The deep voxels' grey values, and those of the voxels just outside the tooth.
  std::vector<float> grey(deep.size(), 0.0f), deep_values, around_values;
  for (int64_t z = 0; z < n[2]; ++z)
    for (int64_t y = 0; y < n[1]; ++y)
      for (int64_t x = 0; x < n[0]; ++x) {
        const size_t i = at(x, y, z);
        if (deep[i]) {
          grey[i] = sampler.at(centreMm(x, y, z));
          deep_values.push_back(grey[i]);
        } else if (!inside[i] && (held(inside, x - 1, y, z) || held(inside, x + 1, y, z) || held(inside, x, y - 1, z) ||
                                  held(inside, x, y + 1, z) || held(inside, x, y, z - 1) || held(inside, x, y, z + 1))) {
          around_values.push_back(sampler.at(centreMm(x, y, z)));
        }
      }
  if (deep_values.empty() || around_values.empty())
    return makeError(path, "the tooth is too thin at this voxel size to read a pulp from the scan (give a higher --level)");
  ScanPulpReport rep;
  rep.unit = scan.unit;
  rep.dentin_grey = median(deep_values);
  rep.around_grey = median(around_values);
  if (!(rep.dentin_grey > rep.around_grey))
    return makeError(path, "the scan is no brighter inside the tooth (" + greyValue(rep.dentin_grey, scan.unit) +
                               ") than around it (" + greyValue(rep.around_grey, scan.unit) +
                               "): is it this tooth's scan, with the surface in its mm?");
  rep.threshold = 0.5 * (rep.dentin_grey + rep.around_grey);
  const MaterialTotals before = volume.materialTotals();
  rep.synthesized_pulp_mm3 = before.volumeMm3(Material::Pulp, frame.voxel_mm);
  for (int64_t z = 0; z < n[2]; ++z)
    for (int64_t y = 0; y < n[1]; ++y)
      for (int64_t x = 0; x < n[0]; ++x) {
        const size_t i = at(x, y, z);
        if (!inside[i]) continue;
        const uint32_t gx = uint32_t(lo[0] + x), gy = uint32_t(lo[1] + y), gz = uint32_t(lo[2] + z);
        const Voxel v = volume.voxel(gx, gy, gz);
        const Material m = voxelMaterial(v);
        if (m == Material::Enamel) continue;
        const bool pulp = deep[i] && grey[i] < rep.threshold;
        const Material now = pulp ? Material::Pulp : m == Material::Pulp ? Material::Dentin : m;
        if (now != m) volume.setVoxel(gx, gy, gz, makeVoxel(now, voxelFill(v)));
        rep.pulp_voxels += pulp;
      }
  rep.pulp_mm3 = volume.materialTotals().volumeMm3(Material::Pulp, frame.voxel_mm);
  char buf[400];
  std::snprintf(buf, sizeof buf,
                " (%.2f mm^3), enamel synthesized; pulp where the grey value is below %s (midway between the "
                "dentin's %s and the surroundings' %s), more than %d voxels inside the tooth; the synthesized pulp's "
                "%.2f mm^3 is dentin",
                rep.pulp_mm3, greyValue(rep.threshold, scan.unit).c_str(), greyValue(rep.dentin_grey, scan.unit).c_str(),
                greyValue(rep.around_grey, scan.unit).c_str(), kScanPulpDepthVoxels, rep.synthesized_pulp_mm3);
  rep.line = "pulp from the scan " + shownPath(path) + buf;
  return rep;
}

}  // namespace

uint64_t addNeighbours(BrickVolume& tooth, const BrickVolume& neighbours) {
  uint64_t added = 0;
  std::array<Voxel, DS_BRICK_VOXELS> out{};
  neighbours.forEachBrick([&](const BrickView& n) {
    if (n.uniform && voxelMaterial(n.value) == Material::Empty) return;
    const BrickView t = tooth.brick(n.coord);
    for (uint32_t i = 0; i < DS_BRICK_VOXELS; ++i) {
      const Voxel tv = t.at(i), nv = n.at(i);
      const bool take = voxelMaterial(tv) == Material::Empty && voxelFill(nv) > 0;
      out[i] = take ? makeVoxel(Material::Neighbour, voxelFill(nv)) : tv;
      added += take;
    }
    tooth.setBrick(n.coord, out.data());
  });
  return added;
}

Result<ToothVolume> buildToothFromMeshes(const MeshToothOptions& options, const ToothAxesHint& hint,
                                         const ToothBuildHooks& hooks, MeshToothReport* report) {
  MeshToothReport local;
  MeshToothReport& rep = report ? *report : local;
  rep = {};
  if (options.synthesize && options.layers.size() != 1)
    return Error{"layers are synthesized from one whole-tooth surface, not from " + std::to_string(options.layers.size()) +
                 " layers"};
  std::vector<LoadedLayer> loaded, near;
  Bounds3 bounds;
  for (const MeshLayerSource& source : options.layers) {
    auto layer = loadLayer(source, options.mm_per_unit, hooks);
    if (!layer) return layer.error();
    bounds.add(layer->mesh.bounds());
    loaded.push_back(std::move(layer).value());
  }
  for (const std::string& path : options.neighbours) {
    auto layer = loadLayer({path, Material::Neighbour}, options.mm_per_unit, hooks);
    if (!layer) return layer.error();
    bounds.add(layer->mesh.bounds());
    near.push_back(std::move(layer).value());
  }
  const std::optional<VolumeFrame>& reference = options.reference;
  // The scan is read, and its box checked, before the voxelization, so that a wrong one fails fast.
  GreyImage pulp_scan;
  if (!options.pulp_from.empty()) {
    if (!options.synthesize) return Error{"the pulp is taken from a scan in place of a synthesized one: give one whole-tooth surface"};
    if (reference) return Error{"the pulp from a scan needs the surface's own mm; a reference grid turns them"};
    auto scan = readPulpScan(options.pulp_from, hooks);
    if (!scan) return scan.error();
    pulp_scan = std::move(scan).value();
    const Bounds3 tooth_box = loaded.front().mesh.bounds(), scan_box = scanExtent(pulp_scan);
    for (int a = 0; a < 3; ++a)
      if (tooth_box.lo[a] < scan_box.lo[a] || tooth_box.hi[a] > scan_box.hi[a])
        return makeError(options.pulp_from, "the tooth's box " + boxText(tooth_box) + " does not lie inside the scan's " +
                                                boxText(scan_box) +
                                                ": the surface's mm must be the scan's (a segmentation of this scan)");
  }
  if (reference && reference->tooth.turned()) {
    bounds = turnLikeReference(*reference, loaded);
    if (!near.empty()) bounds.add(turnLikeReference(*reference, near));
  }
  std::vector<MeshLayer> layers;
  for (const LoadedLayer& l : loaded) layers.push_back({l.material, &l.mesh, l.path});

  Result<VolumeFrame> frame = reference                ? Result<VolumeFrame>(*reference)
                              : options.voxel_mm > 0.0 ? fitGridToVoxelSize(bounds, options.voxel_mm)
                                                       : fitGridToLevel(bounds, options.level);
  if (!frame) return frame.error();
  if (reference && !gridHolds(*reference, bounds))
    warnVia(hooks, "the meshes reach outside the grid of " + shownPath(options.reference_name) +
                       "; what lies outside is dropped");
  auto setup = makeRaySetup(layers, *frame, options.voxelize);
  if (!setup) return setup.error();

  bool on_engine = false;
  if (options.engine.open) {
    Result<bool> opened = options.engine.open();
    if (!opened) return opened.error();
    on_engine = *opened;
  }
  if (hooks.approve) {
    VoxelizeCost cost = estimateMeshVoxelize(*setup, on_engine);
    if (options.synthesize) cost = withSynthesis(cost, loaded.front().mesh.bounds(), frame->voxel_mm);
    if (Status planned = hooks.approve(cost); !planned) return planned.error();
  }
  const auto t0 = std::chrono::steady_clock::now();
  Result<BrickVolume> voxels = on_engine ? options.engine.run(*setup, options.voxelize, progressOf(hooks))
                                         : voxelizeCpu(*setup, options.voxelize, progressOf(hooks));
  if (!voxels) return voxels.error();
  rep.voxelize_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  rep.engine_ran = on_engine;
  for (const LoadedLayer& l : loaded) rep.layers.push_back({l.path, l.material, l.mesh.triangleCount(), l.volume_mm3});

  ToothVolume tooth{*frame, std::move(voxels).value()};
  // The layers come before the neighbours join, so that the shape they read is the tooth's alone.
  ToothAxesHint stand = hint;
  if (options.synthesize) {
    LayerSynthOptions so = *options.synthesize;
    so.crown = hint.crown;
    auto synth = synthesizeLayers(tooth.voxels, frame->voxel_mm, so, &progressOf(hooks));
    if (!synth) return synth.error();
    if (!options.pulp_from.empty()) {
      auto pulp = pulpFromScan(tooth.voxels, *frame, pulp_scan, options.pulp_from);
      if (!pulp) return pulp.error();
      pulp_scan = GreyImage{};
      synth->dentin_mm3 += synth->pulp_mm3 - pulp->pulp_mm3;
      synth->pulp_mm3 = pulp->pulp_mm3;
      // After the first line, which says the layers are synthesized: this one says which are not.
      synth->lines.insert(synth->lines.begin() + std::min<std::ptrdiff_t>(1, std::ptrdiff_t(synth->lines.size())), pulp->line);
      rep.scan_pulp = std::move(pulp).value();
    }
    recordSynthesis(tooth, *synth);
    if (!stand.crown) stand.crown = synth->crown;
    // Without a mesial end, the mesiodistal line still turns the tooth so that its neighbours would
    // lie along x; its sign is arbitrary, so it stays assumed (below).
    if (!stand.mesial && !stand.buccal) stand.mesial = synth->mesial ? synth->mesial : synth->mesiodistal;
    rep.synthesized = std::move(synth).value();
  }
  if (!near.empty()) {
    const TriangleMesh all = joinedMesh(near);
    auto near_setup = makeRaySetup({{Material::Enamel, &all, "the neighbours"}}, *frame, options.voxelize);
    if (!near_setup) return near_setup.error();
    if (hooks.approve)
      if (Status planned = hooks.approve(estimateMeshVoxelize(*near_setup, false)); !planned) return planned.error();
    Result<BrickVolume> near_voxels = voxelizeCpu(*near_setup, options.voxelize, progressOf(hooks));
    if (!near_voxels) return near_voxels.error();
    rep.neighbour_voxels = addNeighbours(tooth.voxels, *near_voxels);
    for (const LoadedLayer& l : near) rep.neighbours.push_back({l.path, l.material, l.mesh.triangleCount(), l.volume_mm3});
  }
  if (!reference) {
    if (Status st = standToothUp(tooth, stand); !st) return st.error();
    // What the shape showed stands as found, not as given: standToothUp took it as a hint.
    const LayerSynthReport* synth = rep.synthesized ? &*rep.synthesized : nullptr;
    if (synth && !hint.crown && synth->crown_found) tooth.frame.tooth.crown_source = AxisSource::Found;
    if (synth && !hint.mesial && !hint.buccal && (synth->mesial || synth->mesiodistal))
      tooth.frame.tooth.mesial_source = synth->mesial ? AxisSource::Found : AxisSource::Assumed;
  }
  return tooth;
}

// ---- 3. Labels --------------------------------------------------------------------------------
Result<ToothVolume> buildToothFromLabels(const LabelImage& image, LabelImportOptions import, const ToothAxesHint& hint,
                                         const ToothBuildHooks& hooks, LabelImportReport* report) {
  if (hooks.approve) import.approve = hooks.approve;
  Result<ToothVolume> tooth = importLabels(image, import, progressOf(hooks), report);
  if (!tooth) return tooth.error();
  // A pitch in the wrong unit (metres for mm) makes a tooth kilometres or microns wide: say so.
  const VoxelBox box = tissueVoxelBoxes(tooth->voxels)[0];
  if (!box.empty()) {
    int64_t extent = 0;
    for (int a = 0; a < 3; ++a) extent = std::max(extent, box.hi[a] - box.lo[a] + 1);
    if (std::string w = labelPitchWarning(double(extent) * tooth->frame.voxel_mm, tooth->frame.voxel_mm, import.where);
        !w.empty())
      warnVia(hooks, escapeControl(w, w.size()));
  }
  if (Status st = standToothUp(*tooth, hint); !st) return st.error();
  return tooth;
}

// ---- 4. Scans ---------------------------------------------------------------------------------
namespace {

// What the segmentation chose: the lines `voxelize` prints and the volume file keeps for `info`.
std::vector<std::string> segmentationLines(const std::string& source, const GreyImage& scan,
                                           const ToothSegmentReport& r) {
  std::vector<std::string> lines;
  char buf[512];
  // The scan's path and the scanner's own words are printed and kept in the file's note: escaped.
  std::string scanner = escapeControl(scan.manufacturer, 64);
  if (!scan.model.empty()) scanner += (scanner.empty() ? "" : " ") + escapeControl(scan.model, 64);
  std::snprintf(buf, sizeof buf, "scan: %s, %d x %d x %d voxels of %.4g x %.4g x %.4g mm, %s%s%s", shownPath(source).c_str(),
                scan.dims[0], scan.dims[1], scan.dims[2], scan.pitch_mm[0], scan.pitch_mm[1], scan.pitch_mm[2],
                scan.unit == GreyUnit::Hounsfield ? "Hounsfield units" : "raw values", scanner.empty() ? "" : ", from ",
                scanner.c_str());
  lines.push_back(buf);
  std::string t = "thresholds (" + r.thresholds_from + "): dentin from " + greyValue(r.dentin_above, r.unit) +
                  ", enamel from " + greyValue(r.enamel_above, r.unit);
  if (r.caries_below) t += ", caries below " + greyValue(*r.caries_below, r.unit);
  lines.push_back(t);
  const std::string how = r.seeded ? ", grown from the seed; " + std::to_string(r.neighbour_voxels_cut) +
                                         " hard voxels of neighbours or bone cut away at the narrowest joins"
                                   : std::string(", the largest piece of hard tissue");
  std::snprintf(buf, sizeof buf, "tooth: voxels %lld..%lld, %lld..%lld, %lld..%lld of the scan%s",
                (long long)r.out_lo[0], (long long)r.out_hi[0], (long long)r.out_lo[1], (long long)r.out_hi[1],
                (long long)r.out_lo[2], (long long)r.out_hi[2], how.c_str());
  lines.push_back(buf);
  std::snprintf(buf, sizeof buf, "clean-up: %llu partial-volume voxels reassigned, %llu islands under %.3g mm^3 (%llu voxels) relabelled",
                (unsigned long long)r.partial_volume_voxels, (unsigned long long)r.islands_removed,
                r.min_island_voxels > 0 ? r.min_island_voxels * scan.pitch_mm[0] * scan.pitch_mm[1] * scan.pitch_mm[2] : 0.0,
                (unsigned long long)r.island_voxels);
  lines.push_back(buf);
  return lines;
}

// A dentin threshold in soft tissue, and (when asked) a tooth of no human tooth's size, are errors
// that say what was found and what to try: both came from a head CT segmented as if it were a tooth.
Status checkSegmentedTooth(const ScanToothOptions& options, const GreyImage& scan, const ToothSegmentOptions& seg,
                           const ToothSegmentReport& r) {
  const std::string threshold = "dentin from " + greyValue(r.dentin_above, r.unit) + " (" + r.thresholds_from + ")";
  if (std::string low = dentinThresholdProblem(r.dentin_above, r.unit); !low.empty())
    return makeError(seg.where, low + ": it takes soft tissue into the tooth; give --dentin-above (dentin is about "
                                      "1500..2000 HU) or --scanner ct-hu, and --roi around the tooth");
  if (!options.human_size_only) return Ok{};
  const ToothSize size = segmentedToothSize(r, scan.pitch_mm);
  const std::string wrong = humanToothSizeProblem(size);
  if (wrong.empty()) return Ok{};
  // Too large is bone and neighbours taken in; too small is a tooth cut short by its box or threshold.
  const bool automatic = r.thresholds_from.rfind("automatic", 0) == 0;
  const std::string tries = size.hard_mm3 < human_tooth::kMinHardMm3
                                ? "give a --roi that holds the whole tooth, or a lower --dentin-above"
                                : std::string("give --roi around one tooth, a --seed in it, or a higher --dentin-above") +
                                      (automatic ? " (or --scanner ct-hu)" : "");
  return makeError(seg.where, "the segmented tooth is no human tooth: " + wrong + ", with " + threshold + "; " + tries +
                                  "; --any-size keeps a specimen that truly is this size");
}

}  // namespace

Result<ToothVolume> buildToothFromGreyImage(GreyImage image, const std::string& described, const ScanToothOptions& options,
                                            const ToothAxesHint& hint, const ToothBuildHooks& hooks,
                                            ScanToothReport* report) {
  ScanToothReport local;
  ScanToothReport& rep = report ? *report : local;
  const std::string source = options.dicom.empty() ? options.ct : options.dicom;
  if (options.voxel_mm > 0.0) {  // the header's pitch is wrong
    image.pitch_mm = {options.voxel_mm, options.voxel_mm, options.voxel_mm};
    image.scanner_from_voxel = scannerWithPitch(image.scanner_from_voxel, image.pitch_mm);
  }
  ToothSegmentOptions seg = options.segment;
  seg.where = source;
  Result<LabelImage> labels = segmentTooth(image, seg, progressOf(hooks), &rep.segment);
  if (!labels) return labels.error();
  const ToothSegmentReport& r = rep.segment;
  if (Status sane = checkSegmentedTooth(options, image, seg, r); !sane) return sane.error();
  if (std::string coarse = coarseVoxelProblem(image.pitch_mm); !coarse.empty())
    warnVia(hooks, shownPath(source) + ": " + coarse +
                       ": the enamel is then mostly partial volume; its layers need a CBCT or micro-CT (0.3 mm voxels "
                       "or finer)");
  if (r.seeded && 2 * r.tooth_voxels < r.hard_component_voxels) {
    char buf[400];
    std::snprintf(buf, sizeof buf,
                  "the seed's tooth keeps %.1f %% of the hard tissue joined to it; where the tooth stands "
                  "alone (an extracted tooth, a micro-CT), leave out --seed: the cut at narrow joins can split a "
                  "tooth's own walls",
                  100.0 * double(r.tooth_voxels) / double(r.hard_component_voxels));
    warnVia(hooks, buf);
  }
  rep.lines = segmentationLines(described, image, r);
  image = GreyImage{};  // frees the grey values before the import

  LabelImportOptions import;
  import.map = toothSegmentLabelMap();
  import.where = source;
  import.level = options.level;
  import.fill_enclosed = options.fill;
  import.seal_mm = options.seal_mm;
  if (hooks.approve) import.approve = hooks.approve;
  Result<ToothVolume> tooth = importLabels(*labels, import, progressOf(hooks));
  if (!tooth) return tooth.error();
  labels = Error{};
  if (Status st = standToothUp(*tooth, hint); !st) return st.error();
  char pulp[128];
  std::snprintf(pulp, sizeof pulp, "pulp: the space the dentin encloses, sealed %.3g mm at open apices; level %d",
                options.seal_mm, tooth->frame.level);
  rep.lines.push_back(pulp);
  for (size_t i = 0; i < rep.lines.size(); ++i) tooth->source_note += (i ? "\n" : "") + rep.lines[i];
  return tooth;
}

Result<ToothVolume> buildToothFromScan(const ScanToothOptions& options, const ToothAxesHint& hint,
                                       const ToothBuildHooks& hooks, ScanToothReport* report) {
  ScanToothReport local;
  ScanToothReport& rep = report ? *report : local;
  rep = {};
  Result<GreyImage> scan = Error{};
  DicomSeriesInfo dicom_info;
  if (!options.dicom.empty()) {
    DicomReadOptions read;
    read.series_uid = options.series;
    read.approve = options.approve_read;
    scan = readDicomSeries(options.dicom, read, progressOf(hooks), &dicom_info);
  } else {
    scan = readGreyVolume(options.ct, greyBudgetBytes(), options.approve_read);
  }
  if (!scan) return scan.error();
  rep.dicom_files = dicom_info.files;
  const std::string described =
      options.dicom.empty() ? options.ct : options.dicom + " (" + std::to_string(dicom_info.files) + " DICOM files)";
  return buildToothFromGreyImage(std::move(scan).value(), described, options, hint, hooks, &rep);
}

}  // namespace dentsim
