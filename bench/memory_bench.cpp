// Brick-memory benchmark rows: measure, then render as JSON, a Markdown table and an SVG plot.
#include "bench/memory_bench.h"

#include <cstdio>
#include <sstream>

#include "bench/svg_plot.h"

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

}  // namespace dentsim::bench
