// `dentsim demo [--headless] --out DIR`: the scripted pen removes the built-in molar's caries while the session is recorded, then the cut is scored.
#include <cstdio>
#include <filesystem>
#include <string>

#include "app/commands.h"
#include "app/mesh_output.h"
#include "app/session_support.h"
#include "io/session_file.h"
#include "sim/builtin_tooth.h"
#include "sim/scripted_paths.h"
#include "sim/session_run.h"
#include "volume/surface_mesher.h"
#include "volume/tooth_file.h"
#include "volume/volume_hash.h"

namespace dentsim::app {
namespace {

struct DemoOptions {
  std::string out = "dentsim-demo";  // output folder
  int level = 9;                     // octree level of the molar
  bool headless = false;             // no window (the only mode until the simulator window lands)
  bool realtime = false;             // pace the loop at its rate on its real-time thread
  std::string params;                // a preset (.json); default: dentsim's defaults
};

int runDemo(const DemoOptions& o) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(o.out, ec);
  if (ec) return fail(o.out + ": cannot create the output folder: " + ec.message());
  if (!o.headless) std::printf("the simulator window is not built yet: running headless\n");

  auto task = builtinTask("caries");
  if (!task) return fail(task.message());
  SimParams params = defaultSimParams();
  if (!o.params.empty()) {
    auto loaded = loadSimParams(o.params);
    if (!loaded) return fail(loaded.message());
    params = std::move(*loaded);
  }

  // The tooth, saved first: the session names it, and replay starts from it.
  auto tooth = builtinMolarTooth(o.level);
  if (!tooth) return fail(tooth.message());
  const std::string initial_path = (fs::path(o.out) / "initial.dvol").string();
  if (Status st = saveTooth(initial_path, *tooth); !st) return fail(st.message());
  const ToothVolume initial = *tooth;
  std::printf("tooth: built-in molar, level %d, %.4f mm voxels, hash %s\n", o.level, tooth->frame.voxel_mm,
              volumeHashHex(tooth->voxels, tooth->frame).c_str());

  CariesPathSettings ps;
  auto path = cariesRemovalPath(tooth->voxels, tooth->frame, params, task->drill_tool, ps);
  if (!path) return fail(path.message());
  std::printf("path: %d layers over the lesion (%.3f mm^3 of caries), %.1f s\n", path->layers, path->lesion_mm3,
              path->duration_s);

  SessionInfo info;
  info.created_utc = utcNow();
  info.program = std::string("dentsim ") + DENTSIM_VERSION;
  info.task = task->name;
  info.tooth_file = "initial.dvol";
  info.tooth_source = builtinToothSource(o.level);
  ScriptedSessionOptions so;
  so.drill_tool = task->drill_tool;
  so.mirror_tool = "";
  so.realtime = o.realtime;
  const std::string session_path = (fs::path(o.out) / "session.dses").string();
  auto run = recordScriptedSession(*tooth, params, path->path, session_path, info, so);
  if (!run) return fail(run.message());
  std::printf("session: %s, %llu steps in %.1f s, removed %.4f mm^3, final volume %s\n", session_path.c_str(),
              static_cast<unsigned long long>(run->steps), run->wall_s, run->removed_mm3, run->final_hash.c_str());
  if (run->steps_lost > 0) return fail(session_path + ": the recorder lost " + std::to_string(run->steps_lost) + " steps");

  const std::string final_path = (fs::path(o.out) / "final.dvol").string();
  if (Status st = saveTooth(final_path, *tooth); !st) return fail(st.message());
  SurfaceOptions mo;
  auto surface = meshVolumeCpu(*tooth, mo);
  if (!surface) return fail(surface.message());
  const std::string mesh_path = (fs::path(o.out) / "final.ply").string();
  if (Status st = writeSurface(mesh_path, MeshFormat::Ply, *surface, "demo final tooth"); !st) return fail(st.message());

  auto session = readSessionFile(session_path);
  if (!session) return fail(session.message());
  auto score = scoreCut(*task, initial, *tooth, nullptr, &*session, ScoreFiles{initial_path, final_path, "", session_path});
  if (!score) return fail(score.message());
  const std::string report_path = (fs::path(o.out) / "score.json").string();
  if (Status st = writeScoreReport(report_path, score->report); !st) return fail(st.message());
  const std::string png_path = (fs::path(o.out) / "score.png").string();
  if (Status st = writeScoreImage(png_path, initial, *tooth, nullptr); !st) return fail(st.message());
  std::printf("%s\n", score->summary.c_str());
  std::printf("wrote %s: initial.dvol session.dses final.dvol final.ply score.json score.png\n", o.out.c_str());
  return 0;
}

}  // namespace

void addDemoCommand(CLI::App& root, Action& action) {
  auto o = std::make_shared<DemoOptions>();
  CLI::App* cmd = root.add_subcommand("demo", "Remove the built-in molar's caries with the scripted pen, record the session and score it");
  cmd->add_option("--out", o->out, "Output folder")->capture_default_str();
  cmd->add_option("--level", o->level, "Octree level of the molar")->check(CLI::Range(6, 11))->capture_default_str();
  cmd->add_flag("--headless", o->headless, "No window (the simulator window is not built yet: always headless)");
  cmd->add_flag("--realtime", o->realtime, "Run the haptic loop at its rate on its real-time thread (else as fast as it goes)");
  cmd->add_option("--params", o->params, "Parameter preset (.json); default: dentsim's defaults");
  cmd->callback([o, &action] { action = [o] { return runDemo(*o); }; });
}

}  // namespace dentsim::app
