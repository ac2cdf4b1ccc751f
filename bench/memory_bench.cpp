// Brick-memory benchmark rows: measure, then render as JSON, a Markdown table and an SVG plot.
#include "bench/memory_bench.h"

#include <chrono>
#include <cstdio>
#include <sstream>
#include <utility>

#include "bench/svg_plot.h"
#include "io/atomic_file.h"
#include "io/nifti_labels.h"
#include "volume/label_import.h"

namespace dentsim::bench {

double paperTable3Mb(int level) {
  switch (level) {
    case 8: return 4.6;
    case 9: return 19.3;
    case 10: return 77.5;
    default: return 0.0;
  }
}

MemoryRow measureMemory(const std::string& tooth, const ToothVolume& volume, double build_s) {
  MemoryRow r;
  r.tooth = tooth;
  r.level = volume.voxels.level();
  r.voxel_mm = volume.frame.voxel_mm;
  r.build_s = build_s;
  r.stats = volume.voxels.stats();
  r.octree = octreeNodeCounts(volume.voxels);
  r.openvdb = openvdbLabelTreeMemory(volume.voxels);
  r.paper_mb = paperTable3Mb(r.level);
  return r;
}

nlohmann::json memoryRowsJson(const std::vector<MemoryRow>& rows) {
  nlohmann::json out = nlohmann::json::array();
  for (const MemoryRow& r : rows) {
    nlohmann::json levels = nlohmann::json::array();
    for (const auto& l : r.octree.levels) levels.push_back({{"black", l.black}, {"white", l.white}, {"mix", l.mix}});
    out.push_back({{"tooth", r.tooth},
                   {"level", r.level},
                   {"voxel_mm", r.voxel_mm},
                   {"build_s", r.build_s},
                   {"dentsim_bytes", r.stats.bytes},
                   {"dense_bricks", r.stats.dense_bricks},
                   {"index_blocks", r.stats.blocks},
                   {"octree_nodes", r.octree.nodes()},
                   {"octree_levels", levels},
                   {"openvdb", {{"available", r.openvdb.available},
                                {"name", r.openvdb.name},
                                {"bytes", r.openvdb.bytes},
                                {"leaf_nodes", r.openvdb.leaf_nodes},
                                {"build_s", r.openvdb.build_s}}},
                   {"paper_table3_bytes", r.paper_mb * 1e6}});
  }
  return out;
}

std::string memoryRowsTable(const std::vector<MemoryRow>& rows) {
  std::ostringstream o;
  o << "| tooth | level | voxel [mm] | dense bricks | dentsim [MB] | OpenVDB [MB] | paper Table 3 [MB] | dentsim/OpenVDB | dentsim/paper | octree nodes |\n"
    << "|---|---|---|---|---|---|---|---|---|---|\n";
  char buf[512];
  for (const MemoryRow& r : rows) {
    const double ours = double(r.stats.bytes) / 1e6;
    const double vdb = double(r.openvdb.bytes) / 1e6;
    std::string vdb_text = r.openvdb.available ? std::to_string(vdb).substr(0, 6) : "n/a";
    std::string vdb_ratio = r.openvdb.available && vdb > 0 ? std::to_string(ours / vdb).substr(0, 5) : "n/a";
    std::string paper_ratio = r.paper_mb > 0 ? std::to_string(ours / r.paper_mb).substr(0, 5) : "n/a";
    std::snprintf(buf, sizeof buf, "| %s | %d | %.4f | %llu | %.2f | %s | %s | %s | %s | %llu |\n", r.tooth.c_str(),
                  r.level, r.voxel_mm, static_cast<unsigned long long>(r.stats.dense_bricks), ours, vdb_text.c_str(),
                  r.paper_mb > 0 ? std::to_string(r.paper_mb).substr(0, 4).c_str() : "n/a", vdb_ratio.c_str(),
                  paper_ratio.c_str(), static_cast<unsigned long long>(r.octree.nodes()));
    o << buf;
  }
  return o.str();
}

std::string memoryRowsSvg(const std::vector<MemoryRow>& rows) {
  std::vector<PlotSeries> series;
  auto seriesFor = [&series](const std::string& name) -> PlotSeries& {
    for (auto& s : series)
      if (s.name == name) return s;
    series.push_back({name, {}});
    return series.back();
  };
  for (const MemoryRow& r : rows) {
    seriesFor("dentsim " + r.tooth).points.emplace_back(r.level, double(r.stats.bytes) / 1e6);
    if (r.openvdb.available) seriesFor("OpenVDB " + r.tooth).points.emplace_back(r.level, double(r.openvdb.bytes) / 1e6);
  }
  PlotSeries paper{"paper Table 3", {}};
  for (int level = 8; level <= 10; ++level) paper.points.emplace_back(level, paperTable3Mb(level));
  series.push_back(paper);
  return svgLinePlot("Tooth volume memory against octree level", "octree level L (grid 2^L)", "memory [MB]", series, true);
}

// ---- the CT teeth run ---------------------------------------------------------------------------

Result<std::vector<MemoryRow>> measureCtTeeth(const CtMemorySettings& settings, Interrupter& progress,
                                              const std::function<void(const std::string&)>& log) {
  auto map = parseLabelMap("1=caries,2=enamel,3=dentin");  // the data README's labels
  if (!map) return map.error();
  std::vector<MemoryRow> rows;
  for (const std::string& tooth : settings.teeth) {
    const std::string path = settings.data_dir + "/ct/" + tooth + ".nii.gz";
    auto image = readNiftiLabels(path);
    if (!image) return Error{image.message() + " (set --data or DENTSIM_DATA_DIR)"};
    for (int level : settings.levels) {
      LabelImportOptions opt;
      opt.map = *map;
      opt.level = level;
      opt.source_pitch_mm = 0.034;  // the header says 1.0; the data README gives the true pitch
      opt.where = path;
      const auto start = std::chrono::steady_clock::now();
      auto volume = importLabels(*image, opt, progress);
      if (!volume) return volume.error();
      volume->voxels.compact();
      const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      rows.push_back(measureMemory(tooth, *volume, build_s));
      const MemoryRow& r = rows.back();
      char line[512];
      std::snprintf(line, sizeof line, "%s level %d: dentsim %.2f MB, %s %s MB, paper %.1f MB", tooth.c_str(), level,
                    double(r.stats.bytes) / 1e6, r.openvdb.name.c_str(),
                    r.openvdb.available ? std::to_string(double(r.openvdb.bytes) / 1e6).c_str() : "n/a", r.paper_mb);
      if (log) log(line);
    }
  }
  return rows;
}

Status writeMemoryReport(const std::string& dir, const std::vector<MemoryRow>& rows) {
  for (const auto& [name, text] : {std::pair{std::string("memory.json"), memoryRowsJson(rows).dump(2) + "\n"},
                                   {std::string("memory.md"), memoryRowsTable(rows)},
                                   {std::string("memory.svg"), memoryRowsSvg(rows)}})
    if (Status s = writeFileAtomic(dir + "/" + name, text); !s) return s;
  return Ok{};
}

}  // namespace dentsim::bench
