// The haptic benchmark (`dentsim bench haptic`): the 1 kHz loop's step time while a round bur prepares a class I cavity in the molar.
//
// The tooth comes in as a VolumeMaker (the app voxelizes the built-in molar on the GPU, tests use
// the CPU reference at a small level). The drill is a scripted pen that plays a cavity preparation
// found on the volume itself, so nothing here needs a device, a GPU or a window.
//
// Contents
//   1. The scripted preparation: where the fossa is, and the pen path that cuts around it
//   2. One level: the loop on its real-time thread (with a second thread draining the voxel edits,
//      as the renderer would), then the same steps back to back on the caller's thread
//   3. The report: JSON, Markdown, SVG
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/mesh_bench.h"
#include "core/result.h"
#include "core/rigid.h"
#include "core/volume_frame.h"
#include "io/pen_path_file.h"
#include "volume/brick_volume.h"

namespace dentsim::bench {

// ---- 1. the scripted preparation -------------------------------------------------------------------

// A class I occlusal preparation with a round bur held vertically (tool axis +Z, rotation identity).
// The fossa is where the bur rests lowest near the crown's centre; the outline is an oval of
// `oval_x_mm` x `oval_y_mm` (the bur tip's path) around it. The pen starts `approach_mm` above the
// bur's resting height over the oval's +x end, the pedal goes down, and the pen's target comes down
// to `press_mm` below that resting height (the coupling spring is 1 N/mm by default, so about
// press_mm newtons), stays `dwell_s`, then traces the oval `laps` times at `speed_mm_s`, following
// the untouched surface press_mm below the resting height and sinking `step_down_mm` more per lap;
// then pedal up and lift. The bur removes tissue at a rate that does not depend on the force, so
// a bur held still would sink to the target: moving on, it cuts a groove a little deeper each lap.
struct CavityPathSettings {
  double bur_radius_mm = 0.5;     // radius of the round bur's head [mm] (round_bur_010)
  double grip_z_mm = 19.0;        // the grip point above the tip along the bur's axis [mm] (kBurGripLocal)
  double approach_mm = 1.0;       // start this far above the resting height [mm]
  double press_mm = 1.5;          // pen target below the resting height [mm]
  double step_down_mm = 0.15;     // extra depth of the target per lap, ramped along the outline [mm]
  double oval_x_mm = 2.0;         // outline extent along x, mesiodistal [mm] (the bur tip's path)
  double oval_y_mm = 1.2;         // outline extent along y, buccolingual [mm]
  double speed_mm_s = 2.0;        // along the outline [mm/s]
  double laps = 2.0;              // laps of the outline, > 0 (fractions allowed)
  double hold_s = 0.1;            // above the outline's start before the turbine starts, > 0 [s]
  double descent_s = 0.3;         // from the approach height to the pressed target [s]
  double dwell_s = 0.1;           // pressed at the outline's start before moving [s]
  double lift_s = 0.2;            // back up to approach_mm above the resting height, pedal up [s]
  double sample_s = 0.01;         // between path samples [s]; the scripted pen interpolates
  double fossa_search_mm = 1.0;   // the fossa: the lowest resting point within this of the crown's centre [mm]
  double fossa_grid_mm = 0.1;     // spacing of that search [mm]
};

struct CavityPath {
  PenPath path;                  // drill samples: grip pose (tip + grip_z along +Z), pedal
  Vec3 crown_centre_mm;          // centre of the tissue bricks' x,y extent, at their top (z) [mm]
  Vec3 fossa_mm;                 // the bur tip resting over the fossa [mm]
  double duration_s = 0.0;       // time of the last sample [s]
  double cut_start_s = 0.0;      // pedal down [s]
  double cut_end_s = 0.0;        // pedal up [s]
  double outline_mm = 0.0;       // length of one lap of the oval [mm]
};

// The bur tip's lowest height [mm] when a ball of `radius_mm` comes down vertically over (x, y) onto
// the volume's tissue (fill over one half), from above the tissue; nullopt when it meets none.
std::optional<double> restingTipHeight(const BrickVolume& volume, const VolumeFrame& frame, double x_mm, double y_mm,
                                       double radius_mm);

// The preparation on this volume. Errors: no tissue under the bur anywhere in the fossa search,
// settings out of range.
Result<CavityPath> cavityPreparationPath(const BrickVolume& volume, const VolumeFrame& frame,
                                         const CavityPathSettings& settings = {});

// ---- 2. one level ----------------------------------------------------------------------------------

struct HapticBenchSettings {
  std::string tool = "round_bur_010";   // built-in bur (loadToolModel)
  CavityPathSettings path;
  bool step_only = true;                // also step the same steps back to back on the caller's thread
  bool replay_edits = true;             // the drain thread applies the edits to a mirror copy, compared at the end
  double drain_period_ms = 4.0;         // the drain thread's sleep between drains [ms] (a 240 Hz renderer)
  double poll_period_ms = 10.0;         // the bench thread's sleep between looks at the loop's time [ms]
  double max_wall_factor = 20.0;        // give up when the thread run takes this times the path's length
  double goal_p99_us = 250.0;           // the goals for the thread's step time [us]
  double goal_max_us = 1000.0;
  int goal_level = 10;                  // the level the goals are for
};

// Step-time statistics of one run [us]; percentiles are the upper edge of StepTimes' 0.5 us bins.
struct StepTimeSummary {
  uint64_t steps = 0;
  double p50_us = 0.0, p90_us = 0.0, p99_us = 0.0, p999_us = 0.0, max_us = 0.0, mean_us = 0.0;
  std::vector<std::pair<double, double>> tail;  // (nines, us): p = 100 (1 - 10^-nines), nines 0..4 by 0.5
};

// What the drill did, per step, over one run.
struct StepLoad {
  uint64_t steps = 0;              // steps seen
  double points_mean = 0.0;        // shell points sampled against the field per step
  uint32_t points_max = 0;
  double clear_mean = 0.0;         // shell points skipped per step: still within their clearance
  double contacts_mean = 0.0;      // shell points in tissue per step
  uint32_t contacts_max = 0;
  uint64_t contact_steps = 0;      // steps with at least one contact
  double force_mean_n = 0.0;       // |force shown to the pen| over the contact steps [N]
  double force_max_n = 0.0;        // [N]
  double lowest_tip_mm = 0.0;      // lowest height the bur's tip reached, simulation frame [mm]
};

struct HapticBenchRow {
  int level = 0;                    // octree level: grid 2^L per side
  double voxel_mm = 0.0;            // [mm]
  uint64_t dense_bricks = 0;        // of the tooth before cutting
  double make_volume_s = 0.0;       // the VolumeMaker's time [s]
  std::string tool;                 // bur name
  uint64_t shell_points = 0;        // points of the whole shell
  uint64_t shell_cutting_points = 0;  // of which on the cutting head
  uint64_t shell_clusters = 0;
  CavityPath path;                  // what was played
  double path_s = 0.0;              // path build time [s]

  // The real-time thread.
  StepTimeSummary thread;           // step times from HapticLoop::stepTimes()
  uint64_t missed_deadlines = 0;    // LoopCounters
  uint64_t pen_dropouts = 0;
  std::string scheduler;            // the loop thread's policy as it ran: "SCHED_FIFO 80", "SCHED_OTHER"
  double wall_s = 0.0;              // start() to stop() [s]
  StepLoad load;                    // per-step work, from the state snapshots of every step
  double removed_mm3 = 0.0;         // tissue removed [mm^3]
  uint64_t voxels_changed = 0;      // voxel edits made
  uint64_t deferred_cuts = 0;       // steps whose cut waited for room
  uint64_t edits_drained = 0;       // edits the drain thread took off the channel
  uint64_t drains = 0;              // drains that found edits
  bool mirror_checked = false;      // replay_edits ran
  bool mirror_equal = false;        // the mirror equals the loop's volume after the run

  // The same steps on the caller's thread, back to back, no deadlines.
  bool has_step_only = false;
  StepTimeSummary step_only;
  StepLoad step_only_load;
  double step_only_removed_mm3 = 0.0;
  uint64_t step_only_voxels_changed = 0;

  bool p99_met = false;             // thread.p99_us < goal_p99_us
  bool max_met = false;             // thread.max_us < goal_max_us
};

// Voxelizes the tooth at `level`, builds the tool and the path, runs the loop on its thread until
// its time passes the path's end (a second thread drains the edits all along), then, when asked,
// the same number of steps back to back on a fresh copy of the tooth. `log` gets progress lines.
// Errors: the maker's, the tool's, the path's, a thread that cannot start or never reaches the end.
Result<HapticBenchRow> runHapticBench(int level, const VolumeMaker& make_volume, const HapticBenchSettings& settings,
                                      const std::function<void(const std::string&)>& log = {});

// ---- 3. the report ---------------------------------------------------------------------------------

struct HapticReportInfo {
  std::string model;            // "built-in four-layer molar"
  std::string command;          // the command line
  std::string cpu;              // CPU model
  int cpu_threads = 0;          // hardware threads
  std::string voxelizer;        // how the tooth was made: "GPU (<device>)", "CPU reference"
  std::string load_before;      // /proc/loadavg before the run
  std::string load_after;       // and after
  HapticBenchSettings settings;
};

nlohmann::json hapticReportJson(const HapticReportInfo& info, const std::vector<HapticBenchRow>& rows);
// A paragraph on the set-up, then the table.
std::string hapticReportMarkdown(const HapticReportInfo& info, const std::vector<HapticBenchRow>& rows);
// The short table alone (what the command prints).
std::string hapticRowsTable(const std::vector<HapticBenchRow>& rows, const HapticBenchSettings& settings);
// The step-time tail per level, thread and step-only runs, with the goals as flat lines.
std::string hapticRowsSvg(const std::vector<HapticBenchRow>& rows, const HapticBenchSettings& settings);
// Writes haptic.json, haptic.md and haptic.svg into `dir`, each atomically. Errors name the file.
Status writeHapticReport(const std::string& dir, const HapticReportInfo& info, const std::vector<HapticBenchRow>& rows);

}  // namespace dentsim::bench
