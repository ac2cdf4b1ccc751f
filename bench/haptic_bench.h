// The haptic benchmark (`dentsim bench haptic`): the 1 kHz loop's step time while a round bur prepares a class I cavity in the molar.
//
// The tooth comes in as a VolumeMaker (the command voxelizes the built-in molar on the GPU, tests use
// the CPU reference at a small level). The drill is a scripted pen that plays a cavity preparation
// found on the volume itself, so nothing here needs a device, a GPU or a window.
//
// Contents
//   1. One level: the loop on its real-time thread (with a second thread draining the voxel edits,
//      as the renderer would), then the same steps on the caller's thread, back to back and then
//      each 1 ms after the last (idle between, as the loop's thread is)
//   2. The report: JSON, Markdown, SVG
// The cavity preparation itself is sim's (src/sim/scripted_paths.h), shared with the demo and tasks.
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
#include "model/tool_generator.h"
#include "sim/scripted_paths.h"
#include "volume/brick_volume.h"

namespace dentsim::bench {

// ---- 1. one level ----------------------------------------------------------------------------------

struct HapticBenchSettings {
  std::string tool = kDefaultBur;       // built-in bur (loadToolModel)
  CavityPathSettings path;
  bool step_only = true;                // also step the same steps back to back on the caller's thread
  bool after_idle = true;               // and again each 1 ms after the last began (with step_only only)
  int32_t idle_latency_us = 0;          // the thread's (and the after-idle run's) PM QoS request; < 0: none
  bool replay_edits = true;             // the drain thread applies the edits to a mirror copy, compared at the end
  double drain_period_ms = 4.0;         // the drain thread's sleep between drains [ms] (a 240 Hz renderer)
  double poll_period_ms = 10.0;         // the bench thread's sleep between looks at the loop's time [ms]
  double max_wall_factor = 20.0;        // give up when the thread run takes this times the path's length
  bool budget = true;                   // the thread's steps keep to the step budget (StepBudget::Clock)
  double rate_hz = 0.0;                 // the loop's rate [Hz]; 0: the preset's (1 kHz)
  double contact_budget = 0.0;          // device.contact_budget, of the period; 0: the preset's
  double cut_budget = 0.0;              // device.cut_budget; 0: the preset's
  // The path error's floor: step only again with the pen path moved this far along x [mm] (0: not run).
  // A tenth of a micrometre is far below any pen's resolution; what it changes is the floor under
  // which no step that is not bit for bit the reference's can bring the path error.
  double floor_offset_mm = 0.0001;
  bool bare_timer = true;               // after the thread, the machine's own misses (DeadlineClock, a busy wait)
  double goal_p99_us = 150.0;           // the goals for the thread's step time [us] (issue 45)
  double goal_max_us = 500.0;
  int goal_level = 10;                  // the level the goals are for
};

// Step-time statistics of one run [us]; percentiles are nearest-rank (core/percentile.h) on StepTimes' 0.5 us
// bins, reported as the bin's upper edge.
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
  double points_left_mean = 0.0;   // shell points the budget left for the next step
  uint32_t points_left_max = 0;
};

// A force against its reference, step by step, over the steps where the reference is in contact.
struct ForceError {
  uint64_t steps = 0;              // steps compared
  double rms_n = 0.0, max_n = 0.0; // |F_thread - F_reference| [N]
  double mean_contact_n = 0.0;     // the reference's mean |F| over those steps [N]
  double rmsPercent() const { return mean_contact_n > 0 ? 100.0 * rms_n / mean_contact_n : 0.0; }
  double maxPercent() const { return mean_contact_n > 0 ? 100.0 * max_n / mean_contact_n : 0.0; }
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
  uint64_t max_step_at = 0;         // the step that took thread.max_us
  uint64_t long_steps = 0;          // steps longer than the period: misses of the step's own making (the rest
                                    // began late: the machine woke the thread late)
  double max_wake_late_us = 0.0;    // the latest a step began after its slot opened (the machine's wake-up) [us]
  uint64_t pen_dropouts = 0;
  std::string scheduler;            // the loop thread's policy as it ran: "SCHED_FIFO 80", "SCHED_OTHER"
  double wall_s = 0.0;              // start() to stop() [s]
  StepLoad load;                    // per-step work, from the state snapshots of every step
  double removed_mm3 = 0.0;         // tissue removed [mm^3]
  uint64_t voxels_changed = 0;      // voxel edits made
  uint64_t deferred_cuts = 0;       // steps whose cut waited for room
  bool budgeted = false;            // the thread kept to the step budget
  double rate_hz = 0.0;             // the loop's rate [Hz]
  uint64_t contact_overruns = 0;    // steps whose contact pass the budget cut short
  uint64_t late_cut_steps = 0;      // steps that left cut jobs for later
  uint64_t max_cut_lag_steps = 0;   // the longest a cut job waited [steps]
  uint64_t forced_cuts = 0;         // cut jobs run over the budget (too late, or the queue was full)
  // The bare timer: a thread at the loop's policy on the same DeadlineClock, each step a busy wait as
  // long as the loop thread's mean step, as many steps, right after the loop's run. What it misses is
  // the machine's (late wake-ups), not the step's.
  bool has_bare_timer = false;
  std::string bare_scheduler;
  uint64_t bare_steps = 0;
  uint64_t bare_missed = 0;
  double bare_busy_us = 0.0;
  double bare_max_wake_late_us = 0.0;
  bool replay_checked = false;      // the thread's schedules replayed on a copy of the tooth
  bool replay_equal = false;        // and gave the thread's final voxels
  uint64_t edits_drained = 0;       // edits the drain thread took off the channel
  uint64_t drains = 0;              // drains that found edits
  bool mirror_checked = false;      // replay_edits ran
  bool mirror_equal = false;        // the mirror equals the loop's volume after the run

  // The same steps on the caller's thread, back to back, no deadlines.
  bool has_step_only = false;
  StepTimeSummary step_only;
  StepTimeSummary step_only_guided;   // the same with a guide along the path (sim/guide_spring.h)
  StepLoad step_only_load;
  // The budget's own error (replay_checked): each of the thread's steps replayed from its schedule,
  // the force it showed against the force an unbudgeted step shows from the same state (a copy of
  // the proxy, the same voxels, the same reading).
  ForceError step_error;
  // And over the whole path (has_step_only): the force shown by the thread against step only's
  // (no budget), the two runs on the same pen path, each on its own tooth, so late cuts and passes
  // cut short show in it as the cavities they make drift apart.
  ForceError force_error;
  // The path error's floor (settings.floor_offset_mm): step only with the pen moved, against step only.
  bool has_path_floor = false;
  double path_floor_offset_mm = 0.0;
  ForceError path_floor;
  double step_only_removed_mm3 = 0.0;
  uint64_t step_only_voxels_changed = 0;
  bool idle_latency_held = false;     // the thread run's request on idle CPUs was granted
  std::string idle_latency_note;      // what was held, or why not
  bool has_after_idle = false;        // the same steps, each started 1 ms after the last: idle between
  StepTimeSummary after_idle;
  double after_idle_removed_mm3 = 0.0;
  uint64_t after_idle_voxels_changed = 0;

  bool p99_met = false;             // thread.p99_us < goal_p99_us
  bool max_met = false;             // thread.max_us < goal_max_us
};

// Voxelizes the tooth at `level`, builds the tool and the path, runs the loop on its thread until
// its time passes the path's end (a second thread drains the edits all along), then, when asked,
// the same number of steps back to back on a fresh copy of the tooth. `log` gets progress lines.
// Errors: the maker's, the tool's, the path's, a thread that cannot start or never reaches the end.
Result<HapticBenchRow> runHapticBench(int level, const VolumeMaker& make_volume, const HapticBenchSettings& settings,
                                      const std::function<void(const std::string&)>& log = {});

// ---- 2. the report ---------------------------------------------------------------------------------

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
