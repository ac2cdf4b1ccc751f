// The frame-time benchmark: the demo's caries removal drawn frame by frame, so each frame re-meshes the bricks the bur changed.
#include "app/frames_bench.h"

#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/simulator.h"
#include "bench/svg_plot.h"
#include "io/atomic_file.h"

namespace dentsim::app {
namespace {

struct FramesRow {
  int level = 0;
  SimulatorOutcome run;
};

std::string fmt(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

int runFramesBench(const FramesBenchOptions& o) {
  std::error_code ec;
  std::filesystem::create_directories(o.out, ec);
  if (ec) return fail(o.out + ": cannot create the output folder: " + ec.message());
  std::vector<FramesRow> rows;
  for (int level : o.levels) {
    SimulatorOptions so;
    so.level = level;
    so.demo_script = true;
    so.headless = !o.window;
    so.lockstep = true;  // each frame shows 1/30 s more of the drilling, whatever the frame costs
    so.fps = 30.0;
    so.vsync = false;
    so.width = o.width;
    so.height = o.height;
    so.bench_frames = o.frames;
    so.bench_from_s = o.from_s;
    so.device = o.device;
    auto run = runSimulator(so);
    if (!run) return fail(run.message());
    rows.push_back({level, *run});
    std::printf("level %d (%s, %s): %llu frames, frame %.1f ms median, %.1f ms p95, %.1f ms mean (%.1f frames/s); "
                "re-mesh %.1f ms mean; %llu triangles\n",
                level, run->windowed ? "window" : "offscreen", run->device.c_str(),
                static_cast<unsigned long long>(run->drawn), run->frame_ms_p50, run->frame_ms_p95, run->frame_ms_mean,
                1000.0 / run->frame_ms_mean, run->remesh_ms_mean, static_cast<unsigned long long>(run->triangles));
  }

  nlohmann::ordered_json j;
  j["benchmark"] = "frames";
  j["what"] = "the built-in molar's scripted caries removal from loop time from_s on, one frame per 1/30 s of loop "
              "time, each frame re-meshing the bricks the bur changed, then drawing tooth, tools, mirror pass and "
              "parameter window";
  j["from_s"] = o.from_s;
  j["width"] = o.width;
  j["height"] = o.height;
  std::string md = "| level | target | device | frames | frame p50 [ms] | frame p95 [ms] | frame mean [ms] | frames/s "
                   "(mean) | re-mesh mean [ms] | triangles |\n|---|---|---|---|---|---|---|---|---|---|\n";
  bench::PlotSeries p50{"frame p50", {}}, p95{"frame p95", {}}, remesh{"re-mesh mean", {}};
  for (const FramesRow& r : rows) {
    j["rows"].push_back({{"level", r.level},
                         {"target", r.run.windowed ? "window" : "offscreen"},
                         {"device", r.run.device},
                         {"frames", r.run.drawn},
                         {"frame_ms_p50", r.run.frame_ms_p50},
                         {"frame_ms_p95", r.run.frame_ms_p95},
                         {"frame_ms_mean", r.run.frame_ms_mean},
                         {"frames_per_s", 1000.0 / r.run.frame_ms_mean},
                         {"remesh_ms_mean", r.run.remesh_ms_mean},
                         {"triangles", r.run.triangles}});
    md += "| " + std::to_string(r.level) + " | " + (r.run.windowed ? "window" : "offscreen") + " | " + r.run.device +
          " | " + std::to_string(r.run.drawn) + " | " + fmt("%.1f", r.run.frame_ms_p50) + " | " +
          fmt("%.1f", r.run.frame_ms_p95) + " | " + fmt("%.1f", r.run.frame_ms_mean) + " | " +
          fmt("%.1f", 1000.0 / r.run.frame_ms_mean) + " | " + fmt("%.1f", r.run.remesh_ms_mean) + " | " +
          std::to_string(r.run.triangles) + " |\n";
    p50.points.emplace_back(r.level, r.run.frame_ms_p50);
    p95.points.emplace_back(r.level, r.run.frame_ms_p95);
    remesh.points.emplace_back(r.level, r.run.remesh_ms_mean);
  }
  const std::string svg = bench::svgLinePlot("Frame time while drilling (" + std::to_string(o.width) + "x" +
                                                 std::to_string(o.height) + ")",
                                             "octree level", "ms", {p50, p95, remesh}, true);
  for (const auto& [name, text] : {std::pair{std::string("frames.json"), j.dump(2) + "\n"},
                                   {std::string("frames.md"), md},
                                   {std::string("frames.svg"), svg}})
    if (Status st = writeFileAtomic(o.out + "/" + name, text); !st) return fail(st.message());
  std::printf("\n%swrote %s/frames.json, frames.md, frames.svg\n", md.c_str(), o.out.c_str());
  return 0;
}

}  // namespace dentsim::app
