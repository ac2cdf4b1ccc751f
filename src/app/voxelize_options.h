// The flags of `dentsim voxelize`, which of them a source refuses, and their translation into the tooth builder's options (volume/tooth_builder.h).
#pragma once

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/result.h"
#include "volume/tissue_table.h"
#include "volume/tooth_builder.h"

namespace dentsim::app {

// The voxel edges a tooth can have: a micro-CT's 1 um to a coarse 10 mm [mm].
constexpr double kMinVoxelMm = 1e-3, kMaxVoxelMm = 10.0;

struct VoxelizeFlags {
  // STL layers, one file per tissue of the table that the voxelizer layers (--enamel, --dentin, ...),
  // or a whole tooth's one surface
  std::array<std::string, kTissueCount> layer;  // by tissue table row; empty: none
  std::string tooth;
  std::string tooth_material;             // one tissue for all of --tooth; empty: layers synthesized
  std::string tooth_type;                 // the synthesized layers' proportions; empty: guessed
  std::vector<std::string> neighbours;    // adjacent teeth's surfaces (--neighbour, repeatable)
  std::string pulp_from;                  // a grey-value scan of the same tooth whose pulp replaces the synthesized one
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
  bool any_size = false;      // keep a segmented tooth outside the range of human teeth (animal teeth, models)
  std::string output;        // .dvol path
  // The tooth's frame, in the input's coordinates; empty: found (crown) or not known (mesial, buccal)
  std::vector<double> crown_axis, mesial_axis, buccal_axis;
  bool keep_orientation = false;  // record the frame but do not turn the grid
  bool force = false;             // run a job planned beyond the memory budget all the same
  std::string plan_json;          // append each estimate here as a JSON line; empty: none
};

// True when STL layers (a tissue's flag or --tooth) are the source.
bool hasMeshes(const VoxelizeFlags& o);
// Whether a tissue of the table has its own layer flag: those the voxelizer layers (not the
// neighbour, which --neighbour adds whole).
bool hasLayerFlag(const TissueRow& row);
// "--enamel/--dentin/--pulp/--caries", for messages.
std::string layerFlagList();

// Options the chosen input cannot use, each refused with the reason; `given` says whether the user
// gave an option (CLI::App::count()), since a default value looks the same as one given.
Status checkVoxelizeOptions(const VoxelizeFlags& o, const std::function<bool(const char*)>& given);
// One source, outputs that are not inputs, and what STL layers refuse; an error names the flags.
Status checkVoxelizeSources(const VoxelizeFlags& o);

// The axes given (--crown-axis, --mesial-axis, --buccal-axis) and --keep-orientation.
Result<ToothAxesHint> axesHint(const VoxelizeFlags& o);

// STL layers: the reference grid of --frame-of read first (so a bad file fails before any mesh is
// loaded), the unit, the layers (--tooth, then the tissues in the voxelizer's priority). No engine:
// the command gives the GPU.
Result<MeshToothOptions> meshToothOptions(const VoxelizeFlags& o);
// A scan: the source, the ROI and seed, thresholds, the level and the pulp fill. No read approval:
// the command plans the read.
Result<ScanToothOptions> scanToothOptions(const VoxelizeFlags& o);
// --labels: what it refuses (--frame-of), needs (--label-map) and the import's options.
Result<LabelImportOptions> labelImportOptions(const VoxelizeFlags& o);

}  // namespace dentsim::app
