// `dentsim bench memory`: brick-volume bytes against the paper's Table 3 and OpenVDB, written as JSON, Markdown and SVG.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include "app/commands.h"
#include "app/terminal_progress.h"
#include "bench/memory_bench.h"
#include "io/nifti_labels.h"
#include "volume/label_import.h"

namespace dentsim::app {
namespace {

struct BenchOptions {
  std::string data_dir;                            // real tooth data (../shared/data)
  std::vector<std::string> teeth{"tooth_2", "tooth_3"};  // CT teeth in data_dir/ct
  std::vector<int> levels{8, 9, 10};               // octree levels to fit each tooth into
  std::string out = "bench-out";                   // folder for JSON, Markdown and SVG
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
}

}  // namespace dentsim::app
