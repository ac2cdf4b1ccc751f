// HapticLoop: the 1 kHz step (read the pens, contact and coupling, command forces, cut, hand off) and the thread that runs it.
//
// Contents
//   1. HapticState (the snapshot other threads read) and StepReport (what one step did)
//   2. HapticLoop: set-up, step() for deterministic callers, start()/stop() for the real-time thread
//   3. StepTimes: a fixed histogram of step durations for p50/p99/max without allocating
//
// The step's budget. On the loop's thread a step spends at most device.contact_budget of the period
// on the contact pass (ContactFinder's budget: clusters not reached keep their last contacts and
// come first next step), then commands the forces, then runs queued cuts while the clock is within
// contact_budget + cut_budget of the step's start. A cut is a job (the drill's contacts, the turbine
// speed, the step) in a queue that keeps the order of the steps; jobs that find no time wait for the
// next step, so no removal is lost, only late. The force shown changes by at most
// device.max_force_change_n_per_ms a millisecond, so a pass cut short never jolts the hand. A step
// whose work was cut short records what it reached (SessionSchedule), and replay follows that, not
// the clock: the replayed volume is the recorded one. step() called directly has no budget unless
// setBudget() asks for one (demos, tests and task validation stay independent of the clock).
// The loop owns the tooth's CPU voxels while it runs: it is their only writer, and cuts land in
// them at once, so the next contact test already feels the removed material. Everything it hands
// out goes through lock-free channels: the state snapshot (triple buffer), the voxel edits
// (EditChannel), the pens' forces (ForceOutput, which turns stale into zero) and parameter changes
// (triple buffer, applied at the start of a step). A step never allocates, blocks, writes a file or
// throws; faults set counters and zero the force.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "core/force_output.h"
#include "core/pen_source.h"
#include "core/result.h"
#include "core/rigid.h"
#include "core/spsc_ring.h"
#include "core/triple_buffer.h"
#include "core/volume_frame.h"
#include "io/pen_path_file.h"
#include "io/session_file.h"
#include "sim/cutter.h"
#include "sim/edit_channel.h"
#include "sim/guide_spring.h"
#include "sim/sim_params.h"
#include "sim/tool_proxy.h"
#include "sim/voxel_field.h"
#include "volume/brick_volume.h"

namespace dentsim {

// ---- 1. state ---------------------------------------------------------------------------------------

// One tool as the other threads see it.
struct ToolState {
  bool present = false;    // a tool is attached to this pen
  bool pen_ok = false;     // the pen gave a reading this step
  Pose pen;                // the pen's grip frame
  Pose tool;               // the proxy's tool frame (what the renderer draws)
  Wrench display;          // what the pen was told to render (clamped), moment about the grip
  uint32_t contacts = 0;   // shell points in tissue
  uint32_t points_tested = 0;  // shell points sampled this step
  uint32_t points_clear = 0;   // shell points not sampled: still within their clearance
  uint32_t points_left = 0;    // shell points the budget left for the next step
};

struct HapticState {
  uint64_t step = 0;                   // steps run
  double t_s = 0.0;                    // loop time [s] = step / rate
  std::array<ToolState, 2> tools{};    // by PenRole
  double pedal = 0.0;                  // turbine speed [0..1]
  double rpm = 0.0;                    // turbine speed [1/min]
  double removed_mm3 = 0.0;            // tissue removed since start [mm^3]
  std::array<double, DS_MATERIAL_COUNT> removed_by_material_mm3{};  // the same by tissue (Material index)
  uint64_t voxels_changed = 0;         // voxel edits since start
  uint64_t deferred_cuts = 0;          // steps whose cut waited for room
  uint32_t cut_queue = 0;              // cut jobs waiting after this step
  uint64_t cut_lag_steps = 0;          // steps the oldest of them has waited (0: none waits)
  uint64_t contact_overruns = 0;       // contact passes the budget cut short, since start
  bool guided = false;                 // a guide's spring joins the drill's force
  Vec3 guide_n;                        // the guide's force this step [N] (before the device's clamp)
};

// What one step did, for tests and benchmarks.
struct StepReport {
  std::array<ProxyStep, 2> tools{};    // by PenRole; empty when no tool or no reading
  std::array<bool, 2> stepped{};       // the tool was stepped
  std::array<bool, 2> force_limited{}; // the force shown was held to its largest change a step
  CutStep cut;                         // the cut jobs this step ran, summed
  uint32_t cuts_run = 0;               // cut jobs this step ran (a step's own, or queued ones)
  uint32_t cuts_forced = 0;            // of which run over the budget: waited kMaxCutLagSteps, or the queue was full
  uint32_t cuts_waiting = 0;           // jobs left in the queue
  uint64_t cut_lag_steps = 0;          // steps the oldest waiting job has waited
  SessionSchedule schedule;            // what the step reached (default: all of it)
  double speed = 0.0;                  // turbine speed used [0..1]
  Vec3 guide_n;                        // the guide's force added to the drill's display [N]
};

// ---- 3. step times -----------------------------------------------------------------------------------

class StepTimes {
 public:
  static constexpr int kBins = 20000;  // 0.5 us bins up to 10 ms; longer steps land in the last bin
  void add(int64_t ns);
  uint64_t count() const { return count_; }
  double percentileUs(double p) const;  // p in [0,100]: nearest rank (core/percentile.h), the bin's upper edge [us]
  double maxUs() const { return double(max_ns_) / 1000.0; }
  double meanUs() const { return count_ ? double(sum_ns_) / double(count_) / 1000.0 : 0.0; }

 private:
  std::vector<uint32_t> bins_ = std::vector<uint32_t>(kBins, 0u);
  uint64_t count_ = 0;
  int64_t max_ns_ = 0;
  int64_t sum_ns_ = 0;
};

// Counters the loop keeps while its thread runs; readable from any thread.
struct LoopCounters {
  std::atomic<uint64_t> steps{0};            // steps run by the thread
  std::atomic<uint64_t> contact_overruns{0}; // steps whose contact pass the budget cut short (any tool)
  std::atomic<uint64_t> late_cuts{0};        // steps that left cut jobs for a later step
  std::atomic<uint64_t> forced_cuts{0};      // cut jobs run over the budget: too late, or the queue was full
  std::atomic<uint64_t> max_cut_lag_steps{0};  // the longest any cut job waited [steps]
  std::atomic<uint64_t> missed_deadlines{0}; // steps that ended after their deadline
  std::atomic<uint64_t> long_steps{0};       // steps that took longer than the period: missed by their own work
  std::atomic<uint64_t> pen_dropouts{0};     // steps where an attached pen gave no reading
  std::atomic<int64_t> max_step_ns{0};       // longest step [ns]
  std::atomic<uint64_t> max_step_at{0};      // which step it was
  std::atomic<int64_t> max_wake_late_ns{0};  // the latest a step began after its slot opened [ns]: the machine's wake-up
};

// ---- 2. the loop -------------------------------------------------------------------------------------

// What a step's work is held to: nothing (the whole pass, every cut), the clock (the parameter set's
// fractions of the period), or a fixed count of points sampled per pass with every cut run (a
// budget that tests can repeat exactly).
enum class StepBudget { None, Clock, Points };

class HapticLoop {
 public:
  // The longest a job waits: one older runs at once, over budget. On a steady machine the bench's
  // loop waits up to 5-7 steps, but a machine slowed for a while (another tenant, a throttled core)
  // left jobs 20 to 100 steps behind: the tissue the bur had already taken pushed on it for up to
  // 0.1 s, half a millimetre of travel. A step made longer by a forced job stays far inside its
  // period; a cavity that far behind the bur is felt.
  static constexpr uint64_t kMaxCutLagSteps = 8;

  // `volume` is the tooth's CPU copy: the loop edits it and must be its only user while running.
  // `edits` (may be null) receives every voxel edit for the GPU side. `mirror` may be null.
  // Reserves spare bricks in `volume` so cutting never allocates.
  HapticLoop(BrickVolume& volume, const VolumeFrame& frame, const SimParams& params, const ToolModel& drill,
             const ToolModel* mirror, EditChannel* edits);
  ~HapticLoop();
  HapticLoop(const HapticLoop&) = delete;
  HapticLoop& operator=(const HapticLoop&) = delete;

  // Attaches a pen to a tool (null detaches). Only while the thread is stopped.
  void attach(PenRole role, PenSource* pen);
  // The guide whose spring joins the drill's force from the next step on (null: none). Only while
  // the thread is stopped; the loop does not own it.
  void setGuide(GuideSpring* guide) {
    guide_ = guide;
    totals_.guided = guide != nullptr;
  }
  // Puts a tool's proxy on its pen's current reading (or on `grip` when given).
  void placeTool(PenRole role, const Pose& grip);

  // One step at loop time step() / rate. Deterministic: the same pens and volume give the same result
  // (with StepBudget::Clock, the same schedule: see followSchedule).
  const StepReport& step();

  // The budget of step() called directly (default None) and of the thread's steps (default Clock).
  // points: the pass's point budget for StepBudget::Points. Only while the thread is stopped.
  void setBudget(StepBudget budget, uint32_t points = 0) {
    budget_ = budget;
    budget_points_ = points;
  }
  void setThreadBudget(StepBudget budget) { thread_budget_ = budget; }
  // Runs every waiting cut job now (stop() does, after the thread's last step; a replay does after
  // its last): the removal a session asked for is all in the voxels when it ends. Returns the jobs
  // run. Only while the thread is stopped.
  uint32_t flushCuts();
  // Replay: the next step reaches what `schedule` says instead of what any budget allows (null: its
  // own budget). The loop keeps the pointer until it is set again.
  void followSchedule(const SessionSchedule* schedule) { follow_ = schedule; }

  // Runs step() on a thread at the parameter set's rate, with absolute deadlines. While it runs, the
  // thread asks that idle CPUs wake within idleLatencyUs() (IdleLatencyRequest; negative: do not ask).
  Status start();
  void stop();  // joins the thread, then flushCuts()
  bool running() const { return thread_.joinable(); }

  // Any thread: new parameters, applied at the start of the next step. Returns the set's serial
  // (1, 2, ...; the constructor's set is 0), which the steps that use it report.
  uint32_t setParams(const SimParams& params);
  // The serial of the set the latest step used (the loop's thread, or after stop()).
  uint32_t activeParamsSerial() const { return active_serial_; }

  // Every later step pushes its readings and results into `ring` (null: none). Only while the thread
  // is stopped. A step that finds the ring full drops its record and counts it (droppedRecords);
  // the records' step numbers show the gap.
  void recordInto(SpscRing<SessionStep>* ring) { record_ = ring; }
  uint64_t droppedRecords() const { return dropped_records_.load(std::memory_order_relaxed); }
  // Consumer thread (one): the latest snapshot.
  const HapticState& latest() { return state_.read(); }
  // The loop's thread (a step hook), or after stop(): what the latest step did.
  const StepReport& lastReport() const { return report_; }
  // Any thread: the force for a pen, zero once stale (device I/O threads read this).
  const ForceOutput& forceOutput(PenRole role) const { return forces_[size_t(role)]; }
  const LoopCounters& counters() const { return counters_; }
  // The step-time histogram of the thread's steps (read after stop()).
  const StepTimes& stepTimes() const { return times_; }
  // Any thread: the steps run so far (the index of the next step).
  uint64_t stepsRun() const { return step_.load(std::memory_order_acquire); }
  // Only while the thread is stopped. Default 0: idle CPUs poll instead of sleeping (see idle_latency.h).
  void setIdleLatencyUs(int32_t us) { idle_latency_us_ = us; }
  int32_t idleLatencyUs() const { return idle_latency_us_; }
  // What the last run got from that request (IdleLatencyRequest::note; read after stop()).
  const std::string& idleLatencyNote() const { return idle_latency_note_; }
  bool idleLatencyHeld() const { return idle_latency_held_; }
  bool idleLatencyDenied() const { return idle_latency_denied_; }  // the file may not be opened (the udev rule)
  double dt() const { return 1.0 / active_params_->device.rate_hz; }
  ToolProxy* proxy(PenRole role) { return proxies_[size_t(role)].get(); }

  // A hook the tests use to stall a step: called at its start, in the loop's thread.
  void setStepHook(void (*hook)(uint64_t step, void* user), void* user) {
    hook_ = hook;
    hook_user_ = user;
  }

 private:
  struct ParamsUpdate {
    SimParams params;
    uint32_t serial = 0;
  };
  void run();
  // Makes `update` the active set and resolves what the step would otherwise look up by name.
  void activate(const ParamsUpdate& update);
  void record(const std::array<PenReading, 2>& readings, int64_t now_ns);

  // The cut stage: a queue of jobs in step order over a ring of contact copies.
  struct CutJob {
    uint64_t step = 0;       // the step whose contacts these are (it seeds the cut's rounding)
    uint32_t first = 0;      // its contacts: cut_pool_[first, first + count)
    uint32_t count = 0;
    double speed = 0.0;      // turbine speed [0..1]
    double dt = 0.0;         // [s]
  };
  static constexpr size_t kCutJobs = 256;
  // Queues the drill's contacts of this step; runs the oldest job first, over budget, while there is no room.
  void enqueueCut(std::span<const ContactPoint> contacts, double speed, double dt, uint64_t step);
  void runCut(std::span<const ContactPoint> contacts, double speed, double dt, uint64_t step);
  // Runs the oldest waiting job; forced: over the budget (too late, or no room), counted as such and
  // not in a schedule's count of jobs run.
  void runOldestCut(bool forced = false);
  void bookCut(const CutStep& cut);  // adds a cut's removal to the running totals
  BrickVolume& volume_;
  VoxelField field_;
  TripleBuffer<ParamsUpdate> params_;
  std::atomic<uint32_t> next_serial_{1};
  const SimParams* active_params_ = nullptr;
  uint32_t active_serial_ = 0;
  SpscRing<SessionStep>* record_ = nullptr;
  std::atomic<uint64_t> dropped_records_{0};
  std::array<std::unique_ptr<ToolProxy>, 2> proxies_;
  std::array<PenSource*, 2> pens_{};
  std::array<const ToolModel*, 2> tools_{};
  double drill_ability_ = 0.0;  // the drill's cutting ability under the active parameters
  Cutter cutter_;
  std::vector<ContactPoint> cut_pool_;
  std::array<CutJob, kCutJobs> cut_jobs_{};
  size_t cut_head_ = 0, cut_count_ = 0;   // the oldest job and how many wait
  uint32_t cut_write_ = 0;                // where the next job's contacts go in cut_pool_
  StepBudget budget_ = StepBudget::None;
  StepBudget thread_budget_ = StepBudget::Clock;
  uint32_t budget_points_ = 0;
  const SessionSchedule* follow_ = nullptr;
  std::array<Vec3, 2> last_force_{};       // the force each pen was shown last step [N]
  EditChannel* edits_;
  GuideSpring* guide_ = nullptr;
  std::array<ForceOutput, 2> forces_;
  TripleBuffer<HapticState> state_;
  HapticState totals_;        // the loop's own running state, published each step
  StepReport report_;
  LoopCounters counters_;
  StepTimes times_;
  std::atomic<uint64_t> step_{0};  // atomic only so that other threads may ask stepsRun()
  std::thread thread_;
  std::atomic<bool> stop_requested_{false};
  int32_t idle_latency_us_ = 0;
  std::string idle_latency_note_ = "not requested";
  bool idle_latency_held_ = false;
  bool idle_latency_denied_ = false;
  void (*hook_)(uint64_t, void*) = nullptr;
  void* hook_user_ = nullptr;
};

}  // namespace dentsim
