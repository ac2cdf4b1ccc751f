// Voxelization benchmark: decimate the layers, time dentsim and OpenVDB on the same grid, report as JSON, Markdown and SVG.
//
// Contents
//   1. Decimated models
//   2. Measurement and medians
//   3. JSON
//   4. Markdown
//   5. SVG
//   6. Files
#include "bench/voxelize_bench.h"

#include <algorithm>
#include <cassert>
#include <cstdarg>
#include <cstdio>
#include <map>
#include <sstream>
#include <utility>

#include "bench/svg_plot.h"
#include "core/text_format.h"
#include "io/atomic_file.h"

namespace dentsim::bench {

// ---- 1. decimated models -----------------------------------------------------------------------

uint64_t DecimatedModel::triangles() const {
  uint64_t n = 0;
  for (const BenchLayer& l : layers) n += l.mesh.triangleCount();
  return n;
}

std::vector<MeshLayer> DecimatedModel::meshLayers() const {
  std::vector<MeshLayer> out;
  for (const BenchLayer& l : layers) out.push_back(MeshLayer{l.material, &l.mesh, l.name});
  return out;
}

DecimatedModel decimateModel(const std::vector<MeshLayer>& layers, double fraction) {
  DecimatedModel model;
  model.fraction = fraction;
  for (const MeshLayer& in : layers) {
    assert(in.mesh);
    BenchLayer l;
    l.name = in.name;
    l.material = in.material;
    l.mesh = decimateMesh(*in.mesh, fraction, &l.decimation);
    l.mesh_mm3 = l.mesh.signedVolume();
    model.layers.push_back(std::move(l));
  }
  return model;
}

// ---- 2. measurement ----------------------------------------------------------------------------

double median(std::vector<double> values) {
  assert(!values.empty());
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

Result<VoxelizeRow> measureVoxelize(const DecimatedModel& model, const VolumeFrame& frame,
                                    const VoxelizeBenchSettings& settings, const DentsimVoxelizer& dentsim) {
  assert(settings.repeats >= 1);
  const std::vector<MeshLayer> layers = model.meshLayers();
  VoxelizeRow r;
  r.level = frame.level;
  r.voxel_mm = frame.voxel_mm;
  r.fraction = model.fraction;
  r.triangles = model.triangles();
  r.repeats = settings.repeats;

  // dentsim: all layers in one pass, as the application voxelizes a tooth.
  if (settings.warmup) {
    auto warm = dentsim(layers, frame);
    if (!warm) return warm.error();
  }
  std::vector<double> kernel_ms;
  DentsimRun last;
  for (int i = 0; i < settings.repeats; ++i) {
    auto run = dentsim(layers, frame);
    if (!run) return run.error();
    r.dentsim_runs_ms.push_back(run->ms);
    kernel_ms.push_back(run->kernel_ms);
    last = std::move(*run);
  }
  r.dentsim_ms = median(r.dentsim_runs_ms);
  r.dentsim_kernel_ms = median(kernel_ms);
  r.hits = last.hits;
  r.dense_bricks = last.dense_bricks;
  for (const BenchLayer& l : model.layers) {
    TissueRow t;
    t.name = l.name;
    t.material = l.material;
    t.triangles = l.mesh.triangleCount();
    t.decimation = l.decimation.method;
    t.open_edges = l.decimation.topology.open_edges;
    t.deviation_mm = l.decimation.error_mm;
    t.mesh_mm3 = l.mesh_mm3;
    t.dentsim_mm3 = last.totals.volumeMm3(l.material, frame.voxel_mm);
    r.tissues.push_back(t);
  }

  // OpenVDB: one level set per surface (it has no notion of layers), the run's time their sum.
  if (!settings.peers) {
    r.openvdb.name = r.openvdb_band.name = "not run (--no-peers)";
    return r;
  }
  for (const VdbInterior variant : {VdbInterior::Filled, VdbInterior::NarrowBand}) {
    PeerTiming& peer = variant == VdbInterior::Filled ? r.openvdb : r.openvdb_band;
    std::vector<std::vector<double>> layer_ms(model.layers.size());
    for (int i = 0; i < settings.repeats; ++i) {
      double sum_ms = 0.0;
      for (size_t k = 0; k < model.layers.size(); ++k) {
        const PeerVoxelize p = openvdbMeshToVolume(model.layers[k].mesh, frame.voxel_mm, frame.origin_mm, variant);
        peer.name = p.name;
        if (!p.available) return r;
        peer.threads = p.threads;
        (variant == VdbInterior::Filled ? r.tissues[k].openvdb_mm3 : r.tissues[k].openvdb_band_mm3) = p.interior_mm3;
        layer_ms[k].push_back(p.ms);
        sum_ms += p.ms;
      }
      peer.runs_ms.push_back(sum_ms);
    }
    peer.available = true;
    peer.ms = median(peer.runs_ms);
    peer.ratio = r.dentsim_ms > 0.0 ? peer.ms / r.dentsim_ms : 0.0;
    if (variant == VdbInterior::Filled)
      for (size_t k = 0; k < model.layers.size(); ++k) r.tissues[k].openvdb_ms = median(layer_ms[k]);
  }
  return r;
}

Result<std::vector<VoxelizeRow>> runVoxelizeBench(const std::vector<MeshLayer>& layers, const Bounds3& bounds,
                                                  const std::vector<int>& levels, const std::vector<double>& percents,
                                                  const VoxelizeBenchSettings& settings, const DentsimVoxelizer& dentsim,
                                                  const std::function<void(const std::string&)>& log) {
  // Decimation depends on the share only; every level voxelizes the same decimated meshes.
  std::vector<DecimatedModel> models;
  for (double percent : percents) models.push_back(decimateModel(layers, percent / 100.0));

  std::vector<VoxelizeRow> rows;
  for (int level : levels) {
    // The full model's grid, so a level has one voxel size for every share.
    auto frame = fitGridToLevel(bounds, level);
    if (!frame) return frame.error();
    for (const DecimatedModel& m : models) {
      auto row = measureVoxelize(m, *frame, settings, dentsim);
      if (!row) return row.error();
      rows.push_back(std::move(row).value());
      const VoxelizeRow& r = rows.back();
      char line[512];
      int n = std::snprintf(line, sizeof line, "level %d, %g%% (%llu triangles): dentsim %.1f ms", r.level,
                            r.fraction * 100.0, static_cast<unsigned long long>(r.triangles), r.dentsim_ms);
      if (r.openvdb.available)
        std::snprintf(line + n, sizeof line - size_t(n), ", OpenVDB filled %.1f ms (x%.2f), narrow band %.1f ms (x%.2f)",
                      r.openvdb.ms, r.openvdb.ratio, r.openvdb_band.ms, r.openvdb_band.ratio);
      if (log) log(line);
    }
  }
  return rows;
}

// ---- 3. JSON -----------------------------------------------------------------------------------

namespace {

nlohmann::json peerJson(const PeerTiming& p) {
  return {{"available", p.available}, {"name", p.name},  {"threads", p.threads},
          {"ms", p.ms},               {"runs_ms", p.runs_ms}, {"ratio_over_dentsim", p.ratio}};
}

}  // namespace

nlohmann::json voxelizeReportJson(const VoxelizeReportInfo& info, const std::vector<VoxelizeRow>& rows) {
  nlohmann::json out_rows = nlohmann::json::array();
  for (const VoxelizeRow& r : rows) {
    nlohmann::json tissues = nlohmann::json::array();
    for (const TissueRow& t : r.tissues)
      tissues.push_back({{"name", t.name},
                         {"material", materialName(t.material)},
                         {"triangles", t.triangles},
                         {"decimation", t.decimation},
                         {"open_edges", t.open_edges},
                         {"deviation_mm", t.deviation_mm},
                         {"mesh_mm3", t.mesh_mm3},
                         {"dentsim_mm3", t.dentsim_mm3},
                         {"openvdb_mm3", t.openvdb_mm3},
                         {"openvdb_band_mm3", t.openvdb_band_mm3},
                         {"openvdb_ms", t.openvdb_ms}});
    out_rows.push_back({{"level", r.level},
                        {"voxel_mm", r.voxel_mm},
                        {"fraction", r.fraction},
                        {"triangles", r.triangles},
                        {"repeats", r.repeats},
                        {"dentsim", {{"ms", r.dentsim_ms},
                                     {"runs_ms", r.dentsim_runs_ms},
                                     {"kernel_ms", r.dentsim_kernel_ms},
                                     {"hits", r.hits},
                                     {"dense_bricks", r.dense_bricks}}},
                        {"openvdb", peerJson(r.openvdb)},
                        {"openvdb_band", peerJson(r.openvdb_band)},
                        {"ratio_openvdb_over_dentsim", r.openvdb.ratio},
                        {"tissues", tissues}});
  }
  return {{"benchmark", "voxelize"},
          {"model", info.model},
          {"command", info.command},
          {"machine", {{"cpu", info.cpu}, {"cpu_threads", info.cpu_threads}, {"device", info.device}}},
          {"settings", {{"repeats", info.settings.repeats},
                        {"warmup_runs", info.settings.warmup ? 1 : 0},
                        {"statistic", "median"},
                        {"subsamples", info.subsamples},
                        {"peers", info.settings.peers}}},
          {"rows", out_rows}};
}

// ---- 4. Markdown -------------------------------------------------------------------------------
namespace {

// 1234567 -> "1,234,567", as docs/PERFORMANCE.md writes counts.
std::string grouped(uint64_t v) {
  std::string digits = std::to_string(v), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string percent(double fraction) { return formatted("%g", fraction * 100.0); }

}  // namespace

std::string voxelizeReportMarkdown(const VoxelizeReportInfo& info, const std::vector<VoxelizeRow>& rows) {
  std::ostringstream o;
  std::string peer = "OpenVDB not run";
  for (const VoxelizeRow& r : rows)
    if (r.openvdb.available) {
      peer = r.openvdb.name.substr(0, r.openvdb.name.find(',')) + " on " + std::to_string(r.openvdb.threads) +
             " TBB threads";
      break;
    } else if (!r.openvdb.name.empty()) {
      peer = r.openvdb.name;
    }
  const int n = info.settings.repeats;
  o << "Model: " << info.model << ". dentsim on " << info.device << " (" << info.subsamples << "x"
    << info.subsamples << " rays per voxel column); " << peer << "; CPU " << info.cpu << ", " << info.cpu_threads
    << " hardware threads. Each time is the median of " << n << (n == 1 ? " run" : " runs")
    << (info.settings.warmup ? ", after one untimed dentsim run" : "")
    << ". dentsim: ray set-up, voxelization and bricks mirrored to the CPU, by the host clock. "
       "OpenVDB: the sum of one meshToVolume per layer, filled (interior band unbounded, exterior 1 voxel) "
       "and as its usual narrow-band level set (3 voxels each side, interior known by sign only).\n\n";
  if (!info.command.empty()) o << "Command: `" << info.command << "`\n\n";

  auto peerMs = [](const PeerTiming& p) { return p.available ? formatted("%.1f", p.ms) : std::string("n/a"); };
  auto peerRatio = [](const PeerTiming& p) { return p.available ? formatted("%.2f", p.ratio) : std::string("n/a"); };
  o << "| level | voxel [mm] | triangles [%] | triangles | dentsim [ms] | GPU kernels [ms] | OpenVDB filled [ms] | "
       "OpenVDB / dentsim | OpenVDB band [ms] | band / dentsim | dense bricks |\n"
       "|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const VoxelizeRow& r : rows)
    o << "| " << r.level << " | " << formatted("%.4f", r.voxel_mm) << " | " << percent(r.fraction) << " | "
      << grouped(r.triangles) << " | " << formatted("%.1f", r.dentsim_ms) << " | " << formatted("%.1f", r.dentsim_kernel_ms)
      << " | " << peerMs(r.openvdb) << " | " << peerRatio(r.openvdb) << " | " << peerMs(r.openvdb_band) << " | "
      << peerRatio(r.openvdb_band) << " | " << grouped(r.dense_bricks) << " |\n";

  // Volumes at the finest decimation measured: the sanity check of both voxelizers.
  double top = 0.0;
  for (const VoxelizeRow& r : rows) top = std::max(top, r.fraction);
  o << "\nTissue volumes at " << percent(top)
    << "% of the triangles [mm^3]. The mesh and OpenVDB columns are each surface's own interior; "
       "dentsim's voxel holds the one material of the highest-priority layer inside it "
       "(pulp > caries > dentin > enamel), so nested layers are counted once.\n\n"
    << "| level | tissue | triangles | mesh | OpenVDB | dentsim |\n|---|---|---|---|---|---|\n";
  for (const VoxelizeRow& r : rows) {
    if (r.fraction != top) continue;
    for (const TissueRow& t : r.tissues)
      o << "| " << r.level << " | " << t.name << " | " << grouped(t.triangles) << " | " << formatted("%.2f", t.mesh_mm3)
        << " | " << (r.openvdb.available ? formatted("%.2f", t.openvdb_mm3) : "n/a") << " | " << formatted("%.2f", t.dentsim_mm3)
        << " |\n";
  }

  // Decimation depends on the share only, so one level's rows describe it.
  o << "\nDecimation (meshoptimizer): method, its geometric deviation, open edges left and the enclosed volume.\n\n"
    << "| triangles [%] | tissue | triangles | method | deviation [mm] | open edges | mesh [mm^3] |\n"
    << "|---|---|---|---|---|---|---|\n";
  std::map<double, bool> done;
  for (const VoxelizeRow& r : rows) {
    if (done[r.fraction]) continue;
    done[r.fraction] = true;
    for (const TissueRow& t : r.tissues)
      o << "| " << percent(r.fraction) << " | " << t.name << " | " << grouped(t.triangles) << " | " << t.decimation
        << " | " << formatted("%.4f", t.deviation_mm) << " | " << grouped(t.open_edges) << " | "
        << formatted("%.2f", t.mesh_mm3) << " |\n";
  }
  return o.str();
}

// ---- 5. SVG ------------------------------------------------------------------------------------

std::string voxelizeRowsSvg(const std::vector<VoxelizeRow>& rows) {
  // One colour per level; solid for dentsim, dashed for OpenVDB filled, dotted for its narrow band.
  std::vector<int> levels;
  for (const VoxelizeRow& r : rows)
    if (std::find(levels.begin(), levels.end(), r.level) == levels.end()) levels.push_back(r.level);
  std::sort(levels.begin(), levels.end());
  std::vector<PlotSeries> series;
  for (size_t i = 0; i < levels.size(); ++i) {
    const std::string level = " L" + std::to_string(levels[i]);
    PlotSeries ours{"dentsim" + level, {}, int(i), ""};
    PlotSeries filled{"OpenVDB filled" + level, {}, int(i), "7,4"};
    PlotSeries band{"OpenVDB band" + level, {}, int(i), "2,3"};
    for (const VoxelizeRow& r : rows) {
      if (r.level != levels[i]) continue;
      ours.points.emplace_back(double(r.triangles), r.dentsim_ms);
      if (r.openvdb.available) filled.points.emplace_back(double(r.triangles), r.openvdb.ms);
      if (r.openvdb_band.available) band.points.emplace_back(double(r.triangles), r.openvdb_band.ms);
    }
    for (PlotSeries* s : {&ours, &filled, &band}) {
      if (s->points.empty()) continue;
      std::sort(s->points.begin(), s->points.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
      series.push_back(std::move(*s));
    }
  }
  return svgLinePlot("Voxelization time of the molar (grid 2^L per side)", "triangles, all layers (log)",
                     "time [ms] (log)", series, /*log_y=*/true, /*log_x=*/true);
}

// ---- 6. files -----------------------------------------------------------------------------------

Status writeVoxelizeReport(const std::string& dir, const VoxelizeReportInfo& info, const std::vector<VoxelizeRow>& rows) {
  for (const auto& [name, text] :
       {std::pair{std::string("voxelize.json"), voxelizeReportJson(info, rows).dump(2) + "\n"},
        {std::string("voxelize.md"), voxelizeReportMarkdown(info, rows)},
        {std::string("voxelize.svg"), voxelizeRowsSvg(rows)}})
    if (Status s = writeFileAtomic(dir + "/" + name, text); !s) return s;
  return Ok{};
}

}  // namespace dentsim::bench
