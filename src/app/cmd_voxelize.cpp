// dentsim voxelize: the command's flags and printing around the tooth builder (STL layers on the GPU, a label volume, or a scan).
#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "app/gpu_choice.h"
#include "app/terminal_progress.h"
#include "app/voxelize_options.h"
#include "core/text_escape.h"
#include "gpu/gpu_voxelizer.h"
#include "io/input_budget.h"
#include "io/nifti_labels.h"
#include "volume/tissue_table.h"
#include "volume/tooth_builder.h"
#include "volume/tooth_file.h"
#include "volume/voxelize_plan.h"

namespace dentsim::app {
namespace {

// Says what the job will cost before it starts, and refuses one beyond the memory budget unless --force.
// With --plan-json the estimate is also appended as one JSON line, for `dentsim bench plan` and scripts.
Status planJob(const dentsim::VoxelizeCost& cost, const VoxelizeFlags& o) {
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

// A synthesized tooth's axes come from its shape, a measured tooth's crown from its enamel.
const char* axisSourceText(AxisSource s, bool from_shape) {
  if (s == AxisSource::Found) return from_shape ? "found from the tooth's shape" : "found from the enamel";
  return s == AxisSource::Given ? "given" : "not known";
}

// One line on the tooth's frame: how the crown axis was known and whether the grid was turned.
void printFrame(const ToothVolume& tooth) {
  const ToothAxes& t = tooth.frame.tooth;
  const bool shape = tooth.layers == LayerSource::Synthesized;
  std::printf("  crown axis %s, now (%.3f, %.3f, %.3f)%s; mesial %s\n", axisSourceText(t.crown_source, shape),
              t.crown[0], t.crown[1], t.crown[2], t.turned() ? " after quarter turns that stand the crown up" : "",
              axisSourceText(t.mesial_source, shape));
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
    if (totals.voxels[m] == 0 || !isToothTissue(mat)) continue;
    std::printf("  %-7s %14.4f mm^3  (%llu voxels)\n", materialName(mat).c_str(), totals.volumeMm3(mat, f.voxel_mm),
                static_cast<unsigned long long>(totals.voxels[m]));
  }
  // Adjacent teeth are in the volume but are no part of the tooth: apart, so the lines above sum to it.
  if (const uint32_t n = DS_MAT_NEIGHBOUR; totals.voxels[n] > 0)
    std::printf("  beside it, its neighbours: %.4f mm^3  (%llu voxels)\n",
                totals.volumeMm3(Material::Neighbour, f.voxel_mm), static_cast<unsigned long long>(totals.voxels[n]));
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

// What the build needs from the command: progress on the terminal, warnings, and the plan.
ToothBuildHooks buildHooks(const VoxelizeFlags& o, TerminalProgress& progress) {
  ToothBuildHooks hooks;
  hooks.progress = &progress;
  hooks.warn = [](const std::string& line) { warn(line); };
  hooks.approve = [&o](const dentsim::VoxelizeCost& cost) { return planJob(cost, o); };
  return hooks;
}

void printVoxelizeTime(const std::string& engine, int subsamples, double ms, const gpu::VoxelizeTiming& timing) {
  std::printf("  voxelized on the %s, %d x %d rays per voxel, in %.0f ms", engine.c_str(), subsamples, subsamples, ms);
  if (timing.bands > 0)
    std::printf(" (voxelizer %.0f ms, kernels %.0f ms: count+scan %.0f, store+sort %.0f, paint %.0f, chunks %.0f; "
                "%llu hits, %llu dense bricks, %u band%s)", timing.total_ms, timing.kernels_ms, timing.count_scan_ms,
                timing.store_sort_ms, timing.paint_ms, timing.chunks_ms, static_cast<unsigned long long>(timing.hits),
                static_cast<unsigned long long>(timing.dense_bricks), timing.bands, timing.bands == 1 ? "" : "s");
  std::printf("\n");
}

int runVoxelizeMeshes(const VoxelizeFlags& o) {
  Result<MeshToothOptions> mo = meshToothOptions(o);
  if (!mo) return fail(mo.message());
  auto hint = axesHint(o);
  if (!hint) return fail(hint.message());
  // The GPU is opened once the rays are set up (a bad mesh fails first); without one, the CPU reference runs.
  std::optional<gpu::Context> gpu_context;
  gpu::VoxelizeTiming timing;
  if (!o.cpu) {
    mo->engine.open = [&o, &gpu_context]() -> Result<bool> {
      auto ctx = openGpuOrFallBack(o.device, "voxelizing on the CPU");
      if (!ctx) return ctx.error();
      gpu_context = std::move(ctx).value();
      return gpu_context.has_value();
    };
    mo->engine.run = [&gpu_context, &timing](const RaySetup& setup, const dentsim::VoxelizeOptions& vo, Interrupter& in) {
      return gpu::voxelizeGpu(*gpu_context, setup, vo, &timing, in);
    };
  }
  TerminalProgress progress;
  MeshToothReport report;
  Result<ToothVolume> tooth = buildToothFromMeshes(*mo, *hint, buildHooks(o, progress), &report);
  if (!tooth) return fail(tooth.message());
  if (Status saved = saveTooth(o.output, *tooth); !saved) return fail(saved.message());
  printSummary(*tooth, o.output);
  if (mo->reference) std::printf("  grid and tooth frame of %s\n", shownPath(o.frame_of).c_str());
  else printFrame(*tooth);
  const std::string engine = report.engine_ran ? "GPU (" + gpu_context->device().name + ")" : "CPU reference";
  printVoxelizeTime(engine, o.subsamples, report.voxelize_ms, timing);
  for (const MeshToothReport::Layer& l : report.layers)
    std::printf("  layer %-7s %s: %zu triangles, mesh volume %.4f mm^3\n",
                report.synthesized ? "tooth" : materialName(l.material).c_str(), shownPath(l.path).c_str(), l.triangles,
                l.volume_mm3);
  for (const MeshToothReport::Layer& l : report.neighbours)
    std::printf("  neighbour %s: %zu triangles, mesh volume %.4f mm^3\n", shownPath(l.path).c_str(), l.triangles,
                l.volume_mm3);
  if (!report.neighbours.empty())
    std::printf("  neighbour voxels %llu, where the tooth has none\n",
                static_cast<unsigned long long>(report.neighbour_voxels));
  // The synthesizer's lines (the first says the layers are synthesized, not measured); kept in the file.
  if (report.synthesized)
    for (const std::string& line : report.synthesized->lines) std::printf("  %s\n", escapeControl(line, line.size()).c_str());
  return 0;
}

int runVoxelizeScan(const VoxelizeFlags& o) {
  auto hint = axesHint(o);
  if (!hint) return fail(hint.message());
  Result<ScanToothOptions> so = scanToothOptions(o);
  if (!so) return fail(so.message());
  // The read is planned once its header gives the size, before the values are allocated. The DICOM
  // reader asks in its checking child too (the same answer); only this process prints the plan.
  const pid_t planner = ::getpid();
  so->approve_read = [&o, planner](uint64_t voxels, uint32_t stored_bytes) -> Status {
    const VoxelizeCost cost = estimateScanRead(voxels, stored_bytes);
    if (::getpid() != planner) return checkAffordable(cost, memoryBudgetBytes(), o.force, "voxelize");
    return planJob(cost, o);
  };
  TerminalProgress progress;
  ScanToothReport report;
  Result<ToothVolume> tooth = buildToothFromScan(*so, *hint, buildHooks(o, progress), &report);
  if (!tooth) return fail(tooth.message());
  if (Status saved = saveTooth(o.output, *tooth); !saved) return fail(saved.message());
  printSummary(*tooth, o.output);
  printFrame(*tooth);
  for (const std::string& line : report.lines) std::printf("  %s\n", line.c_str());
  return 0;
}

int runVoxelize(const VoxelizeFlags& o) {
  if (Status st = checkVoxelizeSources(o); !st) return fail(st.message());
  if (hasMeshes(o)) return runVoxelizeMeshes(o);
  if (!o.dicom.empty() || !o.ct.empty()) return runVoxelizeScan(o);
  Result<LabelImportOptions> import = labelImportOptions(o);
  if (!import) return fail(import.message());
  auto hint = axesHint(o);
  if (!hint) return fail(hint.message());
  Result<LabelImage> image = readNiftiLabels(o.labels);
  if (!image) return fail(image.message());
  TerminalProgress progress;
  LabelImportReport report;
  Result<ToothVolume> tooth = buildToothFromLabels(*image, *import, *hint, buildHooks(o, progress), &report);
  if (!tooth) return fail(tooth.message());
  image = Error{};  // frees the labels before the save compacts and encodes the bricks
  if (Status saved = saveTooth(o.output, *tooth); !saved) return fail(saved.message());
  printSummary(*tooth, o.output);
  printFrame(*tooth);
  printCleanup(report.cleanup, o.min_piece);
  return 0;
}

}  // namespace

void addVoxelizeCommand(CLI::App& root, Action& action) {
  auto opts = std::make_shared<VoxelizeFlags>();
  CLI::App* cmd = root.add_subcommand("voxelize", "Build a .dvol tooth from STL tissue layers, one whole-tooth surface, a segmented CT label volume, or a scan (DICOM, NIfTI, NRRD)");
  for (size_t t = 0; t < kTissueCount; ++t) {
    if (!hasLayerFlag(kTissueTable[t])) continue;  // the neighbour: --neighbour, whole teeth, repeatable
    std::string help = kTissueTable[t].name;
    help[0] = char(std::toupper(static_cast<unsigned char>(help[0])));
    cmd->add_option("--" + std::string(kTissueTable[t].name), opts->layer[t], help + " surface (STL)");
  }
  cmd->add_option("--tooth", opts->tooth,
                  "A whole tooth as one closed surface (STL, PLY or OBJ): enamel, dentin and pulp are synthesized from "
                  "its shape by published proportions, and its crown axis found there (docs/VOXELIZE.md)");
  cmd->add_option("--tooth-material", opts->tooth_material,
                  "Keep --tooth one tissue, this one (e.g. dentin): no layers are synthesized");
  cmd->add_option("--tooth-type", opts->tooth_type,
                  "The synthesized layers' proportions: " + toothTypeNames() + " (default: guessed from the size and roots)");
  cmd->add_option("--pulp-from", opts->pulp_from,
                  "With --tooth: take the pulp from a grey-value scan of the same tooth (NIfTI, NRRD or a DICOM "
                  "folder) instead of synthesizing it; the surface's mm (after --units and --scale) must be the "
                  "scan's world mm, as in a segmentation exported from that scan. Enamel stays synthesized");
  cmd->add_option("--neighbour", opts->neighbours,
                  "An adjacent tooth's closed surface (STL, PLY or OBJ), whole, as neighbour tissue in the same grid; "
                  "repeat for each (with --tooth or the tissue layers)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
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
  cmd->add_flag("--any-size", opts->any_size,
                "Scan: keep a tooth outside the range of human teeth (50..3000 mm^3 of hard tissue, 35 mm long), "
                "for animal teeth and enlarged models; without it such a tooth is refused");
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
