// `dentsim info FILE.dvol [--json]`: grid, bytes, brick and octree node counts, tissue volumes, whether the layers are measured or synthesized, and what made them.
#include <cstdio>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "volume/octree_stats.h"
#include "volume/tooth_file.h"
#include "volume/tooth_frame.h"
#include "volume/tooth_layer_synth.h"

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
  const bool synthesized = t.layers == LayerSource::Synthesized;
  j["layers"] = {{"source", synthesized ? "synthesized" : "measured"}};
  if (synthesized) j["layers"]["tooth_type"] = toothTypeName(ToothType(t.synthesized_type));
  const ToothAxes& a = f.tooth;
  const auto source = [](AxisSource from) { return from == AxisSource::Found ? "found" : from == AxisSource::Given ? "given" : "assumed"; };
  const Vec3 centre = toothOcclusalCentreMm(t);
  j["tooth_frame"] = {{"crown", a.crown},
                      {"crown_from", source(a.crown_source)},
                      {"mesial", a.mesial},
                      {"mesial_from", source(a.mesial_source)},
                      {"buccal", a.buccal},
                      {"buccal_from", source(a.buccal_source)},
                      {"occlusal_centre_mm", {centre.x, centre.y, centre.z}},
                      {"occlusal_centre_from", a.has_occlusal_centre ? "file" : "measured"},
                      {"turn", a.turn}};
  // Bounds in mm of each tissue's voxels (their outer faces), in the simulation frame.
  const auto boxes = tissueVoxelBoxes(t.voxels);
  nlohmann::json bounds;
  for (uint32_t m = 0; m < DS_TISSUE_COUNT; ++m) {
    const VoxelBox& b = boxes[m];
    if (b.empty()) continue;
    nlohmann::json lo = nlohmann::json::array(), hi = nlohmann::json::array();
    for (int i = 0; i < 3; ++i) {
      lo.push_back(f.origin_mm[i] + double(b.lo[i]) * f.voxel_mm);
      hi.push_back(f.origin_mm[i] + double(b.hi[i] + 1) * f.voxel_mm);
    }
    bounds[m == 0 ? std::string("tooth") : materialName(Material(m))] = {{"lo_mm", lo}, {"hi_mm", hi}};
  }
  j["bounds"] = bounds;
  // What the voxelization chose (a scan's thresholds, its tooth's box), one entry a line.
  if (!t.source_note.empty()) {
    nlohmann::json lines = nlohmann::json::array();
    size_t at = 0;
    while (at <= t.source_note.size()) {
      const size_t end = std::min(t.source_note.find('\n', at), t.source_note.size());
      if (end > at) lines.push_back(t.source_note.substr(at, end - at));
      at = end + 1;
    }
    j["source_note"] = lines;
  }
  return j;
}

// Three numbers with `digits` after the point: the format stays a literal.
std::string triple(const nlohmann::json& v, int digits = 3) {
  char one[3][40];
  for (int i = 0; i < 3; ++i) std::snprintf(one[i], sizeof one[i], "%.*f", digits, v[size_t(i)].get<double>());
  return std::string("(") + one[0] + ", " + one[1] + ", " + one[2] + ")";
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
  std::printf("tissues     volume [mm^3]     voxels   bounds [mm]\n");
  for (const auto& [name, t] : j["tissues"].items()) {
    std::printf("  %-8s  %14.4f %12llu", name.c_str(), t["volume_mm3"].get<double>(), t["voxels"].get<unsigned long long>());
    if (j["bounds"].contains(name))
      std::printf("   %s to %s", triple(j["bounds"][name]["lo_mm"], 2).c_str(), triple(j["bounds"][name]["hi_mm"], 2).c_str());
    std::printf("\n");
  }
  if (j["bounds"].contains("tooth"))
    std::printf("  %-8s  %27s   %s to %s\n", "tooth", "", triple(j["bounds"]["tooth"]["lo_mm"], 2).c_str(),
                triple(j["bounds"]["tooth"]["hi_mm"], 2).c_str());
  // Synthesized layers are a model's guess at where enamel ends and pulp begins: say so before the numbers are read as measured.
  if (j["layers"]["source"] == "synthesized")
    std::printf("layers      synthesized from one surface (%s type), not measured\n",
                j["layers"]["tooth_type"].get<std::string>().c_str());
  const auto& a = j["tooth_frame"];
  std::printf("tooth frame (simulation frame, mm)\n");
  std::printf("  crown     %s  %s\n", triple(a["crown"]).c_str(), a["crown_from"].get<std::string>().c_str());
  std::printf("  mesial    %s  %s (distal the opposite)\n", triple(a["mesial"]).c_str(), a["mesial_from"].get<std::string>().c_str());
  std::printf("  buccal    %s  %s (lingual the opposite)\n", triple(a["buccal"]).c_str(), a["buccal_from"].get<std::string>().c_str());
  std::printf("  occlusal centre %s  %s\n", triple(a["occlusal_centre_mm"], 2).c_str(),
              a["occlusal_centre_from"].get<std::string>() == "file" ? "" : "(measured: the file has no frame)");
  const auto& turn = a["turn"];
  bool turned = false;
  for (int i = 0; i < 9; ++i) turned = turned || turn[size_t(i)].get<int>() != (i % 4 == 0 ? 1 : 0);
  if (turned) {
    std::string rows;
    for (int r = 0; r < 3; ++r) {
      std::string row;
      for (int c = 0; c < 3; ++c) {
        const int e = turn[size_t(3 * r + c)].get<int>();
        if (e != 0) row = std::string(e < 0 ? "-" : "+") + "xyz"[c];
      }
      rows += std::string(r ? ", " : "") + "xyz"[r] + " = source " + row;
    }
    std::printf("  turned    %s\n", rows.c_str());
  }
  if (j.contains("source_note")) {
    std::printf("made from\n");
    for (const auto& line : j["source_note"]) std::printf("  %s\n", line.get<std::string>().c_str());
  }
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
  CLI::App* cmd = root.add_subcommand("info", "Grid, bytes, brick and octree node counts, tissue volumes and bounds, the tooth frame of a .dvol");
  cmd->add_option("file", opts->path, "Volume file (.dvol)")->required();
  cmd->add_flag("--json", opts->json, "Print JSON");
  cmd->callback([opts, &action] { action = [opts] { return runInfo(*opts); }; });
}

}  // namespace dentsim::app
