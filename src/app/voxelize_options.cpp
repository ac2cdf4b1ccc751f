// Reading `dentsim voxelize`'s flags into the tooth builder's options, and refusing what a source cannot use (app/voxelize_options.h).
#include "app/voxelize_options.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <tuple>

#include "app/cli_checks.h"
#include "core/text_escape.h"
#include "io/mesh_units.h"
#include "volume/tooth_file.h"

namespace dentsim::app {
namespace {

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

// The grid of an existing volume, so that a voxelization compares with it voxel for voxel. The whole
// frame is kept, scanner matrix and source box included: the grid is the same, so an export of the
// result overlays the same scan.
Result<VolumeFrame> referenceFrame(const std::string& path) {
  Result<ToothVolume> reference = loadTooth(path);
  if (!reference) return makeError("--frame-of", reference.message());
  return reference->frame;
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

// Reads the fill tissue of --fill-enclosed; `fallback` when it is not given.
Result<Material> fillTissue(const std::string& name, Material fallback) {
  if (name.empty()) return fallback;
  Material m{};
  if (!parseMaterial(name, &m) || m == Material::Empty)
    return Error{"--fill-enclosed: unknown tissue '" + escapeControl(name) + "' (expected " + tissueNameList() + ")"};
  return m;
}

// "enamel, dentin, pulp or caries": the tissues a layer (and --tooth-material) can hold.
std::string layerTissueList() {
  std::vector<std::string> names;
  for (const TissueRow& row : kTissueTable)
    if (hasLayerFlag(row)) names.push_back(row.name);
  std::string out;
  for (size_t i = 0; i < names.size(); ++i) out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return out;
}

}  // namespace

bool hasLayerFlag(const TissueRow& row) { return materialPriority(row.material) > 0; }

bool hasMeshes(const VoxelizeFlags& o) {
  for (const std::string& path : o.layer)
    if (!path.empty()) return true;
  return !o.tooth.empty();
}

std::string layerFlagList() {
  std::string out;
  for (const TissueRow& row : kTissueTable)
    if (hasLayerFlag(row)) out += (out.empty() ? "--" : "/--") + std::string(row.name);
  return out;
}


Status checkVoxelizeOptions(const VoxelizeFlags& o, const std::function<bool(const char*)>& given) {
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
                                "--find-caries", "--min-island-mm3", "--any-size"})
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
  if (Status st = refuseOption(given("--tooth-type") && o.tooth.empty(), "--tooth-type",
                               "sets the proportions of layers synthesized from --tooth; no --tooth is given");
      !st)
    return st;
  if (Status st = refuseOption(given("--tooth-type") && given("--tooth-material"), "--tooth-type",
                               "sets the proportions of synthesized layers; --tooth-material keeps one tissue");
      !st)
    return st;
  if (Status st = refuseOption(given("--pulp-from") && o.tooth.empty(), "--pulp-from",
                               "replaces the pulp synthesized from --tooth; no --tooth is given");
      !st)
    return st;
  if (Status st = refuseOption(given("--pulp-from") && given("--tooth-material"), "--pulp-from",
                               "replaces a synthesized pulp; --tooth-material keeps one tissue");
      !st)
    return st;
  if (Status st = refuseOption(given("--pulp-from") && given("--frame-of"), "--pulp-from",
                               "reads the scan in the surface's own mm; --frame-of turns the surface into another grid");
      !st)
    return st;
  if (Status st = refuseOption(given("--neighbour") && !meshes && !o.labels.empty(), "--neighbour",
                               "adds adjacent teeth to STL layers; with --labels, map their label to neighbour in "
                               "--label-map");
      !st)
    return st;
  if (Status st = refuseOption(given("--neighbour") && !meshes && (!o.dicom.empty() || !o.ct.empty()), "--neighbour",
                               "adds adjacent teeth to STL layers; a scan's tooth is cut from its neighbours");
      !st)
    return st;
  return refuseOption(given("--seal-mm") && o.fill_enclosed.empty() && !scan, "--seal-mm",
                      "seals openings for --fill-enclosed; no --fill-enclosed is given");
}

Status checkVoxelizeSources(const VoxelizeFlags& o) {
  const bool meshes = hasMeshes(o);
  const int sources = int(meshes) + int(!o.labels.empty()) + int(!o.dicom.empty()) + int(!o.ct.empty());
  if (sources > 1) return Error{"give one source: STL layers, --labels, --dicom or --ct"};
  if (!o.neighbours.empty() && !meshes && sources == 0)
    return Error{"--neighbour adds adjacent teeth to a tooth: give --tooth or " + layerFlagList() + " too"};
  if (!o.neighbours.empty() && !meshes)
    return Error{"--neighbour adds adjacent teeth to STL layers, not to --labels, --dicom or --ct (labels: map the "
                 "neighbours' label to neighbour in --label-map)"};
  std::vector<std::string> inputs(o.layer.begin(), o.layer.end());
  inputs.insert(inputs.end(), {o.tooth, o.labels, o.frame_of, o.dicom, o.ct, o.pulp_from});
  inputs.insert(inputs.end(), o.neighbours.begin(), o.neighbours.end());
  if (Status st = checkOutputsAreNotInputs(inputs, {o.output, o.plan_json}); !st) return st;
  if (meshes && (o.min_piece != 0 || !o.label_map.empty() || !o.fill_enclosed.empty()))
    return Error{"--min-piece, --label-map and --fill-enclosed apply to --labels, not to STL layers"};
  if (sources == 0)
    return Error{"nothing to voxelize: give " + layerFlagList() + " STL layers, --tooth, --labels, --dicom or --ct"};
  return Ok{};
}

Result<ToothAxesHint> axesHint(const VoxelizeFlags& o) {
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

Result<MeshToothOptions> meshToothOptions(const VoxelizeFlags& o) {
  MeshToothOptions mo;
  if (!o.frame_of.empty()) {
    if (o.level > 0 || o.voxel_size > 0.0)
      return Error{"--frame-of takes the grid of " + shownPath(o.frame_of) + "; leave out --level and --voxel-size"};
    if (!o.crown_axis.empty() || !o.mesial_axis.empty() || !o.buccal_axis.empty() || o.keep_orientation)
      return Error{"--frame-of takes the tooth frame of " + shownPath(o.frame_of) +
                   "; leave out the axes and --keep-orientation"};
    Result<VolumeFrame> f = referenceFrame(o.frame_of);
    if (!f) return f.error();
    mo.reference = *f;
    mo.reference_name = o.frame_of;
  }
  LengthUnit unit{};
  if (!parseLengthUnit(o.units, &unit))
    return Error{"--units: unknown unit '" + escapeControl(o.units) + "' (expected mm, cm, m or um)"};
  if (!(o.scale > 0.0) || !std::isfinite(o.scale)) return Error{"--scale must be a positive number"};
  mo.mm_per_unit = millimetresPer(unit) * o.scale;
  if (!o.tooth.empty()) {
    Material m = Material::Dentin;  // synthesis reads the tooth's voxels, whatever their tissue
    if (!o.tooth_material.empty() &&
        (!parseMaterial(o.tooth_material, &m) || m == Material::Empty || materialPriority(m) == 0))
      return Error{"--tooth-material: unknown tissue '" + escapeControl(o.tooth_material) + "' (expected " +
                   layerTissueList() + "; adjacent teeth: --neighbour)"};
    mo.layers.push_back({o.tooth, m});
    if (o.tooth_material.empty()) {
      LayerSynthOptions synth;
      if (!o.tooth_type.empty()) {
        std::optional<ToothType> type = parseToothType(o.tooth_type);
        if (!type)
          return Error{"--tooth-type: unknown type '" + escapeControl(o.tooth_type) + "' (expected " + toothTypeNames() +
                       ")"};
        synth.type = *type;
      }
      mo.synthesize = synth;
      mo.pulp_from = o.pulp_from;
    }
  }
  for (size_t t : layersByPriority())
    if (!o.layer[t].empty()) mo.layers.push_back({o.layer[t], kTissueTable[t].material});
  mo.neighbours = o.neighbours;
  mo.voxel_mm = o.voxel_size;
  mo.level = o.level > 0 ? o.level : 9;
  mo.voxelize.subsamples = o.subsamples;
  mo.voxelize.hole_radius = o.hole_radius;
  return mo;
}

Result<ScanToothOptions> scanToothOptions(const VoxelizeFlags& o) {
  ScanToothOptions so;
  so.dicom = o.dicom;
  so.series = o.series;
  so.ct = o.ct;
  so.voxel_mm = o.voxel_size;
  ToothSegmentOptions& seg = so.segment;
  if (!o.roi.empty()) {
    MmBox box;
    if (!parseRoi(o.roi, &box)) return Error{"--roi: expected x0,y0,z0:x1,y1,z1 in mm, not '" + escapeControl(o.roi) + "'"};
    seg.roi = box;
  }
  if (!o.seed.empty()) {
    if (o.seed.size() != 3) return Error{"--seed: expected three numbers x,y,z in mm"};
    seg.seed_mm = std::array<double, 3>{o.seed[0], o.seed[1], o.seed[2]};
  }
  seg.dentin_above = o.dentin_above;
  seg.enamel_above = o.enamel_above;
  seg.caries_below = o.caries_below;
  seg.caries = o.find_caries;
  seg.preset = o.scanner;
  seg.min_island_mm3 = o.min_island_mm3;
  so.human_size_only = !o.any_size;
  so.level = o.level > 0 ? o.level : 9;
  Result<Material> fill = fillTissue(o.fill_enclosed, Material::Pulp);
  if (!fill) return fill.error();
  so.fill = *fill;
  so.seal_mm = o.seal_mm;
  return so;
}

Result<LabelImportOptions> labelImportOptions(const VoxelizeFlags& o) {
  if (!o.frame_of.empty()) return Error{"--frame-of applies to STL layers; --labels keeps the label volume's grid"};
  if (o.label_map.empty()) return Error{"--labels needs --label-map"};
  if (o.min_piece < 0) return Error{"--min-piece must be 0 or more voxels, not " + std::to_string(o.min_piece)};
  Result<LabelMap> map = parseLabelMap(o.label_map);
  if (!map) return Error{"--label-map: " + map.message()};
  LabelImportOptions import;
  import.map = std::move(map.value());
  import.where = o.labels;
  if (o.voxel_size > 0.0) import.source_pitch_mm = o.voxel_size;
  if (o.level > 0) import.level = o.level;
  if (!o.fill_enclosed.empty()) {
    Result<Material> fill = fillTissue(o.fill_enclosed, Material::Pulp);
    if (!fill) return fill.error();
    import.fill_enclosed = *fill;
    import.seal_mm = o.seal_mm;
  }
  import.min_piece_voxels = o.min_piece;
  return import;
}

}  // namespace dentsim::app
