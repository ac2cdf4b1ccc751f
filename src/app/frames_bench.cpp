// The frame-time benchmark: the demo's caries removal drawn frame by frame, full detail against screen-sized detail in one run; the same frames and five views compared pixel by pixel; the mirror's cost drawn at its shown size against the old fixed image; the demo's first frame.
#include "app/frames_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/simulator.h"
#include "bench/svg_plot.h"
#include "core/text_format.h"
#include "gpu/compute.h"
#include "gpu/context.h"
#include "io/atomic_file.h"
#include "render/camera.h"
#include "render/frame_compare.h"
#include "render/look_params.h"
#include "render/offscreen.h"
#include "render/scene_renderer.h"
#include "render/tooth_surfaces.h"
#include "sim/builtin_tooth.h"
#include "sim/surface_probe.h"

namespace dentsim::app {
namespace {

namespace fs = std::filesystem;

struct RunRow {
  int level = 0;
  bool screen_sized = false;  // false: the full-detail path
  SimulatorOutcome run;
};

// One view of the uncut molar drawn both ways, tooth alone.
struct ViewRow {
  int level = 0;
  std::string view;
  uint64_t full_triangles = 0, triangles = 0;
  render::FrameDifference diff;
};

// The molar seen from above with the mirror beside it, drawn by three renderers' ways in turn: no
// mirror, the mirror pass at the glass's shown size (pixel for pixel, the default), and the old fixed
// 512 x 512 image of the whole view. Each frame is recorded, submitted and waited for [ms, median].
struct MirrorRow {
  int level = 0;
  PixelRect glass;                  // the mirror pass's rectangle on the frame (shown size) [px]
  uint32_t fixed_side = 512;        // the old image's side [px]
  int frames = 0;                   // per way
  double none_ms = 0.0, shown_ms = 0.0, fixed_ms = 0.0;
  uint64_t shown_triangles = 0, fixed_triangles = 0;  // of the tooth, in the mirror pass
};

struct FirstFrameRow {
  int level = 0;
  bool in_parts = false;
  double first_frame_s = 0.0, full_detail_s = 0.0;
};

std::array<uint8_t, 3> backgroundRgb() {
  const std::array<float, 3> bg = render::FrameState{}.background;
  return {uint8_t(std::lround(bg[0] * 255.0f)), uint8_t(std::lround(bg[1] * 255.0f)), uint8_t(std::lround(bg[2] * 255.0f))};
}

SimulatorOptions demoRun(const FramesBenchOptions& o, int level) {
  SimulatorOptions so;
  so.level = level;
  so.demo_script = true;
  so.frames.headless = !o.window;
  so.lockstep = true;  // each frame shows 1/30 s more of the drilling, whatever the frame costs
  so.fps = 30.0;
  so.frames.vsync = false;
  so.frames.width = o.width;
  so.frames.height = o.height;
  so.end.bench_frames = o.frames;
  so.end.bench_from_s = o.from_s;
  so.frames.device = o.device;
  so.sound.sound = false;
  so.frames.mesher = o.mesher;
  so.frames.ui = false;  // the panel's cost is not the tooth's; the pictures compare the scene alone
  so.frames.progressive = false;
  return so;
}

// The five views of the molar at `level`, each drawn at full detail and with screen-sized detail.
Status compareViews(const FramesBenchOptions& o, int level, std::vector<ViewRow>& rows) {
  gpu::ContextOptions co;
  co.graphics = true;
  co.device_override = o.device;
  auto ctx = gpu::Context::create(gpu::withEnvironment(co));
  if (!ctx) return ctx.error();
  auto tooth = builtinMolarTooth(level);
  if (!tooth) return tooth.error();
  auto surfaces = render::ToothSurfaces::create(*ctx, NormalMode::Box216, render::kDefaultCoarseCopies, o.mesher);
  if (!surfaces) return surfaces.error();
  if (Status st = surfaces->build(tooth->voxels); !st) return st;
  auto renderer = render::SceneRenderer::create(*ctx, render::kDefaultColourFormat, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  if (!renderer) return renderer.error();
  const VolumeFrame& f = tooth->frame;
  const BrickBox box = tissueBricks(tooth->voxels);
  const double brick_mm = f.voxel_mm * DS_BRICK_DIM;
  glm::vec3 lo, hi;
  for (int a = 0; a < 3; ++a) {
    const uint32_t blo = a == 0 ? box.lo.x : a == 1 ? box.lo.y : box.lo.z, bhi = a == 0 ? box.hi.x : a == 1 ? box.hi.y : box.hi.z;
    lo[a] = float(f.origin_mm[size_t(a)] + blo * brick_mm);
    hi[a] = float(f.origin_mm[size_t(a)] + (bhi + 1) * brick_mm);
  }
  const glm::vec3 centre = 0.5f * (lo + hi);
  const float radius = 0.5f * glm::length(hi - lo);
  struct View {
    const char* name;
    render::ViewPreset preset;
    float zoom;
  };
  for (const View v : {View{"buccal", render::ViewPreset::Buccal, 1.0f}, View{"occlusal", render::ViewPreset::Occlusal, 1.0f},
                       View{"mesial", render::ViewPreset::Mesial, 1.0f}, View{"occlusal x3", render::ViewPreset::Occlusal, 3.0f},
                       View{"buccal x1/3", render::ViewPreset::Buccal, 1.0f / 3.0f}}) {
    render::OrbitCamera camera;
    camera.setView(v.preset, centre, radius);
    camera.setDistance(camera.distance() / v.zoom);
    render::FrameState fs;
    fs.view = camera.view();
    fs.projection = camera.projection(float(o.width) / float(o.height));
    fs.eye = camera.eye();
    fs.light_dir = glm::normalize(camera.eye() - centre);
    fs.tooth_frame = f;
    fs.looks = defaultLookParams().looks;
    fs.drill_shown = false;
    ViewRow row;
    row.level = level;
    row.view = v.name;
    fs.lod.pixel_error = 0.0f;
    auto full = render::renderOffscreen(*ctx, *renderer, *surfaces, fs, uint32_t(o.width), uint32_t(o.height));
    if (!full) return full.error();
    row.full_triangles = renderer->toothDrawStats().main_triangles;
    fs.lod.pixel_error = o.detail_pixels;
    auto lod = render::renderOffscreen(*ctx, *renderer, *surfaces, fs, uint32_t(o.width), uint32_t(o.height));
    if (!lod) return lod.error();
    row.triangles = renderer->toothDrawStats().main_triangles;
    row.diff = render::compareFrames(*full, *lod, backgroundRgb());
    rows.push_back(row);
  }
  return ctx->waitIdle();
}

// The median wall time of `frames` offscreen frames of each way, the ways taking turns frame by frame
// so that a machine's drift (another job, the clock) falls on all of them alike.
Status mirrorCost(const FramesBenchOptions& o, int level, std::vector<MirrorRow>& rows) {
  gpu::ContextOptions co;
  co.graphics = true;
  co.device_override = o.device;
  auto ctx = gpu::Context::create(gpu::withEnvironment(co));
  if (!ctx) return ctx.error();
  auto tooth = builtinMolarTooth(level);
  if (!tooth) return tooth.error();
  auto surfaces = render::ToothSurfaces::create(*ctx, NormalMode::Box216, render::kDefaultCoarseCopies, o.mesher);
  if (!surfaces) return surfaces.error();
  if (Status st = surfaces->build(tooth->voxels); !st) return st;
  MirrorRow row;
  row.level = level;
  row.frames = std::max(5, std::min(o.frames, 40));
  render::SceneRendererOptions fixed_options;
  fixed_options.mirror_resolution = row.fixed_side;
  auto shown = render::SceneRenderer::create(*ctx, render::kDefaultColourFormat, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
  if (!shown) return shown.error();
  auto fixed = render::SceneRenderer::create(*ctx, render::kDefaultColourFormat, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                                             fixed_options);
  if (!fixed) return fixed.error();
  auto target = render::OffscreenTarget::create(*ctx, uint32_t(o.width), uint32_t(o.height));
  if (!target) return target.error();

  // From above, the mirror beside the tooth tilted 45 degrees toward it: the eye sees the lingual
  // side in the glass (as the renderer's tests place it).
  const TissueBox box = tissueBox(tooth->voxels, tooth->frame);
  const glm::vec3 centre = render::toGlm(box.centre());
  const float radius = float(0.5 * norm(box.hi - box.lo));
  render::OrbitCamera camera;
  camera.setView(render::ViewPreset::Occlusal, centre, radius);
  camera.setDistance(camera.distance() * 1.6f);
  camera.setTarget(centre + glm::vec3(0.0f, radius * 0.6f, 0.0f));
  render::FrameState fs;
  fs.view = camera.view();
  fs.projection = camera.projection(float(o.width) / float(o.height));
  fs.eye = camera.eye();
  fs.light_dir = glm::normalize(camera.eye() - centre);
  fs.tooth_frame = tooth->frame;
  fs.looks = defaultLookParams().looks;
  fs.drill_shown = false;
  fs.lod.pixel_error = o.detail_pixels;
  fs.mirror.position = render::fromGlm(centre + glm::vec3(0.0f, radius * 1.25f, radius * 0.3f));
  fs.mirror.rotation = Quat::fromAxisAngle({1.0, 0.0, 0.0}, 3.14159265358979 / 4.0);

  std::array<std::vector<double>, 3> ms;  // no mirror, shown size, fixed
  for (int f = 0; f < row.frames + 1; ++f)
    for (int way = 0; way < 3; ++way) {
      render::SceneRenderer& r = way == 2 ? *fixed : *shown;
      fs.mirror_shown = way != 0;
      const auto t0 = std::chrono::steady_clock::now();
      Status st = gpu::submitAndWait(*ctx, "mirror bench frame", [&](gpu::Commands& cmds) -> Status {
        r.markSubmitted(cmds.serial());
        return r.recordFrame(cmds.cmd(), target->image(), *surfaces, fs);
      });
      if (!st) return st;
      if (way != 0 && !r.mirrorDrawn()) return makeError("bench frames", "the mirror pass did not run");
      if (way == 1) row.glass = r.mirrorRect();
      // The shown size picks finer copies of the tooth: its pixels are the main view's, not 2.5 wide.
      if (way == 1) row.shown_triangles = r.toothDrawStats().mirror_triangles;
      if (way == 2) row.fixed_triangles = r.toothDrawStats().mirror_triangles;
      // The first round makes the targets (and the shown-size image): left out.
      if (f > 0) ms[size_t(way)].push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
  const auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  row.none_ms = median(ms[0]);
  row.shown_ms = median(ms[1]);
  row.fixed_ms = median(ms[2]);
  shown->forgetTargets();
  fixed->forgetTargets();
  rows.push_back(row);
  return ctx->waitIdle();
}

}  // namespace

int runFramesBench(const FramesBenchOptions& o) {
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) return fail(o.out + ": cannot create the output folder: " + ec.message());
  const fs::path scratch = fs::path(o.out) / "frames-scratch";
  // The frame both paths write as a picture, in the middle of the timed ones (a window draws every
  // frame from the start, headless only from from_s on).
  const double shot_s = (o.window ? 0.0 : o.from_s) + 0.5 * double(o.frames) / 30.0;
  std::vector<RunRow> rows;
  std::vector<render::FrameDifference> shot_diffs;
  std::vector<ViewRow> views;
  std::vector<FirstFrameRow> firsts;
  std::vector<MirrorRow> mirrors;
  for (int level : o.levels) {
    std::array<std::string, 2> shots;
    for (int path = 0; path < 2; ++path) {
      SimulatorOptions so = demoRun(o, level);
      so.frames.detail_pixels = path == 0 ? 0.0f : o.detail_pixels;
      const fs::path dir = scratch / (std::to_string(level) + (path == 0 ? "-full" : "-screen"));
      fs::remove_all(dir, ec);
      so.out = dir.string();
      so.shots.shots_s = {shot_s};
      auto run = runSimulator(so);
      if (!run) return fail(run.message());
      rows.push_back({level, path == 1, *run});
      shots[size_t(path)] = (dir / "shot-1.png").string();
      std::printf("level %d, %s (%s, %s): frame %.1f ms median, %.1f ms p95, %.1f ms mean (%.1f frames/s); re-mesh "
                  "%.1f ms mean; %.0f triangles drawn a frame\n",
                  level, path == 0 ? "full detail" : "screen-sized detail", run->windowed ? "window" : "offscreen",
                  run->device.c_str(), run->frame_ms_p50, run->frame_ms_p95, run->frame_ms_mean,
                  1000.0 / run->frame_ms_mean, run->remesh_ms_mean, run->triangles_drawn_mean);
    }
    auto full = readPng(shots[0]);
    auto screen = readPng(shots[1]);
    if (!full) return fail(full.message());
    if (!screen) return fail(screen.message());
    if (full->width != screen->width || full->height != screen->height)
      return fail(shots[1] + ": not the size of " + shots[0]);
    shot_diffs.push_back(render::compareFrames(*full, *screen, backgroundRgb()));
    if (Status st = compareViews(o, level, views); !st) return fail(st.message());
    if (Status st = mirrorCost(o, level, mirrors); !st) return fail(st.message());
    if (o.first_frame) {
      for (bool parts : {false, true}) {
        SimulatorOptions so = demoRun(o, level);
        so.end.bench_frames = parts ? 1000000 : 1;  // in parts: on until full detail is everywhere
        so.end.bench_from_s = 0.0;
        so.frames.progressive = parts;
        so.frames.detail_pixels = o.detail_pixels;
        so.end.quit_at_full_detail = parts;
        auto run = runSimulator(so);
        if (!run) return fail(run.message());
        firsts.push_back({level, parts, run->first_frame_s, parts ? run->full_detail_s : run->first_frame_s});
      }
    }
  }
  fs::remove_all(scratch, ec);

  nlohmann::ordered_json j;
  j["benchmark"] = "frames";
  j["what"] = "the built-in molar's scripted caries removal from loop time from_s on, one frame per 1/30 s of loop "
              "time, each frame re-meshing the bricks the bur changed, then drawing tooth, tools and mirror pass "
              "(no panel), once at full detail and once with screen-sized detail; the frame at shot_s of both "
              "compared; five views of the uncut molar (tooth only) drawn both ways; the mirror's cost (the molar from "
              "above with the mirror beside it: no mirror, the mirror pass at the glass's shown size, the old fixed "
              "512 x 512 image; median offscreen frame, recorded, submitted and waited for); the demo's first frame";
  j["from_s"] = o.from_s;
  j["shot_s"] = shot_s;
  j["width"] = o.width;
  j["height"] = o.height;
  j["detail_pixels"] = o.detail_pixels;
  j["mesher"] = gpu::mesherKindName(o.mesher);
  std::string md = "| level | path | device | frames | frame p50 [ms] | frame p95 [ms] | frame mean [ms] | frames/s "
                   "(mean) | re-mesh mean [ms] | triangles drawn a frame |\n|---|---|---|---|---|---|---|---|---|---|\n";
  bench::PlotSeries full_p50{"full detail, frame p50", {}}, screen_p50{"screen-sized, frame p50", {}};
  for (const RunRow& r : rows) {
    j["rows"].push_back({{"level", r.level},
                         {"path", r.screen_sized ? "screen-sized" : "full"},
                         {"target", r.run.windowed ? "window" : "offscreen"},
                         {"device", r.run.device},
                         {"frames", r.run.drawn},
                         {"frame_ms_p50", r.run.frame_ms_p50},
                         {"frame_ms_p95", r.run.frame_ms_p95},
                         {"frame_ms_mean", r.run.frame_ms_mean},
                         {"frames_per_s", 1000.0 / r.run.frame_ms_mean},
                         {"remesh_ms_mean", r.run.remesh_ms_mean},
                         {"triangles_drawn_mean", r.run.triangles_drawn_mean},
                         {"surface_triangles", r.run.triangles}});
    md += "| " + std::to_string(r.level) + " | " + (r.screen_sized ? "screen-sized" : "full") + " | " + r.run.device +
          " | " + std::to_string(r.run.drawn) + " | " + formatted("%.1f", r.run.frame_ms_p50) + " | " +
          formatted("%.1f", r.run.frame_ms_p95) + " | " + formatted("%.1f", r.run.frame_ms_mean) + " | " +
          formatted("%.1f", 1000.0 / r.run.frame_ms_mean) + " | " + formatted("%.1f", r.run.remesh_ms_mean) + " | " +
          formatted("%.0f", r.run.triangles_drawn_mean) + " |\n";
    (r.screen_sized ? screen_p50 : full_p50).points.emplace_back(r.level, r.run.frame_ms_p50);
  }
  md += "\n| level | full / screen-sized frame (mean) | shot: mean difference [grey] | pixels over 8 | crack pixels |\n"
        "|---|---|---|---|---|\n";
  for (size_t i = 0; i < shot_diffs.size(); ++i) {
    const RunRow &full = rows[2 * i], &screen = rows[2 * i + 1];
    const double speedup = full.run.frame_ms_mean / screen.run.frame_ms_mean;
    const render::FrameDifference& d = shot_diffs[i];
    j["shots"].push_back({{"level", full.level},
                          {"speedup_mean", speedup},
                          {"mean_abs_difference", d.mean_abs},
                          {"pixels_over_8", d.differing},
                          {"crack_pixels", d.cracks}});
    md += "| " + std::to_string(full.level) + " | " + formatted("%.2f", speedup) + " | " + formatted("%.2f", d.mean_abs) + " | " +
          std::to_string(d.differing) + " | " + std::to_string(d.cracks) + " |\n";
  }
  md += "\n| level | view | tooth pixels | triangles full | triangles screen-sized | per tooth pixel | mean difference "
        "[grey] | pixels over 8 | crack pixels |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const ViewRow& v : views) {
    const double per_px = v.diff.covered ? double(v.triangles) / double(v.diff.covered) : 0.0;
    j["views"].push_back({{"level", v.level},
                          {"view", v.view},
                          {"tooth_pixels", v.diff.covered},
                          {"triangles_full", v.full_triangles},
                          {"triangles", v.triangles},
                          {"triangles_per_tooth_pixel", per_px},
                          {"mean_abs_difference", v.diff.mean_abs},
                          {"pixels_over_8", v.diff.differing},
                          {"crack_pixels", v.diff.cracks}});
    md += "| " + std::to_string(v.level) + " | " + v.view + " | " + std::to_string(v.diff.covered) + " | " +
          std::to_string(v.full_triangles) + " | " + std::to_string(v.triangles) + " | " + formatted("%.2f", per_px) + " | " +
          formatted("%.2f", v.diff.mean_abs) + " | " + std::to_string(v.diff.differing) + " | " +
          std::to_string(v.diff.cracks) + " |\n";
  }
  md += "\n| level | glass on screen [px] | no mirror [ms] | mirror at shown size [ms] | mirror fixed 512 [ms] | "
        "shown / fixed | shown / no mirror | mirror triangles shown / fixed |\n|---|---|---|---|---|---|---|---|\n";
  for (const MirrorRow& m : mirrors) {
    j["mirror"].push_back({{"level", m.level},
                           {"glass_px", {m.glass.width, m.glass.height}},
                           {"frames", m.frames},
                           {"frame_ms_no_mirror", m.none_ms},
                           {"frame_ms_shown_size", m.shown_ms},
                           {"frame_ms_fixed", m.fixed_ms},
                           {"fixed_side_px", m.fixed_side},
                           {"shown_over_fixed", m.shown_ms / m.fixed_ms},
                           {"shown_over_no_mirror", m.shown_ms / m.none_ms},
                           {"mirror_triangles_shown_size", m.shown_triangles},
                           {"mirror_triangles_fixed", m.fixed_triangles}});
    md += "| " + std::to_string(m.level) + " | " + std::to_string(m.glass.width) + " x " + std::to_string(m.glass.height) +
          " | " + formatted("%.1f", m.none_ms) + " | " + formatted("%.1f", m.shown_ms) + " | " + formatted("%.1f", m.fixed_ms) +
          " | " + formatted("%.2f", m.shown_ms / m.fixed_ms) + " | " + formatted("%.2f", m.shown_ms / m.none_ms) + " | " +
          std::to_string(m.shown_triangles) + " / " + std::to_string(m.fixed_triangles) + " |\n";
  }
  if (!firsts.empty()) {
    md += "\n| level | build | first frame [s] | full detail everywhere [s] |\n|---|---|---|---|\n";
    for (const FirstFrameRow& f : firsts) {
      j["first_frame"].push_back({{"level", f.level},
                                  {"build", f.in_parts ? "in parts" : "whole"},
                                  {"first_frame_s", f.first_frame_s},
                                  {"full_detail_s", f.full_detail_s}});
      md += "| " + std::to_string(f.level) + " | " + (f.in_parts ? "in parts" : "whole") + " | " +
            formatted("%.2f", f.first_frame_s) + " | " + formatted("%.2f", f.full_detail_s) + " |\n";
    }
  }
  const std::string svg = bench::svgLinePlot("Frame time while drilling (" + std::to_string(o.width) + "x" +
                                                 std::to_string(o.height) + ")",
                                             "octree level", "ms", {full_p50, screen_p50}, true);
  for (const auto& [name, text] : {std::pair{std::string("frames.json"), j.dump(2) + "\n"},
                                   {std::string("frames.md"), md},
                                   {std::string("frames.svg"), svg}})
    if (Status st = writeFileAtomic(o.out + "/" + name, text); !st) return fail(st.message());
  std::printf("\n%swrote %s/frames.json, frames.md, frames.svg\n", md.c_str(), o.out.c_str());
  return 0;
}

}  // namespace dentsim::app
