// One builder per tooth source (STL layers, a label volume, a scan) into a tooth volume standing in its frame: voxelize without its flags.
//
// Contents
//   1. ToothBuildHooks: progress, warnings and the plan, from the caller
//   2. buildToothFromMeshes: STL, PLY or OBJ layers, voxelized by the CPU reference or an engine the caller
//      gives; one whole-tooth surface split into layers; adjacent teeth as neighbour voxels
//   3. buildToothFromLabels: a label volume imported
//   4. buildToothFromScan: a grey-value volume segmented into tissues, then imported
//
// Every builder ends with standToothUp (volume/tooth_frame.h): the crown axis from the hint, the
// enamel, or a synthesized tooth's shape, the grid turned unless hint.turn is false. The caller saves and prints. The GPU voxelizer
// sits in a later stage than this one, so it comes in as a MeshVoxelizeEngine.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/interrupter.h"
#include "core/result.h"
#include "io/dicom_series.h"
#include "io/grey_image.h"
#include "io/nifti_labels.h"
#include "volume/brick_volume.h"
#include "volume/ct_segment.h"
#include "volume/label_import.h"
#include "volume/mesh_voxelizer.h"
#include "volume/tooth_frame.h"
#include "volume/tooth_layer_synth.h"
#include "volume/voxelize_plan.h"

namespace dentsim {

// ---- 1. ToothBuildHooks -----------------------------------------------------------------------
struct ToothBuildHooks {
  Interrupter* progress = nullptr;                      // nullptr: nullInterrupter()
  std::function<void(const std::string&)> warn;         // each warning as it arises, one line; empty: dropped
  std::function<Status(const VoxelizeCost&)> approve;   // the plan, once a job's cost is known; an error ends the build
};

// ---- 2. buildToothFromMeshes ------------------------------------------------------------------
struct MeshLayerSource {
  std::string path;                     // STL file, or PLY or OBJ when its name ends in .ply or .obj
  Material material = Material::Dentin;  // the tissue inside it
};

// A voxelizer other than the CPU reference (the GPU's, from app), for the same RaySetup and the same
// result. `open` runs once the rays are set up and before the plan, whose estimate depends on it.
struct MeshVoxelizeEngine {
  std::function<Result<bool>()> open;  // true: `run` voxelizes; false: the CPU reference does; an error ends the build
  std::function<Result<BrickVolume>(const RaySetup&, const VoxelizeOptions&, Interrupter&)> run;
};

struct MeshToothOptions {
  std::vector<MeshLayerSource> layers;   // loaded and listed in this order
  double mm_per_unit = 1.0;              // STL coordinate unit to mm (the unit times any extra scale)
  // The grid and tooth frame of an existing volume (`--frame-of`), so that the two compare voxel for
  // voxel; the meshes turn as its tooth was turned, and the frame is kept, not found again.
  std::optional<VolumeFrame> reference;
  std::string reference_name;            // names the reference where the meshes reach outside its grid
  double voxel_mm = 0.0;                 // without a reference: the output voxel edge [mm]; 0: fit to `level`
  int level = 9;                         // without a reference and voxel_mm: fit into a 2^level grid
  VoxelizeOptions voxelize;
  MeshVoxelizeEngine engine;             // empty `open`: the CPU reference
  // The one layer is a whole tooth's closed surface: its voxels are split into enamel, dentin and
  // pulp (volume/tooth_layer_synth.h), and the crown axis and mesial found there stand it up, as
  // Found. `crown` here is ignored: the hint's crown, when given, is passed on. None: as voxelized.
  std::optional<LayerSynthOptions> synthesize;
  // Adjacent teeth's closed surfaces (STL, PLY or OBJ), each whole: voxelized by the CPU reference in the
  // same grid (fitted to the tooth and them) and kept as Material::Neighbour where the tooth is
  // empty, the tooth winning shared voxels. They stay out of the crown axis and the layers.
  std::vector<std::string> neighbours;
  // With `synthesize` and no reference: a grey-value scan of the same tooth (NIfTI or NRRD, or a DICOM
  // folder) whose dark space inside the tooth becomes the pulp in place of the synthesized one. The
  // surface's mm (after mm_per_unit) are taken to be the scan's world mm, as a segmentation exported
  // from that scan has them. Empty: the pulp stays synthesized.
  std::string pulp_from;
};

// The pulp taken from a scan (MeshToothOptions::pulp_from): the tooth's voxels, enamel left out, that
// lie at least kScanPulpDepthVoxels inside the tooth and whose grey value is below `threshold`.
struct ScanPulpReport {
  double dentin_grey = 0.0;     // median grey value of the tooth's deep voxels (the bulk of a tooth is dentin) [scan's unit]
  double around_grey = 0.0;     // median grey value of the voxels just outside the tooth (soft tissue, air) [scan's unit]
  double threshold = 0.0;       // midway between the two: darker is pulp [scan's unit]
  GreyUnit unit = GreyUnit::Raw;
  uint64_t pulp_voxels = 0;     // voxels that are pulp now
  double pulp_mm3 = 0.0;        // their volume [mm^3]
  double synthesized_pulp_mm3 = 0.0;  // the synthesized pulp it replaced [mm^3]
  std::string line;             // "pulp from the scan NAME (N mm^3), enamel synthesized; ...", also in synthesized->lines
};
// How deep inside the tooth [voxels, 6-connected] a dark voxel must lie to be pulp: the rim's voxels
// sample the scan half outside the tooth, and a dark dent in the surface is no pulp.
inline constexpr int kScanPulpDepthVoxels = 2;

struct MeshToothReport {
  struct Layer {
    std::string path;
    Material material = Material::Dentin;
    size_t triangles = 0;
    double volume_mm3 = 0.0;  // |signed volume| of the mesh, after the unit [mm^3]
  };
  std::vector<Layer> layers;  // in MeshToothOptions::layers' order
  bool engine_ran = false;    // the caller's engine voxelized (else the CPU reference)
  double voxelize_ms = 0.0;   // wall time of the voxelization alone [ms]
  std::optional<LayerSynthReport> synthesized;  // with MeshToothOptions::synthesize: what was found and made
  std::vector<Layer> neighbours;                // in MeshToothOptions::neighbours' order, material Neighbour
  uint64_t neighbour_voxels = 0;                // voxels that became Neighbour (the tooth's kept where shared)
  std::optional<ScanPulpReport> scan_pulp;      // with MeshToothOptions::pulp_from
};

// Reads each layer and neighbour (warning on holes, non-manifold or flipped edges, an inside-out mesh
// and an implausible extent, naming the file), scales it to mm, fits the grid to all of them (or
// takes the reference's), sets up the rays, asks the engine and the plan, voxelizes, synthesizes the
// layers when asked (recording it in the tooth: LayerSource::Synthesized, the report's lines in
// source_note), takes the pulp from the scan when given (read before the voxelization; the grid is
// not yet turned, so its mm are the surface's), adds the neighbours, and stands the tooth up (not
// with a reference, whose frame is kept). Errors: the first file that cannot be read, synthesis
// asked with other than one layer, a grid that does not fit, the engine's or the plan's error,
// synthesizeLayers' error, a cancel, and standToothUp's; with pulp_from also the scan's reader's, a
// scan without synthesis or with a reference, a tooth's box not inside the scan's (both boxes named),
// and a scan no brighter inside the tooth than around it.
Result<ToothVolume> buildToothFromMeshes(const MeshToothOptions& options, const ToothAxesHint& hint,
                                         const ToothBuildHooks& hooks, MeshToothReport* report = nullptr);

// The neighbours' voxels join the tooth's where the tooth has none, as Material::Neighbour with
// their own fill: the tooth wins every voxel it reaches, so its voxels are those of a run without
// neighbours. Returns the voxels added. Both volumes are on one grid. Used by buildToothFromMeshes
// and the built-in molar's neighbours (sim/builtin_tooth.h).
uint64_t addNeighbours(BrickVolume& tooth, const BrickVolume& neighbours);

// ---- 3. buildToothFromLabels ------------------------------------------------------------------
// Imports `image` with `import` (its `approve` is hooks.approve when the hooks have one), warns when
// the tissue's extent at the pitch is no tooth's (a header's pitch in the wrong unit), and stands
// the tooth up. Errors: importLabels' and standToothUp's.
Result<ToothVolume> buildToothFromLabels(const LabelImage& image, LabelImportOptions import, const ToothAxesHint& hint,
                                         const ToothBuildHooks& hooks, LabelImportReport* report = nullptr);

// ---- 4. buildToothFromScan --------------------------------------------------------------------
struct ScanToothOptions {
  std::string dicom;                 // a DICOM series' folder, or one multi-frame file; empty: `ct`
  std::string series;                // with dicom: the Series Instance UID to read
  std::string ct;                    // a NIfTI or NRRD grey-value volume
  double voxel_mm = 0.0;             // the scan's true voxel edge, when its header is wrong [mm]; 0: the header's
  ScanReadApproval approve_read;     // asked once the header gives the size (the DICOM reader asks in its child too)
  ToothSegmentOptions segment;       // `where` is set to the source
  int level = 9;                     // the tooth is fitted into a 2^level grid
  Material fill = Material::Pulp;    // the space the dentin encloses
  double seal_mm = 0.2;              // closing radius for that fill [mm]
  // Refuse a tooth outside the range of human teeth (volume/tooth_sanity.h). Off by default, since
  // tests of the pipeline's mechanics segment phantoms a few mm wide; `voxelize` turns it on unless
  // --any-size.
  bool human_size_only = false;
};

struct ScanToothReport {
  ToothSegmentReport segment;
  int32_t dicom_files = 0;           // files of the DICOM series read; 0 for --ct
  // What the segmentation chose, as `voxelize` prints it and the tooth's source_note keeps it: the
  // scan, the thresholds, the tooth's box, the clean-up, and last the pulp line.
  std::vector<std::string> lines;
};

// Reads the scan, applies voxel_mm, segments the tooth (warning when a seed keeps less than half of
// the hard tissue joined to it, and when the voxels are too coarse for enamel), imports the labels
// with the pulp filled, stands the tooth up and records `lines` in source_note. The grey values are
// freed before the import. Errors: the reader's, segmentTooth's, a dentin threshold below soft tissue
// in HU, with human_size_only a tooth no human tooth's size (each naming what to try), importLabels'
// and standToothUp's. A refused tooth leaves no warning behind it: its error is the one line.
Result<ToothVolume> buildToothFromScan(const ScanToothOptions& options, const ToothAxesHint& hint,
                                       const ToothBuildHooks& hooks, ScanToothReport* report = nullptr);

// The scan path after reading, for a GreyImage already in memory: `described` names it in the
// first line. The image is consumed (freed before the import).
Result<ToothVolume> buildToothFromGreyImage(GreyImage image, const std::string& described, const ScanToothOptions& options,
                                            const ToothAxesHint& hint, const ToothBuildHooks& hooks,
                                            ScanToothReport* report = nullptr);

}  // namespace dentsim
