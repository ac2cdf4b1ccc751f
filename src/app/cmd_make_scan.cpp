// `dentsim make-scan`: a phantom DICOM series from a segmented tooth (known tissues, a scanner's blur and noise), to try `voxelize --dicom` on a known answer.
#include <cstdio>
#include <memory>
#include <string>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "app/terminal_progress.h"
#include "io/dicom_series.h"
#include "io/nifti_labels.h"
#include "volume/clinical_phantom.h"
#include "volume/label_import.h"
#include "volume/scan_model.h"
#include "volume/tissue_table.h"

namespace dentsim::app {
namespace {

struct MakeScanOptions {
  std::string labels;       // NIfTI label volume
  std::string label_map;    // "1=caries,2=enamel,3=dentin"
  double voxel_size = 0.0;  // the labels' true voxel edge when the header is wrong [mm]; 0: the header's
  ScanModel model;
  // A clinical CT's view (volume/clinical_phantom.h): 0 / false leave the phantom as it was
  double scan_voxel_mm = 0.0;  // the scanner's voxel edge, averaged onto before the noise [mm]; 0: the labels'
  double bone_slab_mm = 0.0;   // bone around the lowest this much of the tooth [mm]; 0: none
  float bone_hu = 1000.0f;     // the slab's value: cortical and dense trabecular bone run 700..1900 HU
  bool neighbour_copy = false; // a shifted copy of the tooth beside it, touching
  bool unsigned_pixels = false;
  bool scramble_names = false;
  std::string output;       // a new or empty folder
};

// Each value the phantom paints, empty first and then every tissue of the table: "empty -1000,
// enamel 2900, dentin 1700, pulp 40, caries 700".
std::string tissueValuesText(const ScanModel& model) {
  const auto item = [&](const char* name, Material m) {
    char value[32];
    std::snprintf(value, sizeof value, "%.0f", double(model.value[size_t(m)]));
    return std::string(name) + " " + value;
  };
  std::string out = item("empty", Material::Empty);
  for (const TissueRow& row : kTissueTable) out += ", " + item(row.name, row.material);
  return out;
}

int runMakeScan(const MakeScanOptions& o) {
  if (Status st = checkOutputsAreNotInputs({o.labels}, {o.output}); !st) return fail(st.message());
  Result<LabelMap> map = parseLabelMap(o.label_map);
  if (!map) return fail("--label-map: " + map.message());
  Result<LabelImage> labels = readNiftiLabels(o.labels);
  if (!labels) return fail(labels.message());
  if (o.neighbour_copy) {
    Result<LabelImage> pair = withNeighbourCopy(*labels, o.labels);
    if (!pair) return fail(pair.message());
    labels = std::move(pair);
  }
  // The noise comes last, on the grid the scanner delivers; without resampling nor bone it is drawn
  // as simulateScan draws it, so the phantom is the one it always was.
  const bool clinical = o.scan_voxel_mm > 0.0 || o.bone_slab_mm > 0.0;
  ScanModel model = o.model;
  if (clinical) model.noise = 0.0;
  TerminalProgress progress;
  Result<GreyImage> scan = simulateScan(*labels, *map, model, o.voxel_size, o.labels, progress);
  if (!scan) return fail(scan.message());
  const int32_t bone_slices = addBoneSlab(*scan, *labels, o.bone_slab_mm, o.bone_hu);
  const double bone_mm = double(bone_slices) * scan->pitch_mm[2];
  labels = Error{};  // frees the labels before the series is written
  if (o.scan_voxel_mm > 0.0) {
    Result<GreyImage> coarse = averageOntoVoxel(*scan, o.scan_voxel_mm, o.labels);
    if (!coarse) return fail(coarse.message());
    scan = std::move(coarse);
  }
  if (clinical) addScanNoise(*scan, o.model.noise, o.model.seed);
  DicomWriteOptions w;
  w.series_description = "dentsim phantom of " + o.labels;
  w.signed_pixels = !o.unsigned_pixels;
  if (o.unsigned_pixels) w.rescale_intercept = -1024;  // stored = HU + 1024, as many scanners write
  w.scramble_names = o.scramble_names;
  Result<std::vector<std::string>> files = writeDicomSeries(o.output, *scan, w);
  if (!files) return fail(files.message());
  std::printf("%s: %zu DICOM slices of %d x %d, voxel %.4g x %.4g x %.4g mm\n", o.output.c_str(), files->size(),
              scan->dims[0], scan->dims[1], scan->pitch_mm[0], scan->pitch_mm[1], scan->pitch_mm[2]);
  std::printf("  values (HU): %s; blur %.4g mm, noise %.4g HU (seed %u)\n", tissueValuesText(o.model).c_str(),
              o.model.blur_mm, o.model.noise, o.model.seed);
  if (o.neighbour_copy) std::printf("  a copy of the tooth beside it along i, touching\n");
  if (bone_slices > 0)
    std::printf("  bone of %.0f HU around the lowest %.4g mm of the tooth\n", double(o.bone_hu), bone_mm);
  return 0;
}

}  // namespace

void addMakeScanCommand(CLI::App& root, Action& action) {
  auto opts = std::make_shared<MakeScanOptions>();
  CLI::App* cmd = root.add_subcommand(
      "make-scan", "Write a phantom CT (a DICOM series) of a segmented tooth: tissue values, blur and noise");
  cmd->add_option("--labels", opts->labels, "Label volume (.nii or .nii.gz)")->required();
  cmd->add_option("--label-map", opts->label_map, "Label to tissue, e.g. 1=caries,2=enamel,3=dentin")->required();
  cmd->add_option("--voxel-size", opts->voxel_size, "True voxel size of the label volume, when its header is wrong [mm]")
      ->check(finiteIn(1e-3, 10.0, "mm"));
  cmd->add_option("--blur-mm", opts->model.blur_mm, "Standard deviation of the scanner's point spread [mm]")
      ->check(finiteIn(0.0, 5.0, "mm"))
      ->capture_default_str();
  cmd->add_option("--noise-hu", opts->model.noise, "Standard deviation of the noise [HU]")
      ->check(finiteIn(0.0, 2000.0, "HU"))
      ->capture_default_str();
  cmd->add_option("--seed", opts->model.seed, "Seed of the noise")->capture_default_str();
  cmd->add_option("--scan-voxel-mm", opts->scan_voxel_mm,
                  "Average the phantom onto voxels of this edge before the noise, as a clinical CT sees a tooth "
                  "(e.g. 1.0) [mm]")
      ->check(finiteIn(1e-3, 10.0, "mm"));
  cmd->add_option("--bone-slab", opts->bone_slab_mm,
                  "Bone around the roots: the lowest this many mm of the tooth (along k) at least --bone-hu [mm]")
      ->check(finiteIn(0.0, 1000.0, "mm"));
  cmd->add_option("--bone-hu", opts->bone_hu, "The bone slab's value [HU]")
      ->check(finiteIn(-1000.0, 4000.0, "HU"))
      ->capture_default_str();
  cmd->add_flag("--neighbour-copy", opts->neighbour_copy, "Put a copy of the tooth beside it along i, touching, as a neighbour");
  cmd->add_flag("--unsigned", opts->unsigned_pixels, "Store unsigned pixels with a rescale intercept of -1024");
  cmd->add_flag("--scramble-names", opts->scramble_names, "Name the files out of slice order, as some exports do");
  cmd->add_option("-o,--output", opts->output, "A new or empty folder for the series")->required();
  cmd->callback([opts, &action] { action = [opts] { return runMakeScan(*opts); }; });
}

}  // namespace dentsim::app
