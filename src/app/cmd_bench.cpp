// `dentsim bench memory` and `bench voxelize`: brick bytes and voxelization time beside the paper and OpenVDB, as JSON, Markdown and SVG.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <thread>

#include "app/commands.h"
#include "app/terminal_progress.h"
#include "bench/memory_bench.h"
#include "bench/voxelize_bench.h"
#include "gpu/context.h"
#include "gpu/gpu_voxelizer.h"
#include "io/nifti_labels.h"
#include "model/builtin_assets.h"
#include "volume/label_import.h"
#include "volume/mesh_voxelizer.h"

namespace dentsim::app {
namespace {

struct BenchOptions {
  std::string data_dir;                            // real tooth data (../shared/data)
  std::vector<std::string> teeth{"tooth_2", "tooth_3"};  // CT teeth in data_dir/ct
  std::vector<int> levels{8, 9, 10};               // octree levels to fit each tooth into
  std::string out = "bench-out";                   // folder for JSON, Markdown and SVG
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

std::string defaultDataDir() {
  if (const char* env = std::getenv("DENTSIM_DATA_DIR"); env && *env) return env;
  return "../shared/data";
}

Status writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) return makeError(path, "cannot write");
  return Ok{};
}

int runMemoryBench(const BenchOptions& o) {
  std::error_code ec;
  std::filesystem::create_directories(o.out, ec);
  if (ec) return fail(o.out + ": cannot create output folder: " + ec.message());
  auto map = parseLabelMap("1=caries,2=enamel,3=dentin");  // the data README's labels
  if (!map) return fail(map.message());
  std::vector<bench::MemoryRow> rows;
  TerminalProgress progress;
  for (const std::string& tooth : o.teeth) {
    const std::string path = o.data_dir + "/ct/" + tooth + ".nii.gz";
    auto image = readNiftiLabels(path);
    if (!image) return fail(image.message() + " (set --data or DENTSIM_DATA_DIR)");
    for (int level : o.levels) {
      LabelImportOptions opt;
      opt.map = *map;
      opt.level = level;
      opt.source_pitch_mm = 0.034;  // the header says 1.0; the data README gives the true pitch
      opt.where = path;
      const auto start = std::chrono::steady_clock::now();
      auto volume = importLabels(*image, opt, progress);
      if (!volume) return fail(volume.message());
      volume->voxels.compact();
      const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      rows.push_back(bench::measureMemory(tooth, *volume, build_s));
      const auto& r = rows.back();
      std::printf("%s level %d: dentsim %.2f MB, %s %s MB, paper %.1f MB\n", tooth.c_str(), level,
                  double(r.stats.bytes) / 1e6, r.openvdb.name.c_str(),
                  r.openvdb.available ? std::to_string(double(r.openvdb.bytes) / 1e6).c_str() : "n/a", r.paper_mb);
    }
  }
  const std::string table = bench::memoryRowsTable(rows);
  std::printf("\n%s", table.c_str());
  for (const auto& [name, text] : {std::pair{std::string("memory.json"), bench::memoryRowsJson(rows).dump(2) + "\n"},
                                   {std::string("memory.md"), table},
                                   {std::string("memory.svg"), bench::memoryRowsSvg(rows)}}) {
    if (auto s = writeText(o.out + "/" + name, text); !s) return fail(s.message());
  }
  std::printf("wrote %s/memory.json, memory.md, memory.svg\n", o.out.c_str());
  return 0;
}

// ---- bench voxelize -----------------------------------------------------------------------------

// dentsim's side of a run: ray set-up and GPU voxelization into bricks mirrored on the CPU, timed by
// the host clock from the meshes to the CPU bricks.
bench::DentsimVoxelizer gpuVoxelizer(gpu::Context& context, const VoxelizeOptions& options) {
  return [&context, options](const std::vector<MeshLayer>& layers,
                             const VolumeFrame& frame) -> Result<bench::DentsimRun> {
    const auto start = std::chrono::steady_clock::now();
    auto setup = makeRaySetup(layers, frame, options);
    if (!setup) return setup.error();
    gpu::VoxelizeTiming timing;
    auto volume = gpu::voxelizeGpu(context, *setup, options, &timing);
    if (!volume) return volume.error();
    bench::DentsimRun run;
    run.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    run.kernel_ms = timing.kernels_ms;
    run.hits = timing.hits;
    run.dense_bricks = volume->stats().dense_bricks;
    run.totals = volume->materialTotals();
    return run;
  };
}

// The built-in molar's layers, or freshly generated ones (the same meshes) while assets/ is empty.
struct MolarModel {
  MolarLayers molar;
  std::string description;
};
MolarModel loadMolarForBench() {
  MolarModel m;
  if (auto loaded = loadBuiltinMolar()) {
    m.molar = std::move(loaded).value();
    m.description = "built-in four-layer molar (assets/teeth/molar_*.stl)";
  } else {
    m.molar = generateMolar();
    m.description = "four-layer molar from generateMolar() (assets/ held none: " + loaded.message() + ")";
  }
  return m;
}

std::string cpuModel() {
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0) {
      const size_t colon = line.find(':');
      if (colon != std::string::npos) return line.substr(line.find_first_not_of(' ', colon + 1));
    }
  return "unknown CPU";
}

template <class T>
std::string joined(const std::vector<T>& values) {
  std::ostringstream o;
  for (size_t i = 0; i < values.size(); ++i) o << (i ? "," : "") << values[i];
  return o.str();
}

int runVoxelizeBench(const VoxelizeBenchOptions& o) {
  std::error_code ec;
  std::filesystem::create_directories(o.out, ec);
  if (ec) return fail(o.out + ": cannot create output folder: " + ec.message());

  gpu::ContextOptions context_options;
  context_options.device_override = o.device;
  auto context = gpu::Context::create(gpu::withEnvironment(context_options));
  if (!context) return fail(context.message());

  const MolarModel model = loadMolarForBench();
  const std::vector<MeshLayer> layers{{Material::Enamel, &model.molar.enamel, "enamel"},
                                      {Material::Dentin, &model.molar.dentin, "dentin"},
                                      {Material::Pulp, &model.molar.pulp, "pulp"},
                                      {Material::Caries, &model.molar.caries, "caries"}};
  Bounds3 bounds;
  for (const MeshLayer& l : layers) bounds.add(l.mesh->bounds());

  VoxelizeOptions voxelize;
  voxelize.subsamples = o.subsamples;
  bench::VoxelizeReportInfo info;
  info.model = model.description;
  info.command = "dentsim bench voxelize --levels " + joined(o.levels) + " --fractions " + joined(o.fractions) +
                 " --repeat " + std::to_string(o.repeat) + " --subsamples " + std::to_string(o.subsamples) +
                 (o.no_peers ? " --no-peers" : "");
  info.cpu = cpuModel();
  info.cpu_threads = int(std::thread::hardware_concurrency());
  const gpu::DeviceInfo& device = context->device();
  info.device = device.name + (device.driver_info.empty() ? "" : " (" + device.driver_info + ")");
  info.subsamples = o.subsamples;
  info.settings.repeats = o.repeat;
  info.settings.peers = !o.no_peers;
  std::printf("voxelize bench: %s\ndentsim on %s; CPU %s, %d threads\n", info.model.c_str(), info.device.c_str(),
              info.cpu.c_str(), info.cpu_threads);

  // Decimation depends on the share only; every level voxelizes the same decimated meshes.
  std::vector<bench::DecimatedModel> models;
  for (double percent : o.fractions) models.push_back(bench::decimateModel(layers, percent / 100.0));

  const bench::DentsimVoxelizer dentsim = gpuVoxelizer(*context, voxelize);
  std::vector<bench::VoxelizeRow> rows;
  for (int level : o.levels) {
    // The full molar's grid, so a level has one voxel size for every share.
    auto frame = fitGridToLevel(bounds, level);
    if (!frame) return fail(frame.message());
    for (const bench::DecimatedModel& m : models) {
      auto row = bench::measureVoxelize(m, *frame, info.settings, dentsim);
      if (!row) return fail(row.message());
      rows.push_back(std::move(row).value());
      const bench::VoxelizeRow& r = rows.back();
      std::printf("level %d, %g%% (%llu triangles): dentsim %.1f ms", r.level, r.fraction * 100.0,
                  static_cast<unsigned long long>(r.triangles), r.dentsim_ms);
      if (r.openvdb.available)
        std::printf(", OpenVDB filled %.1f ms (x%.2f), narrow band %.1f ms (x%.2f)", r.openvdb.ms, r.openvdb.ratio,
                    r.openvdb_band.ms, r.openvdb_band.ratio);
      std::printf("\n");
      std::fflush(stdout);
    }
  }

  const std::string report = bench::voxelizeReportMarkdown(info, rows);
  std::printf("\n%s", report.c_str());
  for (const auto& [name, text] :
       {std::pair{std::string("voxelize.json"), bench::voxelizeReportJson(info, rows).dump(2) + "\n"},
        {std::string("voxelize.md"), report},
        {std::string("voxelize.svg"), bench::voxelizeRowsSvg(rows)}}) {
    if (auto s = writeText(o.out + "/" + name, text); !s) return fail(s.message());
  }
  std::printf("wrote %s/voxelize.json, voxelize.md, voxelize.svg\n", o.out.c_str());
  return 0;
}

}  // namespace

void addBenchCommand(CLI::App& root, Action& action) {
  CLI::App* bench = root.add_subcommand("bench", "Benchmarks recorded in docs/PERFORMANCE.md (JSON, Markdown, SVG)");
  bench->require_subcommand(1);
  auto opts = std::make_shared<BenchOptions>();
  opts->data_dir = defaultDataDir();
  CLI::App* memory = bench->add_subcommand("memory", "Brick-volume bytes and octree nodes of the CT teeth at levels 8-10, "
                                                     "beside the paper's Table 3 and an OpenVDB label tree");
  memory->add_option("--data", opts->data_dir, "Folder with ct/tooth_N.nii.gz")->capture_default_str();
  memory->add_option("--teeth", opts->teeth, "CT teeth to measure")->delimiter(',')->capture_default_str();
  memory->add_option("--levels", opts->levels, "Octree levels")->delimiter(',')->check(CLI::Range(3, 12))->capture_default_str();
  memory->add_option("--out", opts->out, "Output folder")->capture_default_str();
  memory->callback([opts, &action] { action = [opts] { return runMemoryBench(*opts); }; });

  auto vopts = std::make_shared<VoxelizeBenchOptions>();
  CLI::App* voxelize = bench->add_subcommand("voxelize", "Time to voxelize the built-in molar, decimated, at several "
                                                         "levels, beside OpenVDB's meshToVolume (paper Fig. 10, Table 1)");
  voxelize->add_option("--levels", vopts->levels, "Octree levels")->delimiter(',')->check(CLI::Range(3, 12))
      ->capture_default_str();
  voxelize->add_option("--fractions", vopts->fractions, "Shares of the triangles to keep [%]")->delimiter(',')
      ->check(CLI::Range(0.01, 100.0))->capture_default_str();
  voxelize->add_option("--repeat", vopts->repeat, "Timed runs per system; the median is reported")
      ->check(CLI::Range(1, 100))->capture_default_str();
  voxelize->add_option("--out", vopts->out, "Output folder")->capture_default_str();
  voxelize->add_flag("--no-peers", vopts->no_peers, "Skip OpenVDB");
  voxelize->add_option("--subsamples", vopts->subsamples, "Rays per voxel column side (1..4)")
      ->check(CLI::Range(1, 4))->capture_default_str();
  voxelize->add_option("--device", vopts->device, "Device index or name substring (also DENTSIM_DEVICE)");
  voxelize->callback([vopts, &action] { action = [vopts] { return runVoxelizeBench(*vopts); }; });
}

}  // namespace dentsim::app
