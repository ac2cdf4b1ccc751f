// `dentsim info FILE.dvol [--json]`: grid, bytes, brick and octree node counts, tissue volumes.
#include <cstdio>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "volume/octree_stats.h"
#include "volume/tooth_file.h"

namespace dentsim::app {
namespace {

struct InfoOptions {
  std::string path;   // the .dvol file
  bool json = false;  // machine-readable output
};

nlohmann::json describe(const std::string& path, const ToothVolume& t) {
  const VolumeFrame& f = t.frame;
  const BrickStats s = t.voxels.stats();
  const OctreeCounts oc = octreeNodeCounts(t.voxels);
  const MaterialTotals totals = t.voxels.materialTotals();
  nlohmann::json j;
  j["file"] = path;
  j["level"] = f.level;
  j["dim"] = t.voxels.dim();
  j["voxel_mm"] = f.voxel_mm;
  j["extent_mm"] = double(t.voxels.dim()) * f.voxel_mm;
  j["origin_mm"] = f.origin_mm;
  if (f.hasSource()) j["source"] = {{"offset", f.source_offset}, {"dims", f.source_dims}};
  j["bricks"] = {{"dense", s.dense_bricks}, {"uniform", s.uniform_bricks},
                 {"uniform_in_tiled_chunks", (s.uniform_chunks) * DS_CHUNK_BRICKS}};
  j["chunks"] = {{"total", s.chunks}, {"uniform", s.uniform_chunks}};
  j["index_blocks"] = s.blocks;
  j["bytes"] = s.bytes;
  nlohmann::json levels = nlohmann::json::array();
  for (size_t d = 0; d < oc.levels.size(); ++d)
    levels.push_back({{"level", d}, {"black", oc.levels[d].black}, {"white", oc.levels[d].white}, {"mix", oc.levels[d].mix}});
  j["octree"] = {{"levels", levels}, {"nodes", oc.nodes()}};
  nlohmann::json tissues;
  for (uint32_t m = 1; m < DS_TISSUE_COUNT; ++m)
    tissues[materialName(Material(m))] = {{"voxels", totals.voxels[m]},
                                          {"volume_mm3", totals.volumeMm3(Material(m), f.voxel_mm)}};
  j["tissues"] = tissues;
  return j;
}

void printText(const nlohmann::json& j) {
  std::printf("file        %s\n", j["file"].get<std::string>().c_str());
  std::printf("grid        %u^3 voxels (level %d), voxel %.5g mm, extent %.4g mm\n", j["dim"].get<unsigned>(),
              j["level"].get<int>(), j["voxel_mm"].get<double>(), j["extent_mm"].get<double>());
  if (j.contains("source")) {
    const auto& s = j["source"];
    std::printf("source      %d x %d x %d voxels at grid offset (%d, %d, %d)\n", s["dims"][0].get<int>(),
                s["dims"][1].get<int>(), s["dims"][2].get<int>(), s["offset"][0].get<int>(), s["offset"][1].get<int>(),
                s["offset"][2].get<int>());
  }
  std::printf("bricks      %llu dense, %llu uniform in %llu index blocks; %llu of %llu chunks uniform\n",
              j["bricks"]["dense"].get<unsigned long long>(), j["bricks"]["uniform"].get<unsigned long long>(),
              j["index_blocks"].get<unsigned long long>(), j["chunks"]["uniform"].get<unsigned long long>(),
              j["chunks"]["total"].get<unsigned long long>());
  std::printf("memory      %llu bytes (%.2f MB)\n", j["bytes"].get<unsigned long long>(), j["bytes"].get<double>() / 1e6);
  std::printf("octree      %llu nodes (black / white / mix per level)\n", j["octree"]["nodes"].get<unsigned long long>());
  for (const auto& l : j["octree"]["levels"]) {
    const auto b = l["black"].get<unsigned long long>(), w = l["white"].get<unsigned long long>(),
               m = l["mix"].get<unsigned long long>();
    if (b + w + m == 0) continue;
    std::printf("  level %2d  %12llu %12llu %12llu\n", l["level"].get<int>(), b, w, m);
  }
  std::printf("tissues     volume [mm^3]     voxels\n");
  for (const auto& [name, t] : j["tissues"].items())
    std::printf("  %-8s  %14.4f %12llu\n", name.c_str(), t["volume_mm3"].get<double>(), t["voxels"].get<unsigned long long>());
}

int runInfo(const InfoOptions& o) {
  auto tooth = loadTooth(o.path);
  if (!tooth) return fail(tooth.message());
  const nlohmann::json j = describe(o.path, *tooth);
  if (o.json) std::cout << j.dump(2) << "\n";
  else printText(j);
  return 0;
}

}  // namespace

void addInfoCommand(CLI::App& root, Action& action) {
  auto opts = std::make_shared<InfoOptions>();
  CLI::App* cmd = root.add_subcommand("info", "Grid, bytes, brick and octree node counts, tissue volumes of a .dvol");
  cmd->add_option("file", opts->path, "Volume file (.dvol)")->required();
  cmd->add_flag("--json", opts->json, "Print JSON");
  cmd->callback([opts, &action] { action = [opts] { return runInfo(*opts); }; });
}

}  // namespace dentsim::app
