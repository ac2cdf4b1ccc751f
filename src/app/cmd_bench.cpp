// `dentsim bench memory|plan|voxelize|mesh|haptic|frames`: the options, then the runner in bench/ (frames_bench.cpp for frames), then what it printed and wrote (`bench scores` is in cmd_bench_scores.cpp).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <algorithm>
#include <memory>
#include <optional>
#include <sstream>
#include <thread>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "app/frames_bench.h"
#include "app/gpu_choice.h"
#include "app/terminal_progress.h"
#include "bench/bench_molar.h"
#include "bench/gpu_runners.h"
#include "bench/haptic_bench.h"
#include "bench/host_info.h"
#include "bench/memory_bench.h"
#include "bench/plan_bench.h"
#include "bench/mesh_bench.h"
#include "bench/voxelize_bench.h"
#include "core/text_format.h"
#include "gpu/context.h"
#include "gpu/mesher_kind.h"
#include "render/tooth_lod.h"
#include "volume/normal_mode.h"

namespace dentsim::app {
namespace {

// A normal mode on the command line: volume/normal_mode.h's one check.
CLI::Validator normalModeCheck() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        return parseNormalMode(text) ? std::string() : "\"" + text + "\" is not a normal mode (" + kNormalModeChoices + ")";
      },
      kNormalModeChoices, "normal mode");
}

struct MemoryBenchOptions {
  bench::CtMemorySettings settings;
  std::string out = "bench-out";  // folder for JSON, Markdown and SVG
};

struct VoxelizeBenchOptions {
  std::vector<int> levels{8, 9, 10};                     // octree levels (grid 2^L per side)
  std::vector<double> fractions{6, 12, 25, 50, 100};     // shares of the molar's triangles [%]
  int repeat = 3;                                        // timed runs per system (median)
  std::string out = "docs/bench";                        // folder for JSON, Markdown and SVG
  bool no_peers = false;                                 // skip OpenVDB
  int subsamples = 2;                                    // VoxelizeOptions::subsamples
  std::string device;                                    // Vulkan device override
};

struct MeshBenchOptions {
  bench::MeshBenchSettings settings;
  std::string out = "docs/bench";  // folder for JSON, Markdown and SVG
  bool no_warmup = false;
  bool no_peers = false;
  bool no_bur = false;
  bool no_normals = false;
  bool cpu = false;                // the single-threaded CPU reference, no Vulkan device at all
  std::string mesher = "gpu";      // GpuSurface's mesher: gpu, cpu or auto (gpu::parseMesherKind)
  std::string device;              // Vulkan device override
};

struct HapticBenchOptions {
  bench::HapticBenchSettings settings;
  std::vector<int> levels{9, 10};  // octree levels of the molar
  std::string out = "docs/bench";  // folder for JSON, Markdown and SVG
  bool cpu_voxelize = false;       // voxelize with the CPU reference even where there is a GPU
  bool no_step_only = false;       // skip the back-to-back run (and the one after idle)
  bool no_after_idle = false;      // skip the run whose steps each follow 1 ms after the last
  bool no_budget = false;          // the thread's steps without the step budget (as before issue 45)
  bool no_bare_timer = false;      // skip the bare timer (the machine's own misses)
  std::string device;              // Vulkan device override
};

std::string defaultDataDir() {
  if (const char* env = std::getenv("DENTSIM_DATA_DIR"); env && *env) return env;
  return "../shared/data";
}

// Progress lines of a runner, shown as they come.
void printLine(const std::string& line) {
  std::printf("%s\n", line.c_str());
  std::fflush(stdout);
}

template <class T>
std::string joined(const std::vector<T>& values) {
  std::ostringstream o;
  for (size_t i = 0; i < values.size(); ++i) o << (i ? "," : "") << values[i];
  return o.str();
}

Status createOutputFolder(const std::string& out) {
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) return makeError(out, "cannot create output folder: " + ec.message());
  return Ok{};
}

// ---- bench memory ------------------------------------------------------------------------------

int runMemoryBench(const MemoryBenchOptions& o) {
  if (Status s = createOutputFolder(o.out); !s) return fail(s.message());
  TerminalProgress progress;
  auto rows = bench::measureCtTeeth(o.settings, progress, printLine);
  if (!rows) return fail(rows.message());
  std::printf("\n%s", bench::memoryRowsTable(*rows).c_str());
  if (Status s = bench::writeMemoryReport(o.out, *rows); !s) return fail(s.message());
  std::printf("wrote %s/memory.json, memory.md, memory.svg\n", o.out.c_str());
  return 0;
}

// ---- bench plan --------------------------------------------------------------------------------

struct PlanBenchOptions {
  bench::PlanBenchSettings settings;
  std::string out = "docs/bench";
};

// Exit 1 when an estimate strays beyond its bound, so a change to the voxelizers that leaves the
// plan behind shows; the table says which.
int runPlanBench(PlanBenchOptions o) {
  if (Status s = createOutputFolder(o.out); !s) return fail(s.message());
  std::error_code ec;
  o.settings.dentsim = std::filesystem::read_symlink("/proc/self/exe", ec).string();
  if (ec) return fail("bench plan: cannot tell where this dentsim is (/proc/self/exe)");
  if (o.settings.scratch.empty())  // the made scan is 290 MB: kept outside the tree, for the next run
    o.settings.scratch = (std::filesystem::temp_directory_path(ec) / "dentsim-bench-plan").string();
  auto rows = bench::runPlanBench(o.settings, printLine);
  if (!rows) return fail(rows.message());
  std::printf("\n%s", bench::planRowsTable(*rows).c_str());
  if (Status s = bench::writePlanReport(o.out, *rows); !s) return fail(s.message());
  std::printf("wrote %s/plan.json, plan.md\n", o.out.c_str());
  const bool within = std::all_of(rows->begin(), rows->end(),
                                  [](const bench::PlanRow& r) { return r.memoryWithin() && r.timeWithin(); });
  if (!within) return fail("bench plan: an estimate strays beyond its bound (marked \"out\" in the table)");
  return 0;
}

// ---- bench voxelize -----------------------------------------------------------------------------

int runVoxelizeBench(const VoxelizeBenchOptions& o) {
  if (Status s = createOutputFolder(o.out); !s) return fail(s.message());
  gpu::ContextOptions context_options;
  context_options.device_override = o.device;
  auto context = gpu::Context::create(gpu::withEnvironment(context_options));
  if (!context) return fail(context.message());
  const bench::BenchMolar model = bench::loadBenchMolar();

  VoxelizeOptions voxelize;
  voxelize.subsamples = o.subsamples;
  bench::VoxelizeReportInfo info;
  info.model = model.description;
  info.command = "dentsim bench voxelize --levels " + joined(o.levels) + " --fractions " + joined(o.fractions) +
                 " --repeat " + std::to_string(o.repeat) + " --subsamples " + std::to_string(o.subsamples) +
                 (o.no_peers ? " --no-peers" : "");
  info.cpu = bench::cpuModel();
  info.cpu_threads = int(std::thread::hardware_concurrency());
  info.device = bench::deviceLabel(context->device());
  info.subsamples = o.subsamples;
  info.settings.repeats = o.repeat;
  info.settings.peers = !o.no_peers;
  std::printf("voxelize bench: %s\ndentsim on %s; CPU %s, %d threads\n", info.model.c_str(), info.device.c_str(),
              info.cpu.c_str(), info.cpu_threads);

  auto rows = bench::runVoxelizeBench(model.layers(), model.bounds(), o.levels, o.fractions, info.settings,
                                      bench::gpuVoxelizer(*context, voxelize), printLine);
  if (!rows) return fail(rows.message());
  std::printf("\n%s", bench::voxelizeReportMarkdown(info, *rows).c_str());
  if (Status s = bench::writeVoxelizeReport(o.out, info, *rows); !s) return fail(s.message());
  std::printf("wrote %s/voxelize.json, voxelize.md, voxelize.svg\n", o.out.c_str());
  return 0;
}

// ---- bench mesh --------------------------------------------------------------------------------

int runMeshBench(MeshBenchOptions o) {
  if (Status s = createOutputFolder(o.out); !s) return fail(s.message());
  o.settings.warmup = !o.no_warmup;
  o.settings.peers = !o.no_peers;
  o.settings.bur = !o.no_bur;
  o.settings.normal_errors = !o.no_normals;

  std::optional<gpu::Context> context;
  if (!o.cpu) {
    auto opened = openGpuOrFallBack(o.device, "measuring the CPU reference mesher");
    if (!opened) return fail(opened.message());
    context = std::move(*opened);
  }
  const bench::BenchMolar model = bench::loadBenchMolar();
  const std::vector<MeshLayer> layers = model.layers();
  // The molar is voxelized on the GPU where there is one (the CPU reference gives the same voxels).
  const bench::VolumeMaker maker = bench::layersVolumeMaker(context ? &*context : nullptr, layers, model.bounds());
  const gpu::MesherKind mesher = gpu::parseMesherKind(o.mesher).value_or(gpu::MesherKind::Gpu);
  const bench::MeshRunner runner = context ? bench::gpuMeshRunner(*context, mesher) : bench::cpuReferenceRunner();

  bench::MeshReportInfo info;
  info.model = model.description;
  const auto& st = o.settings;
  info.command = "dentsim bench mesh --levels " + joined(st.levels) + " --normals " + joined(st.normal_modes) +
                 " --repeat " + std::to_string(st.repeats) + " --frames " + std::to_string(st.bur_path.frames) +
                 (o.no_peers ? " --no-peers" : "") + (o.no_bur ? " --no-bur" : "") +
                 (o.no_normals ? " --no-normals" : "") + (o.cpu ? " --cpu" : " --mesher " + o.mesher);
  info.cpu = bench::cpuModel();
  info.cpu_threads = int(std::thread::hardware_concurrency());
  info.device = context ? bench::deviceLabel(context->device()) : "none";
  info.runner = runner.name;
  info.settings = o.settings;
  std::printf("mesh bench: %s\n%s; CPU %s, %d threads\n", info.model.c_str(), info.runner.c_str(), info.cpu.c_str(),
              info.cpu_threads);
  auto report = bench::runMeshBench(o.settings, maker, runner, printLine);
  if (!report) return fail(report.message());
  if (Status w = bench::writeMeshReport(o.out, info, *report); !w) return fail(w.message());
  std::printf("\n%s", bench::meshReportMarkdown(info, *report).c_str());
  std::printf("wrote %s/mesh.json, mesh.md, mesh.svg, mesh_bur.svg\n", o.out.c_str());
  return 0;
}

// ---- bench haptic ------------------------------------------------------------------------------

int runHapticBenchCommand(HapticBenchOptions o) {
  if (Status s = createOutputFolder(o.out); !s) return fail(s.message());
  o.settings.step_only = !o.no_step_only;
  o.settings.after_idle = !o.no_after_idle;
  o.settings.budget = !o.no_budget;
  o.settings.bare_timer = !o.no_bare_timer;

  std::optional<gpu::Context> context;
  if (!o.cpu_voxelize) {
    auto opened = openGpuOrFallBack(o.device, "voxelizing with the CPU reference");
    if (!opened) return fail(opened.message());
    context = std::move(*opened);
  }
  const bench::BenchMolar model = bench::loadBenchMolar();
  const std::vector<MeshLayer> layers = model.layers();
  const bench::VolumeMaker maker = bench::layersVolumeMaker(context ? &*context : nullptr, layers, model.bounds());

  bench::HapticReportInfo info;
  info.model = model.description;
  info.command = "dentsim bench haptic --levels " + joined(o.levels) + " --laps " +
                 joined(std::vector<double>{o.settings.path.laps}) + (o.cpu_voxelize ? " --cpu-voxelize" : "") +
                 (o.no_step_only ? " --no-step-only" : "") + (o.no_after_idle ? " --no-after-idle" : "") +
                 (o.settings.idle_latency_us != 0 ? " --idle-latency-us " + std::to_string(o.settings.idle_latency_us)
                                                  : std::string()) +
                 (o.no_budget ? " --no-budget" : "") +
                 (o.settings.rate_hz > 0 ? " --rate-hz " + formatted("%g", o.settings.rate_hz) : std::string()) +
                 (o.settings.contact_budget > 0 ? " --contact-budget " + formatted("%g", o.settings.contact_budget) : std::string()) +
                 (o.settings.cut_budget > 0 ? " --cut-budget " + formatted("%g", o.settings.cut_budget) : std::string()) +
                 (o.no_bare_timer ? " --no-bare-timer" : "") +
                 (o.settings.floor_offset_mm != bench::HapticBenchSettings{}.floor_offset_mm
                      ? " --floor-offset-mm " + formatted("%g", o.settings.floor_offset_mm)
                      : std::string());
  info.cpu = bench::cpuModel();
  info.cpu_threads = int(std::thread::hardware_concurrency());
  info.voxelizer = context ? "the GPU voxelizer on " + context->device().name : std::string("the CPU reference");
  info.settings = o.settings;
  info.load_before = bench::loadAverage();
  std::printf("haptic bench: %s\n%s; CPU %s, %d threads; load average %s\n", info.model.c_str(),
              info.voxelizer.c_str(), info.cpu.c_str(), info.cpu_threads, info.load_before.c_str());
  std::fflush(stdout);

  std::vector<bench::HapticBenchRow> rows;
  for (int level : o.levels) {
    auto row = bench::runHapticBench(level, maker, o.settings, printLine);
    if (!row) return fail(row.message());
    rows.push_back(std::move(row).value());
  }
  info.load_after = bench::loadAverage();
  if (Status w = bench::writeHapticReport(o.out, info, rows); !w) return fail(w.message());
  std::printf("\n%s\nload average before %s, after %s\n", bench::hapticRowsTable(rows, o.settings).c_str(),
              info.load_before.c_str(), info.load_after.c_str());
  std::printf("wrote %s/haptic.json, haptic.md, haptic.svg\n", o.out.c_str());
  return 0;
}

}  // namespace

void addBenchCommand(CLI::App& root, Action& action) {
  CLI::App* bench = root.add_subcommand("bench", "Benchmarks recorded in docs/PERFORMANCE.md (JSON, Markdown, SVG)");
  bench->require_subcommand(1);
  auto opts = std::make_shared<MemoryBenchOptions>();
  opts->settings.data_dir = defaultDataDir();
  CLI::App* memory = bench->add_subcommand("memory", "Brick-volume bytes and octree nodes of the CT teeth at levels 8-10, "
                                                     "beside the paper's Table 3 and an OpenVDB label tree");
  memory->add_option("--data", opts->settings.data_dir, "Folder with ct/tooth_N.nii.gz")->capture_default_str();
  memory->add_option("--teeth", opts->settings.teeth, "CT teeth to measure")->delimiter(',')->capture_default_str();
  memory->add_option("--levels", opts->settings.levels, "Octree levels")->delimiter(',')->check(CLI::Range(3, 12))->capture_default_str();
  memory->add_option("--out", opts->out, "Output folder")->capture_default_str();
  memory->callback([opts, &action] { action = [opts] { return runMemoryBench(*opts); }; });

  auto popts = std::make_shared<PlanBenchOptions>();
  popts->settings.data_dir = defaultDataDir();
  CLI::App* plan = bench->add_subcommand("plan", "voxelize's plan (peak memory, time) beside what each run took, "
                                                 "per input path (STL on CPU and GPU, labels, a scan) and level");
  plan->add_option("--data", popts->settings.data_dir, "Folder with teeth/ and ct/ (the shared tooth data)")
      ->capture_default_str();
  plan->add_option("--paths", popts->settings.paths, "Input paths: stl-cpu, stl-gpu, labels, scan")
      ->delimiter(',')->capture_default_str();
  plan->add_option("--levels", popts->settings.levels, "Octree levels")->delimiter(',')->check(CLI::Range(3, 13))
      ->capture_default_str();
  plan->add_option("--scratch", popts->settings.scratch, "Folder for the made scan (kept for the next run) and the runs' outputs (default: TMPDIR/dentsim-bench-plan)");
  plan->add_option("--out", popts->out, "Output folder")->capture_default_str();
  plan->callback([popts, &action] { action = [popts] { return runPlanBench(*popts); }; });

  auto vopts = std::make_shared<VoxelizeBenchOptions>();
  CLI::App* voxelize = bench->add_subcommand("voxelize", "Time to voxelize the built-in molar, decimated, at several "
                                                         "levels, beside OpenVDB's meshToVolume (paper Fig. 10, Table 1)");
  voxelize->add_option("--levels", vopts->levels, "Octree levels")->delimiter(',')->check(CLI::Range(3, 12))
      ->capture_default_str();
  voxelize->add_option("--fractions", vopts->fractions, "Shares of the triangles to keep [%]")->delimiter(',')
      ->check(finiteIn(0.01, 100.0, "%"))->capture_default_str();
  voxelize->add_option("--repeat", vopts->repeat, "Timed runs per system; the median is reported")
      ->check(CLI::Range(1, 100))->capture_default_str();
  voxelize->add_option("--out", vopts->out, "Output folder")->capture_default_str();
  voxelize->add_flag("--no-peers", vopts->no_peers, "Skip OpenVDB");
  voxelize->add_option("--subsamples", vopts->subsamples, "Rays per voxel column side (1..4)")
      ->check(CLI::Range(1, 4))->capture_default_str();
  voxelize->add_option("--device", vopts->device, "Device index or name substring (also DENTSIM_DEVICE)");
  voxelize->callback([vopts, &action] { action = [vopts] { return runVoxelizeBench(*vopts); }; });

  auto mopts = std::make_shared<MeshBenchOptions>();
  auto& ms = mopts->settings;
  CLI::App* mesh = bench->add_subcommand("mesh", "Time to re-mesh a 1/32^3 part and the whole surface of the molar at "
                                                 "levels 8-10 per normal mode (paper Fig. 15), beside VTK Flying "
                                                 "Edges; a bur path; normal errors of a sphere and torus");
  mesh->add_option("--levels", ms.levels, "Octree levels")->delimiter(',')->check(CLI::Range(5, 12))->capture_default_str();
  mesh->add_option("--normals", ms.normal_modes, std::string("Normal modes (") + kNormalModeChoices + ")")->delimiter(',')
      ->check(normalModeCheck())->capture_default_str();
  mesh->add_option("--repeat", ms.repeats, "Timed runs per measurement (median)")->check(CLI::Range(1, 100))
      ->capture_default_str();
  mesh->add_option("--part-divisor", ms.part_divisor, "The part is a cube of side dim / this")
      ->check(CLI::Range(1, 1024))->capture_default_str();
  mesh->add_option("--frames", ms.bur_path.frames, "Frames of the bur path")->check(CLI::Range(1, 100000))
      ->capture_default_str();
  mesh->add_option("--bur-level", ms.bur_path.level, "Level of the bur path")->check(CLI::Range(5, 12))
      ->capture_default_str();
  mesh->add_option("--bur-normals", ms.bur_path.normals, "Normal mode of the bur path")
      ->check(normalModeCheck())->capture_default_str();
  mesh->add_option("--normals-levels", ms.normals.levels, "Levels of the normal-error solids")->delimiter(',')
      ->check(CLI::Range(4, 10))->capture_default_str();
  mesh->add_flag("--no-warmup", mopts->no_warmup, "No untimed run before each series");
  mesh->add_flag("--no-peers", mopts->no_peers, "Skip VTK");
  mesh->add_flag("--no-bur", mopts->no_bur, "Skip the bur path");
  mesh->add_flag("--no-normals", mopts->no_normals, "Skip the normal-error table");
  auto* cpu_flag = mesh->add_flag("--cpu", mopts->cpu,
                                  "Measure the single-threaded CPU reference (meshVolumeCpu) without a Vulkan device");
  mesh->add_option("--mesher", mopts->mesher,
                   std::string("GpuSurface's mesher: the compute kernel, CPU threads, or auto (CPU threads on a CPU "
                               "device) (") + gpu::kMesherKindChoices + ")")
      ->check(mesherCheck())
      ->excludes(cpu_flag)
      ->capture_default_str();
  mesh->add_option("--out", mopts->out, "Output folder")->capture_default_str();
  mesh->add_option("--device", mopts->device, "Device index or name substring (also DENTSIM_DEVICE)");
  mesh->callback([mopts, &action] { action = [mopts] { return runMeshBench(*mopts); }; });

  auto hopts = std::make_shared<HapticBenchOptions>();
  CLI::App* haptic = bench->add_subcommand("haptic", "Step time of the haptic loop (1 kHz, its step budget) while a 1 mm round bur "
                                                     "prepares a class I cavity in the molar (thread, step-only and "
                                                     "after-idle runs, missed deadlines, points per step, the budget's overruns and force error)");
  haptic->add_option("--levels", hopts->levels, "Octree levels")->delimiter(',')->check(CLI::Range(5, 11))
      ->capture_default_str();
  haptic->add_option("--laps", hopts->settings.path.laps, "Laps of the cavity outline")->check(finiteIn(0.05, 20.0, "laps"))
      ->capture_default_str();
  haptic->add_flag("--cpu-voxelize", hopts->cpu_voxelize, "Voxelize the molar with the CPU reference");
  haptic->add_flag("--no-step-only", hopts->no_step_only,
                   "Skip the back-to-back run on the bench thread (the unbudgeted reference of the force error)");
  haptic->add_flag("--no-budget", hopts->no_budget, "Run the loop's thread without the step budget");
  haptic->add_option("--rate-hz", hopts->settings.rate_hz, "The loop's rate [Hz] (default: the preset's, 1000)")
      ->check(finiteIn(100.0, 10000.0, "rate"));
  haptic->add_option("--contact-budget", hopts->settings.contact_budget,
                     "The contact pass's budget, a fraction of the period (default: the preset's)")
      ->check(finiteIn(0.001, 0.9, "contact budget"));
  haptic->add_option("--cut-budget", hopts->settings.cut_budget,
                     "The cut stage's budget after the contact's, a fraction of the period (default: the preset's)")
      ->check(finiteIn(0.001, 0.9, "cut budget"));
  haptic->add_flag("--no-bare-timer", hopts->no_bare_timer,
                   "Skip the bare timer: after the thread, a thread at the same priority whose steps are busy waits "
                   "(the machine's own missed deadlines)");
  haptic->add_option("--floor-offset-mm", hopts->settings.floor_offset_mm,
                     "The path error's floor: step only again with the pen path moved this far [mm]; 0: skip")
      ->check(finiteIn(0.0, 1.0, "offset"))
      ->capture_default_str();
  haptic->add_flag("--no-after-idle", hopts->no_after_idle,
                   "Skip the run on the bench thread whose steps each start 1 ms after the last");
  haptic->add_option("--idle-latency-us", hopts->settings.idle_latency_us,
                     "While the loop runs, ask that idle CPUs wake within this many us (/dev/cpu_dma_latency); "
                     "-1: do not ask")
      ->check(CLI::Range(-1, 1000000))
      ->capture_default_str();
  haptic->add_option("--out", hopts->out, "Output folder")->capture_default_str();
  haptic->add_option("--device", hopts->device, "Device index or name substring (also DENTSIM_DEVICE)");
  haptic->callback([hopts, &action] { action = [hopts] { return runHapticBenchCommand(*hopts); }; });

  auto fopts = std::make_shared<FramesBenchOptions>();
  CLI::App* frames = bench->add_subcommand("frames", "Frame time of the simulator while the demo drills the molar at "
                                                     "several levels: re-mesh, tooth, tools, mirror pass, panel");
  frames->add_option("--levels", fopts->levels, "Octree levels")->delimiter(',')->check(CLI::Range(6, 11));
  frames->add_option("--frames", fopts->frames, "Frames drawn per level")->check(CLI::Range(4, 100000))->capture_default_str();
  frames->add_option("--from", fopts->from_s, "Loop time of the first frame [s]")
      ->check(finiteIn(0.0, 24.0 * 3600.0, "s"))
      ->capture_default_str();
  frames->add_option("--width", fopts->width, "Frame width [px]")->check(CLI::Range(64, 8192))->capture_default_str();
  frames->add_option("--height", fopts->height, "Frame height [px]")->check(CLI::Range(64, 8192))->capture_default_str();
  frames->add_flag("--window", fopts->window, "Draw into a window (needs a display) instead of offscreen");
  frames->add_option("--detail-pixels", fopts->detail_pixels, "Screen-sized detail's error, beside full detail [px]")
      ->check(finiteIn(0.01, render::kMaxDetailPixels, "px"))
      ->capture_default_str();
  frames->add_flag("!--no-first-frame", fopts->first_frame, "Skip timing the demo's first frame");
  addMesherOption(*frames, &fopts->mesher);
  frames->add_option("--out", fopts->out, "Output folder")->capture_default_str();
  frames->add_option("--device", fopts->device, "Vulkan device index or name part");
  frames->callback([fopts, &action] { action = [fopts] { return runFramesBench(*fopts); }; });

  addScoresBenchCommand(*bench, action);
}

}  // namespace dentsim::app
