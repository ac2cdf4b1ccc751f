// dentsim export: writes a .dvol tooth as a NIfTI label volume (0 empty, 1 enamel, 2 dentin, 3 pulp, 4 caries).
#include <cstdio>
#include <memory>
#include <string>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "io/nifti_labels.h"
#include "volume/label_import.h"
#include "volume/tooth_file.h"

namespace dentsim::app {
namespace {

struct ExportOptions {
  std::string input;   // .dvol path
  std::string output;  // .nii or .nii.gz path
};

int runExport(const ExportOptions& o) {
  if (Status st = checkOutputsAreNotInputs({o.input}, {o.output}); !st) return fail(st.message());
  Result<ToothVolume> tooth = loadTooth(o.input);
  if (!tooth) return fail(tooth.message());
  const LabelImage image = exportLabels(*tooth);
  if (Status written = writeNiftiLabels(o.output, image); !written) {
    // The NIfTI writer cannot always tell why; the folder and the free space can.
    const std::string why = whyCannotWrite(o.output, image.labels.size() + 352);
    return fail(written.message() + (why.empty() ? "" : " (" + why + ")"));
  }
  std::printf("%s: %d x %d x %d labels, voxel %.6g mm\n", o.output.c_str(), image.dims[0], image.dims[1],
              image.dims[2], image.pitch_mm[0]);
  return 0;
}

}  // namespace

void addExportCommand(CLI::App& root, Action& action) {
  auto opts = std::make_shared<ExportOptions>();
  CLI::App* cmd = root.add_subcommand("export", "Write a .dvol tooth as a NIfTI label volume for 3D Slicer or ITK-SNAP");
  cmd->add_option("input", opts->input, "Volume file (.dvol)")->required();
  cmd->add_option("-o,--output", opts->output, "Label volume (.nii or .nii.gz)")->required();
  cmd->callback([opts, &action] { action = [opts] { return runExport(*opts); }; });
}

}  // namespace dentsim::app
