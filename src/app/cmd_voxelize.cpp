// dentsim voxelize: builds a .dvol tooth from a segmented CT label volume (NIfTI) and a label map.
#include <cstdio>
#include <memory>
#include <optional>
#include <string>

#include "app/commands.h"
#include "app/terminal_progress.h"
#include "io/nifti_labels.h"
#include "volume/label_import.h"
#include "volume/tooth_file.h"

namespace dentsim::app {
namespace {

struct VoxelizeOptions {
  std::string labels;        // NIfTI label volume
  std::string label_map;     // "1=caries,2=enamel,3=dentin"
  double voxel_size = 0.0;   // source voxel edge [mm] for labels (overrides the header); 0: unset
  int level = 0;             // fit into a 2^level grid; 0: unset
  std::string fill_enclosed; // tissue for empty space the tooth encloses; empty: none
  double seal_mm = 0.2;       // closing radius for --fill-enclosed [mm]; about the apical foramen radius
  std::string output;        // .dvol path
};

void printSummary(const ToothVolume& tooth, const std::string& output) {
  const VolumeFrame& f = tooth.frame;
  const MaterialTotals totals = tooth.voxels.materialTotals();
  std::printf("%s: grid %lld^3 (level %d), voxel %.6g mm\n", output.c_str(), static_cast<long long>(f.dim()),
              f.level, f.voxel_mm);
  for (uint32_t m = 1; m < DS_TISSUE_COUNT; ++m) {
    const auto mat = static_cast<Material>(m);
    if (totals.voxels[m] == 0) continue;
    std::printf("  %-7s %14.4f mm^3  (%llu voxels)\n", materialName(mat).c_str(), totals.volumeMm3(mat, f.voxel_mm),
                static_cast<unsigned long long>(totals.voxels[m]));
  }
}

int runVoxelize(const VoxelizeOptions& o) {
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
      return fail("--fill-enclosed: unknown tissue '" + o.fill_enclosed + "' (expected enamel, dentin, pulp or caries)");
    import.fill_enclosed = m;
    import.seal_mm = o.seal_mm;
  }

  Result<LabelImage> image = readNiftiLabels(o.labels);
  if (!image) return fail(image.message());
  TerminalProgress progress;
  Result<ToothVolume> tooth = importLabels(*image, import, progress);
  if (!tooth) return fail(tooth.message());
  image = Error{};  // frees the labels before the save compacts and encodes the bricks
  if (Status saved = saveTooth(o.output, *tooth); !saved) return fail(saved.message());
  printSummary(*tooth, o.output);
  return 0;
}

}  // namespace

void addVoxelizeCommand(CLI::App& root, Action& action) {
  auto opts = std::make_shared<VoxelizeOptions>();
  CLI::App* cmd = root.add_subcommand("voxelize", "Build a .dvol tooth from a segmented CT label volume");
  cmd->add_option("--labels", opts->labels, "Label volume (.nii or .nii.gz)")->required();
  cmd->add_option("--label-map", opts->label_map, "Label to tissue, e.g. 1=caries,2=enamel,3=dentin")->required();
  cmd->add_option("--voxel-size", opts->voxel_size,
                  "True voxel size of the label volume [mm], when its header is wrong")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--level", opts->level, "Resample to fit the tooth into a 2^N grid")
      ->check(CLI::Range(DS_MIN_LEVEL, DS_MAX_LEVEL));
  cmd->add_option("--fill-enclosed", opts->fill_enclosed,
                  "Tissue for empty space the tooth encloses (e.g. pulp)");
  cmd->add_option("--seal-mm", opts->seal_mm,
                  "With --fill-enclosed: seal openings (root canal apices) narrower than about twice this "
                  "radius before filling; 0 fills only fully closed space [mm]")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("-o,--output", opts->output, "Output volume (.dvol)")->required();
  cmd->callback([opts, &action] { action = [opts] { return runVoxelize(*opts); }; });
}

}  // namespace dentsim::app
