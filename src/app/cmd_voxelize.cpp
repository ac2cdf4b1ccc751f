// dentsim voxelize: builds a .dvol tooth from STL tissue layers (GPU depth peeling) or from a segmented CT label volume.
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "app/gpu_choice.h"
#include "app/terminal_progress.h"
#include "core/text_escape.h"
#include "gpu/gpu_voxelizer.h"
#include "io/mesh_units.h"
#include "io/dicom_series.h"
#include "io/grey_volume_file.h"
#include "io/input_budget.h"
#include "io/nifti_labels.h"
#include "io/stl_file.h"
#include "volume/ct_segment.h"
#include "volume/label_import.h"
#include "volume/mesh_voxelizer.h"
#include "volume/tissue_table.h"
#include "volume/tooth_file.h"
#include "volume/tooth_frame.h"
#include "volume/voxelize_plan.h"

namespace dentsim::app {
namespace {

// The voxel edges a tooth can have: a micro-CT's 1 um to a coarse 10 mm [mm].
constexpr double kMinVoxelMm = 1e-3, kMaxVoxelMm = 10.0;

struct VoxelizeOptions {
  // STL layers, one file per tissue of the table (--enamel, --dentin, ...), or a one-layer tooth
  std::array<std::string, kTissueCount> layer;  // by tissue table row; empty: none
  std::string tooth;
  std::string tooth_material = "dentin";  // tissue of a --tooth mesh
  std::string units = "mm";               // unit of the STL coordinates
  double scale = 1.0;                     // extra factor after the unit
  int subsamples = 2;                     // rays per voxel side
  int hole_radius = 8;                    // rays a leaky ray searches for a donor
  bool cpu = false;                       // the CPU reference instead of the GPU
  std::string device;                     // Vulkan device override
  // CT labels
  std::string labels;        // NIfTI label volume
  std::string label_map;     // "1=caries,2=enamel,3=dentin"
  double voxel_size = 0.0;   // labels: source voxel edge (overrides the header); STL: output voxel edge [mm]; 0: unset
  int level = 0;             // fit into a 2^level grid; 0: unset
  std::string frame_of;      // STL: take the grid of this .dvol (excludes level and voxel_size); empty: fit one
  std::string fill_enclosed; // tissue for empty space the tooth encloses; empty: none
  double seal_mm = 0.2;       // closing radius for --fill-enclosed [mm]; about the apical foramen radius
  long long min_piece = 0;    // labels: relabel pieces of one tissue smaller than this [voxels]; 0: off
  // A scanner's grey values: a DICOM series, or a NIfTI/NRRD volume, segmented into tissues
  std::string dicom;          // folder of a DICOM series (or one multi-frame file)
  std::string series;         // the Series Instance UID to read from a folder holding several
  std::string ct;             // .nii, .nii.gz, .nrrd or .nhdr grey-value volume
  std::string roi;            // "x0,y0,z0:x1,y1,z1" in the scan's mm
  std::vector<double> seed;   // x,y,z in the scan's mm
  std::optional<double> enamel_above, dentin_above, caries_below;  // thresholds [the scan's unit]
  std::string scanner;        // a named preset of thresholds
  bool find_caries = false;   // label demineralised tissue open to the surface as caries
  double min_island_mm3 = ToothSegmentOptions{}.min_island_mm3;
  std::string output;        // .dvol path
  // The tooth's frame, in the input's coordinates; empty: found (crown) or not known (mesial, buccal)
  std::vector<double> crown_axis, mesial_axis, buccal_axis;
  bool keep_orientation = false;  // record the frame but do not turn the grid
  bool force = false;             // run a job planned beyond the memory budget all the same
  std::string plan_json;          // append each estimate here as a JSON line; empty: none
};

// Says what the job will cost before it starts, and refuses one beyond the memory budget unless --force.
// With --plan-json the estimate is also appended as one JSON line, for `dentsim bench plan` and scripts.
Status planJob(const dentsim::VoxelizeCost& cost, const VoxelizeOptions& o) {
  std::printf("plan: %s\n", describeCost(cost).c_str());
  std::fflush(stdout);
  if (!o.plan_json.empty()) {
    const nlohmann::json line = {{"level", cost.level},           {"scan_voxels", cost.scan_voxels},
                                 {"dense_bricks", cost.surface_bricks}, {"memory_bytes", cost.memory_bytes},
                                 {"seconds", cost.seconds}};
    std::ofstream out(o.plan_json, std::ios::app);
    out << line.dump() << "\n";
    if (!out) return makeError(o.plan_json, "cannot append the plan");
  }
  return checkAffordable(cost, memoryBudgetBytes(), o.force, "voxelize");
}

Result<ToothAxesHint> axesHint(const VoxelizeOptions& o) {
  ToothAxesHint hint;
  hint.turn = !o.keep_orientation;
  for (auto [values, axis, flag] : {std::tuple{&o.crown_axis, &hint.crown, "--crown-axis"},
                                    {&o.mesial_axis, &hint.mesial, "--mesial-axis"},
                                    {&o.buccal_axis, &hint.buccal, "--buccal-axis"}}) {
    if (values->empty()) continue;
    if (values->size() != 3) return makeError(flag, "expected three numbers x,y,z");
    *axis = Vec3{(*values)[0], (*values)[1], (*values)[2]};
  }
  return hint;
}

const char* axisSourceText(AxisSource s) {
  return s == AxisSource::Found ? "found from the enamel" : s == AxisSource::Given ? "given" : "not known";
}

// One line on the tooth's frame: how the crown axis was known and whether the grid was turned.
void printFrame(const ToothVolume& tooth) {
  const ToothAxes& t = tooth.frame.tooth;
  std::printf("  crown axis %s, now (%.3f, %.3f, %.3f)%s; mesial %s\n", axisSourceText(t.crown_source), t.crown[0],
              t.crown[1], t.crown[2], t.turned() ? " after quarter turns that stand the crown up" : "",
              axisSourceText(t.mesial_source));
  if (t.crown_source == AxisSource::Assumed)
    warn("the enamel does not show which way the crown faces (none, or centred on the tooth): +z is taken as the crown axis (give --crown-axis)");
}

void printSummary(const ToothVolume& tooth, const std::string& output) {
  const VolumeFrame& f = tooth.frame;
  const MaterialTotals totals = tooth.voxels.materialTotals();
  std::printf("%s: grid %lld^3 (level %d), voxel %.6g mm\n", shownPath(output).c_str(), static_cast<long long>(f.dim()),
              f.level, f.voxel_mm);
  for (uint32_t m = 1; m < DS_TISSUE_COUNT; ++m) {
    const auto mat = static_cast<Material>(m);
    if (totals.voxels[m] == 0) continue;
    std::printf("  %-7s %14.4f mm^3  (%llu voxels)\n", materialName(mat).c_str(), totals.volumeMm3(mat, f.voxel_mm),
                static_cast<unsigned long long>(totals.voxels[m]));
  }
}

// One line for the clean-up: what was relabelled, by tissue before and after. Silent when it was off.
void printCleanup(const PieceCleanup& c, long long min_piece) {
  if (min_piece <= 0) return;
  std::string from, into;
  for (uint32_t m = 0; m < DS_TISSUE_COUNT; ++m) {
    const std::string name = materialName(static_cast<Material>(m));
    if (c.pieces[m] > 0)
      from += (from.empty() ? "" : ", ") + name + " " + std::to_string(c.pieces[m]) + " (" +
              std::to_string(c.voxels[m]) + (c.voxels[m] == 1 ? " voxel)" : " voxels)");
    if (c.voxels_into[m] > 0)
      into += (into.empty() ? "" : ", ") + name + " " + std::to_string(c.voxels_into[m]);
  }
  if (from.empty())
    std::printf("  pieces under %lld voxels relabelled: none\n", min_piece);
  else
    std::printf("  pieces under %lld voxels relabelled: %s; voxels now %s\n", min_piece, from.c_str(), into.c_str());
}

// ---- the per-tissue STL layers: one flag per tissue table row ----

bool hasMeshes(const VoxelizeOptions& o) {
  for (const std::string& path : o.layer)
    if (!path.empty()) return true;
  return !o.tooth.empty();
}

// "--enamel/--dentin/--pulp/--caries", for messages.
std::string layerFlagList() {
  std::string out;
  for (const TissueRow& row : kTissueTable) out += (out.empty() ? "--" : "/--") + std::string(row.name);
  return out;
}

// The table rows in the voxelizer's priority, lowest first (enamel, dentin, caries, pulp): the order
// the layers are loaded and then listed in, whatever order the table keeps.
std::array<size_t, kTissueCount> layersByPriority() {
  std::array<size_t, kTissueCount> rows{};
  for (size_t t = 0; t < kTissueCount; ++t) rows[t] = t;
  std::stable_sort(rows.begin(), rows.end(), [](size_t a, size_t b) {
    return materialPriority(kTissueTable[a].material) < materialPriority(kTissueTable[b].material);
  });
  return rows;
}

struct LoadedLayer {
  std::string path;
  Material material = Material::Dentin;
  TriangleMesh mesh;
  double volume_mm3 = 0.0;
};

// Reads one layer, converts it to mm and says what is wrong with it; an error ends the command.
Result<LoadedLayer> loadLayer(const std::string& path, Material material, double mm_per_unit) {
  auto stl = readStl(path);
  if (!stl) return stl.error();
  LoadedLayer layer{path, material, std::move(stl->mesh), 0.0};
  layer.mesh.scale(mm_per_unit);
  const MeshTopology& topo = stl->info.topology;
  const std::string shown = shownPath(path);  // the warnings below name the file, escaped
  if (topo.open_edges > 0)
    warn(shown + ": " + std::to_string(topo.open_edges) + " open edges (holes); rays through a hole borrow the layer from the nearest ray that is closed");
  if (topo.nonmanifold_edges > 0)
    warn(shown + ": " + std::to_string(topo.nonmanifold_edges) + " non-manifold edges");
  if (!topo.consistent())
    warn(shown + ": " + std::to_string(topo.flipped_edges) + " edges with inconsistent winding; the inside is taken by winding number");
  else if (topo.signed_volume_mm3 < 0.0)
    warn(shown + ": the mesh is inside out (negative volume); it is filled all the same");
  if (std::string w = toothExtentWarning(layer.mesh.bounds(), path); !w.empty())
    warn(escapeControl(w, w.size()));
  layer.volume_mm3 = std::abs(layer.mesh.signedVolume());
  return layer;
}

// The grid of an existing volume, so that a voxelization compares with it voxel for voxel. The whole
// frame is kept, scanner matrix and source box included: the grid is the same, so an export of the
// result overlays the same scan.
Result<VolumeFrame> referenceFrame(const std::string& path) {
  Result<ToothVolume> reference = loadTooth(path);
  if (!reference) return makeError("--frame-of", reference.message());
  return reference->frame;
}

// True when the bounds lie within the frame's grid box (to a thousandth of a voxel).
bool gridHolds(const VolumeFrame& f, const Bounds3& bounds) {
  const double side = double(f.dim()) * f.voxel_mm;
  const double slack = 1e-3 * f.voxel_mm;
  for (int a = 0; a < 3; ++a)
    if (bounds.lo[a] < f.origin_mm[a] - slack || bounds.hi[a] > f.origin_mm[a] + side + slack) return false;
  return true;
}

int runVoxelizeMeshes(const VoxelizeOptions& o) {
  // The reference grid is read first: a bad file then fails before any mesh is loaded.
  std::optional<VolumeFrame> reference;
  if (!o.frame_of.empty()) {
    if (o.level > 0 || o.voxel_size > 0.0)
      return fail("--frame-of takes the grid of " + shownPath(o.frame_of) + "; leave out --level and --voxel-size");
    if (!o.crown_axis.empty() || !o.mesial_axis.empty() || !o.buccal_axis.empty() || o.keep_orientation)
      return fail("--frame-of takes the tooth frame of " + shownPath(o.frame_of) + "; leave out the axes and --keep-orientation");
    Result<VolumeFrame> f = referenceFrame(o.frame_of);
    if (!f) return fail(f.message());
    reference = *f;
  }
  LengthUnit unit{};
  if (!parseLengthUnit(o.units, &unit)) return fail("--units: unknown unit '" + escapeControl(o.units) + "' (expected mm, cm, m or um)");
  if (!(o.scale > 0.0) || !std::isfinite(o.scale)) return fail("--scale must be a positive number");
  const double mm_per_unit = millimetresPer(unit) * o.scale;

  std::vector<std::pair<std::string, Material>> inputs;
  if (!o.tooth.empty()) {
    Material m{};
    if (!parseMaterial(o.tooth_material, &m) || m == Material::Empty)
      return fail("--tooth-material: unknown tissue '" + escapeControl(o.tooth_material) + "'");
    inputs.push_back({o.tooth, m});
  }
  for (size_t t : layersByPriority())
    if (!o.layer[t].empty()) inputs.push_back({o.layer[t], kTissueTable[t].material});

  std::vector<LoadedLayer> loaded;
  Bounds3 bounds;
  for (const auto& [path, m] : inputs) {
    auto layer = loadLayer(path, m, mm_per_unit);
    if (!layer) return fail(layer.message());
    bounds.add(layer->mesh.bounds());
    loaded.push_back(std::move(layer).value());
  }
  auto hint = axesHint(o);
  if (!hint) return fail(hint.message());
  if (reference && reference->tooth.turned()) {
    // The reference grid was turned to stand its tooth up: the meshes turn the same way about its centre.
    const double half = 0.5 * double(reference->dim()) * reference->voxel_mm;
    const Vec3 centre{reference->origin_mm[0] + half, reference->origin_mm[1] + half, reference->origin_mm[2] + half};
    bounds = Bounds3{};
    for (LoadedLayer& l : loaded) {
      for (Vec3f& p : l.mesh.positions) {
        const Vec3 q = turned(reference->tooth.turn, Vec3{p[0], p[1], p[2]} - centre) + centre;
        p = Vec3f{float(q.x), float(q.y), float(q.z)};
      }
      bounds.add(l.mesh.bounds());
    }
  }
  std::vector<MeshLayer> layers;
  for (const LoadedLayer& l : loaded) layers.push_back({l.material, &l.mesh, l.path});

  Result<VolumeFrame> frame = reference            ? Result<VolumeFrame>(*reference)
                             : o.voxel_size > 0.0 ? fitGridToVoxelSize(bounds, o.voxel_size)
                                                  : fitGridToLevel(bounds, o.level > 0 ? o.level : 9);
  if (!frame) return fail(frame.message());
  if (reference && !gridHolds(*reference, bounds))
    warn("the meshes reach outside the grid of " + shownPath(o.frame_of) + "; what lies outside is dropped");
  dentsim::VoxelizeOptions vo;
  vo.subsamples = o.subsamples;
  vo.hole_radius = o.hole_radius;
  auto setup = makeRaySetup(layers, *frame, vo);
  if (!setup) return fail(setup.message());

  TerminalProgress progress;
  std::optional<Result<BrickVolume>> voxels;
  std::string engine = "CPU reference";
  gpu::VoxelizeTiming timing;
  std::optional<gpu::Context> gpu_context;
  if (!o.cpu) {
    auto ctx = openGpuOrFallBack(o.device, "voxelizing on the CPU");
    if (!ctx) return fail(ctx.message());
    gpu_context = std::move(ctx).value();
  }
  const bool on_gpu = gpu_context.has_value();
  if (Status planned = planJob(estimateMeshVoxelize(*setup, on_gpu), o); !planned) return fail(planned.message());
  const auto t0 = std::chrono::steady_clock::now();
  if (on_gpu) {
    voxels.emplace(gpu::voxelizeGpu(*gpu_context, *setup, vo, &timing, progress));
    engine = "GPU (" + gpu_context->device().name + ")";
  }
  if (!voxels) voxels.emplace(voxelizeCpu(*setup, vo, progress));
  if (!*voxels) return fail(voxels->message());
  const double voxelize_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  ToothVolume tooth{*frame, std::move(*voxels).value()};
  if (!reference)
    if (Status st = standToothUp(tooth, *hint); !st) return fail(st.message());
  if (Status saved = saveTooth(o.output, tooth); !saved) return fail(saved.message());
  printSummary(tooth, o.output);
  if (reference) std::printf("  grid and tooth frame of %s\n", shownPath(o.frame_of).c_str());
  else printFrame(tooth);
  std::printf("  voxelized on the %s, %d x %d rays per voxel, in %.0f ms", engine.c_str(), o.subsamples, o.subsamples,
              voxelize_ms);
  if (timing.bands > 0)
    std::printf(" (voxelizer %.0f ms, kernels %.0f ms: count+scan %.0f, store+sort %.0f, paint %.0f, chunks %.0f; "
                "%llu hits, %llu dense bricks, %u band%s)", timing.total_ms, timing.kernels_ms, timing.count_scan_ms,
                timing.store_sort_ms, timing.paint_ms, timing.chunks_ms, static_cast<unsigned long long>(timing.hits),
                static_cast<unsigned long long>(timing.dense_bricks), timing.bands, timing.bands == 1 ? "" : "s");
  std::printf("\n");
  for (const LoadedLayer& l : loaded)
    std::printf("  layer %-7s %s: %zu triangles, mesh volume %.4f mm^3\n", materialName(l.material).c_str(),
                shownPath(l.path).c_str(), l.mesh.triangleCount(), l.volume_mm3);
  return 0;
}

// "x0,y0,z0:x1,y1,z1" [mm] into a box; false when it is not six finite numbers in that shape.
bool parseRoi(const std::string& text, MmBox* box) {
  const size_t colon = text.find(':');
  if (colon == std::string::npos || text.find(':', colon + 1) != std::string::npos) return false;
  auto corner = [](const std::string& part, std::array<double, 3>* out) {
    size_t at = 0;
    for (int a = 0; a < 3; ++a) {
      const size_t comma = a < 2 ? part.find(',', at) : part.size();
      if (comma == std::string::npos) return false;
      const std::string item = part.substr(at, comma - at);
      char* end = nullptr;
      (*out)[size_t(a)] = std::strtod(item.c_str(), &end);
      if (item.empty() || end != item.c_str() + item.size() || !std::isfinite((*out)[size_t(a)])) return false;
      at = comma + 1;
    }
    return true;
  };
  return corner(text.substr(0, colon), &box->lo) && corner(text.substr(colon + 1), &box->hi);
}

std::string greyValue(double v, GreyUnit unit) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.6g %s", v, greyUnitName(unit));
  return buf;
}

// What the segmentation chose, in the lines `voxelize` prints and the volume file keeps for `info`.
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
  std::snprintf(buf, sizeof buf, "tooth: voxels %lld..%lld, %lld..%lld, %lld..%lld of the scan%s",
                (long long)r.out_lo[0], (long long)r.out_hi[0], (long long)r.out_lo[1], (long long)r.out_hi[1],
                (long long)r.out_lo[2], (long long)r.out_hi[2],
                r.seeded ? (", grown from the seed; " + std::to_string(r.neighbour_voxels_cut) +
                            " hard voxels of neighbours or bone cut away at the narrowest joins").c_str()
                         : ", the largest piece of hard tissue");
  lines.push_back(buf);
  std::snprintf(buf, sizeof buf, "clean-up: %llu partial-volume voxels reassigned, %llu islands under %.3g mm^3 (%llu voxels) relabelled",
                (unsigned long long)r.partial_volume_voxels, (unsigned long long)r.islands_removed,
                r.min_island_voxels > 0 ? r.min_island_voxels * scan.pitch_mm[0] * scan.pitch_mm[1] * scan.pitch_mm[2] : 0.0,
                (unsigned long long)r.island_voxels);
  lines.push_back(buf);
  return lines;
}

int runVoxelizeScan(const VoxelizeOptions& o) {
  auto hint = axesHint(o);
  if (!hint) return fail(hint.message());
  ToothSegmentOptions seg;
  const std::string source = o.dicom.empty() ? o.ct : o.dicom;
  seg.where = source;
  if (!o.roi.empty()) {
    MmBox box;
    if (!parseRoi(o.roi, &box)) return fail("--roi: expected x0,y0,z0:x1,y1,z1 in mm, not '" + escapeControl(o.roi) + "'");
    seg.roi = box;
  }
  if (!o.seed.empty()) {
    if (o.seed.size() != 3) return fail("--seed: expected three numbers x,y,z in mm");
    seg.seed_mm = std::array<double, 3>{o.seed[0], o.seed[1], o.seed[2]};
  }
  seg.dentin_above = o.dentin_above;
  seg.enamel_above = o.enamel_above;
  seg.caries_below = o.caries_below;
  seg.caries = o.find_caries;
  seg.preset = o.scanner;
  seg.min_island_mm3 = o.min_island_mm3;

  TerminalProgress progress;
  Result<GreyImage> scan = Error{};
  DicomSeriesInfo dicom_info;
  // The read is planned once its header gives the size, before the values are allocated. The DICOM
  // reader asks in its checking child too (the same answer); only this process prints the plan.
  const pid_t planner = ::getpid();
  const ScanReadApproval approve = [&o, planner](uint64_t voxels, uint32_t stored_bytes) -> Status {
    const VoxelizeCost cost = estimateScanRead(voxels, stored_bytes);
    if (::getpid() != planner) return checkAffordable(cost, memoryBudgetBytes(), o.force, "voxelize");
    return planJob(cost, o);
  };
  if (!o.dicom.empty()) {
    DicomReadOptions read;
    read.series_uid = o.series;
    read.approve = approve;
    scan = readDicomSeries(o.dicom, read, progress, &dicom_info);
  } else {
    scan = readGreyVolume(o.ct, greyBudgetBytes(), approve);
  }
  if (!scan) return fail(scan.message());
  if (o.voxel_size > 0.0) {  // the header's pitch is wrong
    scan->pitch_mm = {o.voxel_size, o.voxel_size, o.voxel_size};
    scan->scanner_from_voxel = scannerWithPitch(scan->scanner_from_voxel, scan->pitch_mm);
  }
  ToothSegmentReport report;
  Result<LabelImage> labels = segmentTooth(*scan, seg, progress, &report);
  if (!labels) return fail(labels.message());
  if (report.seeded && 2 * report.tooth_voxels < report.hard_component_voxels)
    warnf("the seed's tooth keeps %.1f %% of the hard tissue joined to it; where the tooth stands "
          "alone (an extracted tooth, a micro-CT), leave out --seed: the cut at narrow joins can split a "
          "tooth's own walls",
          100.0 * double(report.tooth_voxels) / double(report.hard_component_voxels));
  std::string described = o.dicom.empty() ? o.ct : o.dicom + " (" + std::to_string(dicom_info.files) + " DICOM files)";
  const std::vector<std::string> lines = segmentationLines(described, *scan, report);
  scan = Error{};  // frees the grey values before the import

  LabelImportOptions import;
  import.map = parseLabelMap("1=enamel,2=dentin,4=caries").value();
  import.where = source;
  import.level = o.level > 0 ? o.level : 9;
  Material fill = Material::Pulp;
  if (!o.fill_enclosed.empty() && (!parseMaterial(o.fill_enclosed, &fill) || fill == Material::Empty))
    return fail("--fill-enclosed: unknown tissue '" + escapeControl(o.fill_enclosed) + "' (expected " + tissueNameList() + ")");
  import.fill_enclosed = fill;
  import.seal_mm = o.seal_mm;
  import.approve = [&o](const dentsim::VoxelizeCost& cost) { return planJob(cost, o); };
  Result<ToothVolume> tooth = importLabels(*labels, import, progress);
  if (!tooth) return fail(tooth.message());
  labels = Error{};
  if (Status st = standToothUp(*tooth, *hint); !st) return fail(st.message());
  char pulp[128];
  std::snprintf(pulp, sizeof pulp, "pulp: the space the dentin encloses, sealed %.3g mm at open apices; level %d",
                o.seal_mm, tooth->frame.level);
  for (const std::string& line : lines) tooth->source_note += line + "\n";
  tooth->source_note += pulp;
  if (Status saved = saveTooth(o.output, *tooth); !saved) return fail(saved.message());
  printSummary(*tooth, o.output);
  printFrame(*tooth);
  for (const std::string& line : lines) std::printf("  %s\n", line.c_str());
  std::printf("  %s\n", pulp);
  return 0;
}

// Options the chosen input cannot use, each refused with the reason; `given` says whether the user
// gave an option (CLI::App::count()), since a default value looks the same as one given.
Status checkVoxelizeOptions(const VoxelizeOptions& o, const std::function<bool(const char*)>& given) {
  const bool meshes = hasMeshes(o);
  if (meshes) {
    if (Status st = refuseOption(given("--voxel-size") && given("--level"), "--voxel-size",
                                 "sets the grid's voxel, --level its size; with STL layers give one of the two");
        !st)
      return st;
  } else if (!o.labels.empty() || !o.dicom.empty() || !o.ct.empty()) {
    const char* source = !o.labels.empty() ? "--labels" : !o.dicom.empty() ? "--dicom" : "--ct";
    for (const char* stl_only : {"--units", "--scale", "--subsamples", "--hole-radius", "--cpu", "--device", "--frame-of"})
      if (Status st = refuseOption(given(stl_only), stl_only,
                                   std::string("applies to STL layers; ") + source + " has its own grid");
          !st)
        return st;
  }
  const bool scan = !o.dicom.empty() || !o.ct.empty();
  for (const char* scan_only : {"--roi", "--seed", "--enamel-above", "--dentin-above", "--caries-below", "--scanner",
                                "--find-caries", "--min-island-mm3"})
    if (Status st = refuseOption(given(scan_only) && !scan, scan_only,
                                 "segments a scan's grey values; give --dicom DIR or --ct FILE");
        !st)
      return st;
  if (Status st = refuseOption(given("--series") && o.dicom.empty(), "--series", "picks a series of --dicom"); !st)
    return st;
  if (Status st = refuseOption(given("--caries-below") && !o.find_caries, "--caries-below",
                               "sets where caries ends; give --find-caries");
      !st)
    return st;
  if (scan)
    for (const char* labels_only : {"--label-map", "--min-piece"})
      if (Status st = refuseOption(given(labels_only), labels_only,
                                   std::string("applies to --labels; a scan's tissues come from its grey values") +
                                       (std::string(labels_only) == "--min-piece" ? " (islands: --min-island-mm3)" : ""));
          !st)
        return st;
  if (Status st = refuseOption(given("--tooth-material") && o.tooth.empty(), "--tooth-material",
                               "is the tissue of --tooth; no --tooth is given");
      !st)
    return st;
  return refuseOption(given("--seal-mm") && o.fill_enclosed.empty() && !scan, "--seal-mm",
                      "seals openings for --fill-enclosed; no --fill-enclosed is given");
}

int runVoxelize(const VoxelizeOptions& o) {
  const bool meshes = hasMeshes(o);
  const int sources = int(meshes) + int(!o.labels.empty()) + int(!o.dicom.empty()) + int(!o.ct.empty());
  if (sources > 1) return fail("give one source: STL layers, --labels, --dicom or --ct");
  std::vector<std::string> inputs(o.layer.begin(), o.layer.end());
  inputs.insert(inputs.end(), {o.tooth, o.labels, o.frame_of, o.dicom, o.ct});
  if (Status st = checkOutputsAreNotInputs(inputs, {o.output, o.plan_json}); !st)
    return fail(st.message());
  if (meshes && (o.min_piece != 0 || !o.label_map.empty() || !o.fill_enclosed.empty()))
    return fail("--min-piece, --label-map and --fill-enclosed apply to --labels, not to STL layers");
  if (sources == 0)
    return fail("nothing to voxelize: give " + layerFlagList() + " STL layers, --tooth, --labels, --dicom or --ct");
  if (meshes) return runVoxelizeMeshes(o);
  if (!o.dicom.empty() || !o.ct.empty()) return runVoxelizeScan(o);
  if (!o.frame_of.empty()) return fail("--frame-of applies to STL layers; --labels keeps the label volume's grid");
  if (o.label_map.empty()) return fail("--labels needs --label-map");
  if (o.min_piece < 0) return fail("--min-piece must be 0 or more voxels, not " + std::to_string(o.min_piece));
  auto hint = axesHint(o);
  if (!hint) return fail(hint.message());
  Result<LabelMap> map = parseLabelMap(o.label_map);
  if (!map) return fail("--label-map: " + map.message());
  LabelImportOptions import;
  import.map = std::move(map.value());
  import.where = o.labels;
  if (o.voxel_size > 0.0) import.source_pitch_mm = o.voxel_size;
  if (o.level > 0) import.level = o.level;
  if (!o.fill_enclosed.empty()) {
    Material m{};
    if (!parseMaterial(o.fill_enclosed, &m) || m == Material::Empty)
      return fail("--fill-enclosed: unknown tissue '" + escapeControl(o.fill_enclosed) + "' (expected " + tissueNameList() + ")");
    import.fill_enclosed = m;
    import.seal_mm = o.seal_mm;
  }
  import.min_piece_voxels = o.min_piece;
  import.approve = [&o](const dentsim::VoxelizeCost& cost) { return planJob(cost, o); };

  Result<LabelImage> image = readNiftiLabels(o.labels);
  if (!image) return fail(image.message());
  TerminalProgress progress;
  LabelImportReport report;
  Result<ToothVolume> tooth = importLabels(*image, import, progress, &report);
  if (!tooth) return fail(tooth.message());
  image = Error{};  // frees the labels before the save compacts and encodes the bricks
  const VoxelBox box = tissueVoxelBoxes(tooth->voxels)[0];
  if (!box.empty()) {
    int64_t extent = 0;
    for (int a = 0; a < 3; ++a) extent = std::max(extent, box.hi[a] - box.lo[a] + 1);
    if (std::string w = labelPitchWarning(double(extent) * tooth->frame.voxel_mm, tooth->frame.voxel_mm, o.labels); !w.empty())
      warn(escapeControl(w, w.size()));
  }
  if (Status st = standToothUp(*tooth, *hint); !st) return fail(st.message());
  if (Status saved = saveTooth(o.output, *tooth); !saved) return fail(saved.message());
  printSummary(*tooth, o.output);
  printFrame(*tooth);
  printCleanup(report.cleanup, o.min_piece);
  return 0;
}

}  // namespace

void addVoxelizeCommand(CLI::App& root, Action& action) {
  auto opts = std::make_shared<VoxelizeOptions>();
  CLI::App* cmd = root.add_subcommand("voxelize", "Build a .dvol tooth from STL tissue layers, a segmented CT label volume, or a scan (DICOM, NIfTI, NRRD)");
  for (size_t t = 0; t < kTissueCount; ++t) {
    std::string help = kTissueTable[t].name;
    help[0] = char(std::toupper(static_cast<unsigned char>(help[0])));
    cmd->add_option("--" + std::string(kTissueTable[t].name), opts->layer[t], help + " surface (STL)");
  }
  cmd->add_option("--tooth", opts->tooth, "A one-layer tooth (STL), filled with --tooth-material");
  cmd->add_option("--tooth-material", opts->tooth_material, "Tissue of --tooth")->capture_default_str();
  cmd->add_option("--units", opts->units, "Unit of the STL coordinates: mm, cm, m or um")->capture_default_str();
  cmd->add_option("--scale", opts->scale, "Extra scale factor for the STL coordinates")
      ->check(finiteIn(1e-6, 1e6, ""))
      ->capture_default_str();
  cmd->add_option("--subsamples", opts->subsamples, "Rays per voxel side for the fill fraction (1-4)")
      ->check(CLI::Range(1, 4))
      ->capture_default_str();
  cmd->add_option("--hole-radius", opts->hole_radius, "How far a ray through a hole looks for a closed one [rays]")
      ->check(CLI::Range(0, 64))
      ->capture_default_str();
  cmd->add_flag("--cpu", opts->cpu, "Voxelize STL layers with the CPU reference instead of the GPU");
  cmd->add_option("--device", opts->device, "Vulkan device index or name substring (also DENTSIM_DEVICE)");
  cmd->add_option("--labels", opts->labels, "Label volume (.nii or .nii.gz)");
  cmd->add_option("--label-map", opts->label_map, "Label to tissue, e.g. 1=caries,2=enamel,3=dentin");
  cmd->add_option("--dicom", opts->dicom, "A scan's DICOM series: its folder (CT, CBCT, micro-CT), segmented into tissues");
  cmd->add_option("--series", opts->series, "With --dicom: the Series Instance UID to read from a folder holding several");
  cmd->add_option("--ct", opts->ct, "A scan's grey values as NIfTI or NRRD (.nii, .nii.gz, .nrrd, .nhdr), segmented into tissues");
  cmd->add_option("--roi", opts->roi, "Scan: the box that holds the tooth, x0,y0,z0:x1,y1,z1 in the scan's mm");
  cmd->add_option("--seed", opts->seed, "Scan: a point in the tooth x,y,z [mm]; the tooth is cut from its neighbours and the bone")
      ->delimiter(',')
      ->expected(3)
      ->check(finiteIn(-1e6, 1e6, "mm"));
  cmd->add_option("--dentin-above", opts->dentin_above, "Scan: hard tissue (dentin) from this grey value up [HU or raw]")
      ->check(finiteIn(-1e9, 1e9, ""));
  cmd->add_option("--enamel-above", opts->enamel_above, "Scan: enamel from this grey value up [HU or raw]")
      ->check(finiteIn(-1e9, 1e9, ""));
  cmd->add_option("--caries-below", opts->caries_below, "Scan, with --find-caries: hard tissue below this is caries [HU or raw]")
      ->check(finiteIn(-1e9, 1e9, ""));
  cmd->add_option("--scanner", opts->scanner, "Scan: thresholds of a named preset (" + toothSegmentPresetNames() + ")");
  cmd->add_flag("--find-caries", opts->find_caries, "Scan: label demineralised tissue open to the surface as caries");
  cmd->add_option("--min-island-mm3", opts->min_island_mm3, "Scan: relabel pieces of one tissue smaller than this [mm^3]")
      ->check(finiteIn(0.0, 1000.0, "mm^3"))
      ->capture_default_str();
  cmd->add_option("--voxel-size", opts->voxel_size,
                  "STL: voxel edge of the output grid [mm]; labels: true voxel size of the label volume, when its "
                  "header is wrong")
      ->check(finiteIn(kMinVoxelMm, kMaxVoxelMm, "mm"));
  cmd->add_option("--level", opts->level, "Fit the tooth into a 2^N grid (STL and scans default 9)")
      ->check(CLI::Range(DS_MIN_LEVEL, DS_MAX_LEVEL));
  // Checked in runVoxelizeMeshes rather than with CLI11's excludes(), so a clash is a one-line error.
  cmd->add_option("--frame-of", opts->frame_of,
                  "STL: voxelize into the grid of this volume (.dvol: same level, voxel size and origin), so the "
                  "two compare voxel for voxel; excludes --level and --voxel-size");
  cmd->add_option("--fill-enclosed", opts->fill_enclosed,
                  "Tissue for empty space the tooth encloses (e.g. pulp; scans: pulp unless given)");
  cmd->add_option("--seal-mm", opts->seal_mm,
                  "With --fill-enclosed: seal openings (root canal apices) narrower than about twice this "
                  "radius before filling; 0 fills only fully closed space [mm]")
      ->check(finiteIn(0.0, 10.0, "mm"))
      ->capture_default_str();
  // Checked in runVoxelize rather than with a CLI11 range, so a negative value is a one-line error.
  cmd->add_option("--min-piece", opts->min_piece,
                  "Labels: before filling, relabel each 6-connected piece of one tissue (empty included) smaller "
                  "than N source voxels to the tissue most of its faces touch; 0 keeps every piece [voxels]")
      ->capture_default_str();
  cmd->add_option("--crown-axis", opts->crown_axis,
                  "The tooth's crown direction x,y,z in the input's coordinates (default: found from where the enamel "
                  "sits against the roots)")
      ->delimiter(',')
      ->expected(3)
      ->check(finiteIn(-1e6, 1e6, ""));
  cmd->add_option("--mesial-axis", opts->mesial_axis, "The tooth's mesial direction x,y,z in the input's coordinates")
      ->delimiter(',')
      ->expected(3)
      ->check(finiteIn(-1e6, 1e6, ""));
  cmd->add_option("--buccal-axis", opts->buccal_axis, "The tooth's buccal direction x,y,z in the input's coordinates")
      ->delimiter(',')
      ->expected(3)
      ->check(finiteIn(-1e6, 1e6, ""));
  cmd->add_flag("--keep-orientation", opts->keep_orientation,
                "Record the tooth's frame but do not turn the grid to stand the crown up");
  cmd->add_flag("--force", opts->force,
                "Run a job whose estimated memory exceeds the memory budget (--max-memory-mb; the plan line says the estimate)");
  cmd->add_option("--plan-json", opts->plan_json,
                  "Append each estimate of the plan (memory, time, dense bricks) to this file as a JSON line");
  cmd->add_option("-o,--output", opts->output, "Output volume (.dvol)")->required();
  cmd->callback([opts, cmd, &action] {
    const Status usable = checkVoxelizeOptions(*opts, [cmd](const char* name) { return cmd->count(name) > 0; });
    action = [opts, usable] { return usable ? runVoxelize(*opts) : fail(usable.message()); };
  });
}

}  // namespace dentsim::app
