// Haptic benchmark: the scripted cavity preparation, the loop's thread and step-only runs, and their JSON, Markdown and SVG report.
//
// Contents
//   1. Step statistics: time summaries and the per-step load
//   2. One level: thread run, step-only run
//   3. JSON
//   4. Markdown
//   5. SVG and files
#include "bench/haptic_bench.h"

#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdarg>
#include <cstdio>
#include <numbers>
#include <optional>
#include <sstream>
#include <stop_token>
#include <system_error>
#include <thread>

#include "bench/svg_plot.h"
#include "core/steady_clock.h"
#include "core/text_format.h"
#include "io/atomic_file.h"
#include "io/pen_playback.h"
#include "sim/deadline_clock.h"
#include "sim/edit_channel.h"
#include "sim/guide_spring.h"
#include "sim/haptic_loop.h"
#include "sim/idle_latency.h"
#include "sim/sim_params.h"
#include "sim/tool_library.h"
#include "sim/voxel_field.h"

namespace dentsim::bench {

// ---- 1. step statistics ----------------------------------------------------------------------------
namespace {

StepTimeSummary summarize(const StepTimes& times) {
  StepTimeSummary s;
  s.steps = times.count();
  s.p50_us = times.percentileUs(50.0);
  s.p90_us = times.percentileUs(90.0);
  s.p99_us = times.percentileUs(99.0);
  s.p999_us = times.percentileUs(99.9);
  s.max_us = times.maxUs();
  s.mean_us = times.meanUs();
  for (int k = 0; k <= 8; ++k) {
    const double nines = 0.5 * k;
    s.tail.emplace_back(nines, times.percentileUs(100.0 * (1.0 - std::pow(10.0, -nines))));
  }
  return s;
}

// Sums of the drill's per-step state, turned into a StepLoad at the end.
struct LoadSums {
  uint64_t steps = 0;
  uint64_t points = 0;
  uint32_t points_max = 0;
  uint64_t clear = 0;
  uint64_t contacts = 0;
  uint32_t contacts_max = 0;
  uint64_t contact_steps = 0;
  double force_sum = 0.0;
  double force_max = 0.0;
  double lowest_tip = HUGE_VAL;
  uint64_t left = 0;
  uint32_t left_max = 0;

  void add(const ToolState& t) {
    ++steps;
    left += t.points_left;
    left_max = std::max(left_max, t.points_left);
    points += t.points_tested;
    points_max = std::max(points_max, t.points_tested);
    clear += t.points_clear;
    contacts += t.contacts;
    contacts_max = std::max(contacts_max, t.contacts);
    if (t.contacts > 0) {
      ++contact_steps;
      const double f = norm(t.display.force);
      force_sum += f;
      force_max = std::max(force_max, f);
    }
    lowest_tip = std::min(lowest_tip, t.tool.position.z);  // the round bur's tip is its frame's origin
  }
  StepLoad load() const {
    StepLoad l;
    l.steps = steps;
    l.points_mean = steps ? double(points) / double(steps) : 0.0;
    l.points_max = points_max;
    l.clear_mean = steps ? double(clear) / double(steps) : 0.0;
    l.contacts_mean = steps ? double(contacts) / double(steps) : 0.0;
    l.contacts_max = contacts_max;
    l.contact_steps = contact_steps;
    l.force_mean_n = contact_steps ? force_sum / double(contact_steps) : 0.0;
    l.force_max_n = force_max;
    l.lowest_tip_mm = std::isfinite(lowest_tip) ? lowest_tip : 0.0;
    l.points_left_mean = steps ? double(left) / double(steps) : 0.0;
    l.points_left_max = left_max;
    return l;
  }
};

// What the step hook gathers on the loop's own thread. At the start of step N (N >= 1) the newest
// snapshot is the one step N-1 published: the hook is the snapshot's only reader while the thread
// runs, so every step is seen once (the last one after stop()). Costs a few tens of ns a step.
struct ThreadProbe {
  HapticLoop* loop = nullptr;
  LoadSums sums;
  // Per step, reserved before the run (the hook never allocates): the drill's force, and what the
  // step reached, for the force error and the replay check.
  std::vector<Vec3> forces;
  std::vector<SessionSchedule> schedules;
  void keep(const StepReport& r) {
    if (forces.size() == forces.capacity()) return;
    forces.push_back(r.stepped[0] ? r.tools[0].display.force : Vec3{});
    schedules.push_back(r.schedule);
  }
  int policy = -1;      // the thread's scheduling policy at its first step
  int priority = 0;
};

void probeStep(uint64_t step, void* user) {
  auto* probe = static_cast<ThreadProbe*>(user);
  if (step == 0) {
    sched_param sp{};
    int policy = 0;
    if (pthread_getschedparam(pthread_self(), &policy, &sp) == 0) {
      probe->policy = policy;
      probe->priority = sp.sched_priority;
    }
  }
  if (step > 0) {
    probe->sums.add(probe->loop->latest().tools[size_t(PenRole::Drill)]);
    probe->keep(probe->loop->lastReport());
  }
}

std::string schedulerName(int policy, int priority) {
  switch (policy) {
    case SCHED_FIFO: return "SCHED_FIFO " + std::to_string(priority);
    case SCHED_RR: return "SCHED_RR " + std::to_string(priority);
    case SCHED_OTHER: return "SCHED_OTHER";
    default: return policy < 0 ? "unknown" : "policy " + std::to_string(policy);
  }
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A guide along the bench's own path (its drill grip every 10 ms, as a professional's session
// gives one): the guided run measures what the guide's search and spring add to a step.
GuidePath guideAlong(const PenPath& path) {
  GuidePath g;
  ScriptedPen pen(path, PenRole::Drill);
  const double end = pen.endTime();
  for (int k = 0; double(k) * g.spacing_s <= end; ++k) {
    PenReading r;
    if (pen.read(double(k) * g.spacing_s, &r)) g.points.push_back(r.grip.position);
  }
  return g;
}

struct ReplayedRun {
  StepTimeSummary times;
  StepLoad load;
  double removed_mm3 = 0.0;
  uint64_t voxels_changed = 0;
  std::vector<Vec3> forces;  // the drill's, per step
  ForceError step_error;     // with `follow`: each step's force shown against an unbudgeted step's from the same state
};

// Accumulates |F - F_reference| over steps where the reference exceeds 0.01 N.
struct ErrorSums {
  ForceError e;
  double sq = 0.0, sum = 0.0;
  void add(const Vec3& f, const Vec3& reference) {
    const double r = norm(reference);
    if (r <= 0.01) return;
    const double d = norm(f - reference);
    ++e.steps;
    sq += d * d;
    sum += r;
    e.max_n = std::max(e.max_n, d);
  }
  ForceError result() const {
    ForceError out = e;
    if (out.steps > 0) {
      out.rms_n = std::sqrt(sq / double(out.steps));
      out.mean_contact_n = sum / double(out.steps);
    }
    return out;
  }
};

// The thread run's steps again, on the calling thread at its own priority and without the drain
// thread: back to back (period_ns 0: the compute alone), or each started period_ns after the last
// began, idle in between as the loop's thread is (a step that overruns starts the next at once).
// A paced run holds the thread's request on idle CPUs (idle_latency_us), as the thread does.
// With `follow`, each step follows the schedule the thread's step of the same index reported.
ReplayedRun replaySteps(BrickVolume& volume, const VolumeFrame& frame, const SimParams& params, const ToolModel& tool,
                        const PenPath& path, uint64_t steps, int64_t period_ns, int32_t idle_latency_us,
                        const GuidePath* guide = nullptr, const std::vector<SessionSchedule>* follow = nullptr) {
  const IdleLatencyRequest idle(period_ns > 0 ? idle_latency_us : -1);
  EditChannel edits;
  ScriptedPen pen(path, PenRole::Drill);
  HapticLoop loop(volume, frame, params, tool, nullptr, &edits);
  loop.attach(PenRole::Drill, &pen);
  loop.placeTool(PenRole::Drill, path.samples.front().pose);
  std::optional<GuideSpring> spring;
  if (guide) {
    spring.emplace(*guide);
    loop.setGuide(&*spring);
  }
  StepTimes times;
  LoadSums sums;
  std::vector<Vec3> forces;
  forces.reserve(steps);
  // The unbudgeted step a followed step is measured against: a copy of the drill's proxy as the step
  // finds it, stepped whole on its own view of the voxels (refreshed each step: the loop cuts them)
  // with the same reading.
  std::optional<VoxelField> reference_field;
  ScriptedPen reference_pen(path, PenRole::Drill);
  ErrorSums step_sums;
  if (follow != nullptr) reference_field.emplace(volume, frame);
  std::vector<uint64_t> sink;
  sink.reserve(size_t{1} << 16);
  int64_t next = steadyNowNs();
  for (uint64_t i = 0; i < steps; ++i) {
    if (period_ns > 0 && i > 0) {
      next += period_ns;
      if (steadyNowNs() < next) {
        sleepUntilNs(next);
      } else {
        next = steadyNowNs();  // the last step overran its slot: the schedule restarts now
      }
    }
    Vec3 reference_force;
    bool referenced = false;
    if (follow != nullptr) {
      loop.followSchedule(i < follow->size() ? &(*follow)[i] : nullptr);
      PenReading reading;
      if (reference_pen.read(loop.latest().t_s, &reading)) {
        reference_field->invalidate();
        ToolProxy whole(*loop.proxy(PenRole::Drill));
        reference_force = whole.step(*reference_field, params, reading, 1.0 / params.device.rate_hz).display.force;
        referenced = true;
      }
    }
    const int64_t t0 = steadyNowNs();
    const StepReport& r = loop.step();
    times.add(steadyNowNs() - t0);
    if (referenced && r.stepped[0]) step_sums.add(r.tools[0].display.force, reference_force);
    forces.push_back(r.stepped[0] ? r.tools[0].display.force : Vec3{});
    sums.add(loop.latest().tools[size_t(PenRole::Drill)]);
    sink.clear();
    edits.drain(&sink);
  }
  // As the thread's stop() did: cut jobs still waiting go into the voxels.
  if (follow != nullptr) loop.flushCuts();
  return {summarize(times), sums.load(),          loop.latest().removed_mm3, loop.latest().voxels_changed,
          std::move(forces),  step_sums.result()};
}

// The thread's force against the reference's, over the steps where the reference pressed (|F| > 0.01 N).
ForceError forceError(const std::vector<Vec3>& thread, const std::vector<Vec3>& reference) {
  ErrorSums sums;
  for (size_t i = 0; i < std::min(thread.size(), reference.size()); ++i) sums.add(thread[i], reference[i]);
  return sums.result();
}

struct BareTimerRun {
  std::string scheduler;
  uint64_t missed = 0;
  int64_t max_wake_late_ns = 0;
};

// The loop's thread without the loop: the same real-time request and DeadlineClock, each step a busy
// wait of busy_ns. Errors: a thread that cannot start.
Result<BareTimerRun> runBareTimer(uint64_t steps, int64_t period_ns, int64_t busy_ns, int32_t idle_latency_us) {
  BareTimerRun out;
  auto body = [&] {
    (void)enterRealTime();
    const IdleLatencyRequest idle(idle_latency_us);
    sched_param sp{};
    int policy = 0;
    out.scheduler = pthread_getschedparam(pthread_self(), &policy, &sp) == 0 ? schedulerName(policy, sp.sched_priority)
                                                                             : schedulerName(-1, 0);
    DeadlineClock clock(steadyNowNs());
    for (uint64_t i = 0; i < steps; ++i) {
      const int64_t t0 = steadyNowNs();
      out.max_wake_late_ns = std::max(out.max_wake_late_ns, clock.open(period_ns, t0));
      while (steadyNowNs() - t0 < busy_ns) {
      }
      if (!clock.close(steadyNowNs(), period_ns)) {
        ++out.missed;
        continue;
      }
      clock.sleep();
    }
  };
  try {
    std::thread t(body);
    t.join();
  } catch (const std::system_error& e) {
    return makeError("bench haptic", std::string("cannot start the bare timer's thread: ") + e.what());
  }
  return out;
}

}  // namespace

// ---- 2. one level ----------------------------------------------------------------------------------

Result<HapticBenchRow> runHapticBench(int level, const VolumeMaker& make_volume, const HapticBenchSettings& s,
                                      const std::function<void(const std::string&)>& log) {
  const std::string where = "bench haptic";
  auto say = [&](const std::string& line) {
    if (log) log(line);
  };
  HapticBenchRow row;
  row.level = level;
  row.tool = s.tool;

  // The tooth, the bur and the path.
  auto start = std::chrono::steady_clock::now();
  auto tooth = make_volume(level);
  if (!tooth) return tooth.error();
  row.make_volume_s = secondsSince(start);
  row.voxel_mm = tooth->frame.voxel_mm;
  row.dense_bricks = tooth->voxels.stats().dense_bricks;
  SimParams params = defaultSimParams();
  if (s.rate_hz > 0) params.device.rate_hz = s.rate_hz;
  if (s.contact_budget > 0) params.device.contact_budget = s.contact_budget;
  if (s.cut_budget > 0) params.device.cut_budget = s.cut_budget;
  row.rate_hz = params.device.rate_hz;
  row.budgeted = s.budget;
  auto tool = loadToolModel(s.tool, params.point_shell);
  if (!tool) return tool.error();
  if (!tool->cuts) return makeError(where, s.tool + " does not cut: the benchmark needs a bur");
  row.shell_points = tool->shell.size();
  row.shell_cutting_points = tool->shell.cuttingCount();
  row.shell_clusters = tool->shell.clusters.size();
  start = std::chrono::steady_clock::now();
  auto path = cavityPreparationPath(tooth->voxels, tooth->frame, s.path);
  if (!path) return path.error();
  row.path = *path;
  row.path_s = secondsSince(start);
  {
    char line[256];
    std::snprintf(line, sizeof line,
                  "level %d: %.4f mm voxels (made in %.1f s), %s shell %llu points; fossa at (%.2f, %.2f, %.2f) mm, "
                  "path %.2f s",
                  level, row.voxel_mm, row.make_volume_s, s.tool.c_str(),
                  static_cast<unsigned long long>(row.shell_points), path->fossa_mm.x, path->fossa_mm.y,
                  path->fossa_mm.z, path->duration_s);
    say(line);
  }
  // Untouched copies: the step-only run cuts the same tooth again; the mirror replays the edits.
  std::optional<BrickVolume> pristine, mirror, replayed;
  if (s.step_only) pristine = tooth->voxels;
  if (s.step_only && s.budget) replayed = tooth->voxels;
  if (s.replay_edits) mirror = tooth->voxels;

  const double rate = params.device.rate_hz;
  const auto needed = uint64_t(std::ceil(path->duration_s * rate - 1e-9)) + 1;  // loop time past the end

  // ---- the real-time thread, with a drain thread beside it ----
  std::vector<Vec3> thread_forces;
  {
    EditChannel edits;
    ScriptedPen pen(path->path, PenRole::Drill);
    HapticLoop loop(tooth->voxels, tooth->frame, params, *tool, nullptr, &edits);
    loop.setIdleLatencyUs(s.idle_latency_us);
    loop.setThreadBudget(s.budget ? StepBudget::Clock : StepBudget::None);
    loop.attach(PenRole::Drill, &pen);
    loop.placeTool(PenRole::Drill, path->path.samples.front().pose);
    ThreadProbe probe;
    probe.loop = &loop;
    probe.forces.reserve(size_t(needed) + size_t(rate) * size_t(s.max_wall_factor * path->duration_s + 5.0));
    probe.schedules.reserve(probe.forces.capacity());
    loop.setStepHook(&probeStep, &probe);

    std::atomic<uint64_t> drained{0}, drains{0};
    const auto drain_period = std::chrono::duration<double, std::milli>(s.drain_period_ms);
    BrickVolume* mirror_volume = mirror ? &*mirror : nullptr;
    auto drain_loop = [&edits, &drained, &drains, drain_period, mirror_volume](std::stop_token stop) {
      std::vector<uint64_t> batch;
      batch.reserve(size_t{1} << 16);
      auto once = [&] {
        batch.clear();
        const size_t got = edits.drain(&batch);
        if (got == 0) return;
        drained.fetch_add(got, std::memory_order_relaxed);
        drains.fetch_add(1, std::memory_order_relaxed);
        if (mirror_volume != nullptr) applyVoxelEdits(*mirror_volume, batch, nullptr);
      };
      while (!stop.stop_requested()) {
        once();
        std::this_thread::sleep_for(drain_period);
      }
      once();  // the loop has stopped: whatever is left
    };
    std::jthread drainer;
    try {
      drainer = std::jthread(drain_loop);
    } catch (const std::system_error& e) {
      return makeError(where, std::string("cannot start the drain thread: ") + e.what());
    }

    say("level " + std::to_string(level) + ": running the loop on its thread for " +
        std::to_string(needed) + " steps");
    start = std::chrono::steady_clock::now();
    if (Status st = loop.start(); !st) return st.error();
    const double limit_s = s.max_wall_factor * path->duration_s + 5.0;
    bool late = false;
    while (loop.counters().steps.load(std::memory_order_relaxed) < needed) {
      std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(s.poll_period_ms));
      if (secondsSince(start) > limit_s) {
        late = true;
        break;
      }
    }
    loop.stop();
    row.wall_s = secondsSince(start);
    drainer.request_stop();
    drainer.join();
    if (late)
      return makeError(where, "the loop ran " + std::to_string(loop.counters().steps.load()) + " of " +
                                  std::to_string(needed) + " steps in " + std::to_string(row.wall_s) + " s");

    row.thread = summarize(loop.stepTimes());
    row.missed_deadlines = loop.counters().missed_deadlines.load();
    row.max_wake_late_us = double(loop.counters().max_wake_late_ns.load()) / 1000.0;
    row.max_step_at = loop.counters().max_step_at.load();
    row.long_steps = loop.counters().long_steps.load();
    row.pen_dropouts = loop.counters().pen_dropouts.load();
    row.scheduler = schedulerName(probe.policy, probe.priority);
    row.idle_latency_held = loop.idleLatencyHeld();
    row.idle_latency_note = loop.idleLatencyNote();
    const HapticState& state = loop.latest();  // the thread has stopped: this thread reads now
    probe.sums.add(state.tools[size_t(PenRole::Drill)]);
    probe.keep(loop.lastReport());
    row.contact_overruns = loop.counters().contact_overruns.load();
    row.late_cut_steps = loop.counters().late_cuts.load();
    row.max_cut_lag_steps = loop.counters().max_cut_lag_steps.load();
    row.forced_cuts = loop.counters().forced_cuts.load();
    row.load = probe.sums.load();
    row.removed_mm3 = state.removed_mm3;
    row.voxels_changed = state.voxels_changed;
    row.deferred_cuts = state.deferred_cuts;
    row.edits_drained = drained.load();
    row.drains = drains.load();
    if (mirror) {
      row.mirror_checked = true;
      row.mirror_equal = *mirror == tooth->voxels;
    }
    // Replay follows what each step reached, not the clock: the same voxels on a copy.
    if (replayed && probe.schedules.size() == row.thread.steps) {
      row.step_error = replaySteps(*replayed, tooth->frame, params, *tool, path->path, row.thread.steps, 0, -1,
                                   nullptr, &probe.schedules)
                           .step_error;
      row.replay_checked = true;
      row.replay_equal = *replayed == tooth->voxels;
    }
    replayed.reset();
    thread_forces = std::move(probe.forces);
  }
  mirror.reset();
  if (s.bare_timer) {
    const auto period_ns = int64_t(std::llround(1e9 / rate));
    auto bare = runBareTimer(row.thread.steps, period_ns, int64_t(std::llround(row.thread.mean_us * 1e3)),
                             s.idle_latency_us);
    if (!bare) return bare.error();
    row.has_bare_timer = true;
    row.bare_scheduler = bare->scheduler;
    row.bare_steps = row.thread.steps;
    row.bare_missed = bare->missed;
    row.bare_busy_us = row.thread.mean_us;
    row.bare_max_wake_late_us = double(bare->max_wake_late_ns) / 1000.0;
  }
  row.p99_met = row.thread.p99_us < s.goal_p99_us;
  row.max_met = row.thread.max_us < s.goal_max_us;
  {
    char line[768];
    std::snprintf(line, sizeof line,
                  "level %d thread (%s): %llu steps, p50 %.1f us, p99 %.1f us, max %.1f us (step %llu), %llu missed, %llu of them "
                  "by the step's own time (latest wake %.0f us after its slot); "
                  "%.0f points sampled/step (%.0f skipped), removed %.3f mm^3; %s",
                  level, row.scheduler.c_str(), static_cast<unsigned long long>(row.thread.steps), row.thread.p50_us,
                  row.thread.p99_us, row.thread.max_us, static_cast<unsigned long long>(row.max_step_at),
                  static_cast<unsigned long long>(row.missed_deadlines), static_cast<unsigned long long>(row.long_steps),
                  row.max_wake_late_us, row.load.points_mean, row.load.clear_mean, row.removed_mm3, row.idle_latency_note.c_str());
    say(line);
    if (row.has_bare_timer) {
      std::snprintf(line, sizeof line,
                    "level %d bare timer (%s, each step a %.1f us busy wait): %llu steps, %llu missed (latest wake %.0f us "
                    "after its slot)",
                    level, row.bare_scheduler.c_str(), row.bare_busy_us, static_cast<unsigned long long>(row.bare_steps),
                    static_cast<unsigned long long>(row.bare_missed), row.bare_max_wake_late_us);
      say(line);
    }
    std::snprintf(line, sizeof line,
                  "level %d budget %s at %.0f Hz: %llu passes cut short (%.0f points left/step, max %u); %llu steps left "
                  "cuts for later (longest wait %llu steps, %llu forced); replay of the schedules: %s; force shown against "
                  "an unbudgeted step from the same state: RMS %.4f N (%.2f %% of %.3f N), max %.4f N",
                  level, row.budgeted ? "on" : "off", row.rate_hz, static_cast<unsigned long long>(row.contact_overruns),
                  row.load.points_left_mean, row.load.points_left_max, static_cast<unsigned long long>(row.late_cut_steps),
                  static_cast<unsigned long long>(row.max_cut_lag_steps), static_cast<unsigned long long>(row.forced_cuts),
                  row.replay_checked ? (row.replay_equal ? "the same voxels" : "OTHER VOXELS") : "not checked",
                  row.step_error.rms_n, row.step_error.rmsPercent(), row.step_error.mean_contact_n,
                  row.step_error.max_n);
    say(line);
  }

  // ---- the same steps on this thread: back to back, then each started 1 ms after the last ----
  if (pristine) {
    // Paced last: it cuts a copy, and the back-to-back run the untouched volume itself.
    std::optional<BrickVolume> paced_volume;
    if (s.after_idle) paced_volume = *pristine;
    BrickVolume guided_volume = *pristine;
    std::optional<BrickVolume> floor_volume;
    if (s.floor_offset_mm > 0) floor_volume = *pristine;
    const ReplayedRun back_to_back =
        replaySteps(*pristine, tooth->frame, params, *tool, path->path, row.thread.steps, 0, -1);
    row.has_step_only = true;
    row.step_only = back_to_back.times;
    row.step_only_load = back_to_back.load;
    row.step_only_removed_mm3 = back_to_back.removed_mm3;
    row.step_only_voxels_changed = back_to_back.voxels_changed;
    row.force_error = forceError(thread_forces, back_to_back.forces);
    char line[256];
    std::snprintf(line, sizeof line, "level %d step only: p50 %.1f us, p99 %.1f us, max %.1f us, mean %.1f us", level,
                  row.step_only.p50_us, row.step_only.p99_us, row.step_only.max_us, row.step_only.mean_us);
    say(line);
    std::snprintf(line, sizeof line,
                  "level %d thread's force against step only's: RMS %.4f N (%.2f %% of %.3f N in contact), max %.4f N "
                  "(%.1f %%), over %llu steps",
                  level, row.force_error.rms_n, row.force_error.rmsPercent(), row.force_error.mean_contact_n,
                  row.force_error.max_n, row.force_error.maxPercent(),
                  static_cast<unsigned long long>(row.force_error.steps));
    say(line);
    if (floor_volume) {
      PenPath moved = path->path;
      for (PenSample& sample : moved.samples) sample.pose.position.x += s.floor_offset_mm;
      const ReplayedRun off = replaySteps(*floor_volume, tooth->frame, params, *tool, moved, row.thread.steps, 0, -1);
      floor_volume.reset();
      row.has_path_floor = true;
      row.path_floor_offset_mm = s.floor_offset_mm;
      row.path_floor = forceError(off.forces, back_to_back.forces);
      std::snprintf(line, sizeof line,
                    "level %d the path error's floor: step only with the pen %.4f mm off, against step only: RMS %.4f N "
                    "(%.2f %%), max %.4f N",
                    level, s.floor_offset_mm, row.path_floor.rms_n, row.path_floor.rmsPercent(), row.path_floor.max_n);
      say(line);
    }
    const GuidePath guide = guideAlong(path->path);
    const ReplayedRun guided =
        replaySteps(guided_volume, tooth->frame, params, *tool, path->path, row.thread.steps, 0, -1, &guide);
    row.step_only_guided = guided.times;
    std::snprintf(line, sizeof line, "level %d step only, guided: p50 %.1f us, p99 %.1f us, max %.1f us, mean %.1f us",
                  level, row.step_only_guided.p50_us, row.step_only_guided.p99_us, row.step_only_guided.max_us,
                  row.step_only_guided.mean_us);
    say(line);
    if (paced_volume) {
      const auto period_ns = int64_t(std::llround(1e9 / rate));
      const ReplayedRun paced =
          replaySteps(*paced_volume, tooth->frame, params, *tool, path->path, row.thread.steps, period_ns,
                      s.idle_latency_us);
      row.has_after_idle = true;
      row.after_idle = paced.times;
      row.after_idle_removed_mm3 = paced.removed_mm3;
      row.after_idle_voxels_changed = paced.voxels_changed;
      std::snprintf(line, sizeof line, "level %d after idle: p50 %.1f us, p99 %.1f us, max %.1f us, mean %.1f us",
                    level, row.after_idle.p50_us, row.after_idle.p99_us, row.after_idle.max_us,
                    row.after_idle.mean_us);
      say(line);
    }
  }
  return row;
}

// ---- 3. JSON ---------------------------------------------------------------------------------------
namespace {

nlohmann::json timesJson(const StepTimeSummary& t) {
  nlohmann::json tail = nlohmann::json::array();
  for (auto [nines, us] : t.tail) tail.push_back({{"nines", nines}, {"us", us}});
  return {{"steps", t.steps},   {"p50_us", t.p50_us}, {"p90_us", t.p90_us},   {"p99_us", t.p99_us},
          {"p999_us", t.p999_us}, {"max_us", t.max_us}, {"mean_us", t.mean_us}, {"tail", tail}};
}

nlohmann::json loadJson(const StepLoad& l) {
  return {{"steps", l.steps},
          {"points_tested_mean", l.points_mean},
          {"points_tested_max", l.points_max},
          {"points_clear_mean", l.clear_mean},
          {"contacts_mean", l.contacts_mean},
          {"contacts_max", l.contacts_max},
          {"contact_steps", l.contact_steps},
          {"force_mean_n", l.force_mean_n},
          {"force_max_n", l.force_max_n},
          {"lowest_tip_mm", l.lowest_tip_mm},
          {"points_left_mean", l.points_left_mean},
          {"points_left_max", l.points_left_max}};
}

nlohmann::json vecJson(const Vec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); }

nlohmann::json errorJson(const ForceError& e) {
  return {{"steps", e.steps},           {"rms_n", e.rms_n},
          {"max_n", e.max_n},           {"mean_contact_n", e.mean_contact_n},
          {"rms_percent", e.rmsPercent()}, {"max_percent", e.maxPercent()}};
}

std::string errorCells(const ForceError& e) {
  return formatted("%.4f", e.rms_n) + " (" + formatted("%.2f", e.rmsPercent()) + " % of " +
         formatted("%.3f", e.mean_contact_n) + ") | " + formatted("%.4f", e.max_n) + " (" +
         formatted("%.1f", e.maxPercent()) + " %)";
}

}  // namespace

nlohmann::json hapticReportJson(const HapticReportInfo& info, const std::vector<HapticBenchRow>& rows) {
  const HapticBenchSettings& s = info.settings;
  const CavityPathSettings& p = s.path;
  nlohmann::json levels = nlohmann::json::array();
  nlohmann::json goal = nullptr;
  for (const HapticBenchRow& r : rows) {
    nlohmann::json step_only = nullptr;
    if (r.has_step_only)
      step_only = {{"times", timesJson(r.step_only)},
                   {"guided_times", timesJson(r.step_only_guided)},
                   {"load", loadJson(r.step_only_load)},
                   {"removed_mm3", r.step_only_removed_mm3},
                   {"voxels_changed", r.step_only_voxels_changed}};
    nlohmann::json after_idle = nullptr;
    if (r.has_after_idle)
      after_idle = {{"times", timesJson(r.after_idle)},
                    {"removed_mm3", r.after_idle_removed_mm3},
                    {"voxels_changed", r.after_idle_voxels_changed}};
    levels.push_back({{"level", r.level},
                      {"voxel_mm", r.voxel_mm},
                      {"dense_bricks", r.dense_bricks},
                      {"make_volume_s", r.make_volume_s},
                      {"tool", {{"name", r.tool},
                                {"shell_points", r.shell_points},
                                {"cutting_points", r.shell_cutting_points},
                                {"clusters", r.shell_clusters}}},
                      {"path", {{"crown_centre_mm", vecJson(r.path.crown_centre_mm)},
                                {"fossa_tip_mm", vecJson(r.path.fossa_mm)},
                                {"duration_s", r.path.duration_s},
                                {"cut_start_s", r.path.cut_start_s},
                                {"cut_end_s", r.path.cut_end_s},
                                {"outline_mm", r.path.outline_mm},
                                {"samples", r.path.path.samples.size()},
                                {"build_s", r.path_s}}},
                      {"thread", {{"times", timesJson(r.thread)},
                                  {"missed_deadlines", r.missed_deadlines},
                                  {"max_wake_late_us", r.max_wake_late_us},
                                  {"max_step_at", r.max_step_at},
                                  {"long_steps", r.long_steps},
                                  {"pen_dropouts", r.pen_dropouts},
                                  {"scheduler", r.scheduler},
                                  {"idle_latency", {{"held", r.idle_latency_held}, {"note", r.idle_latency_note}}},
                                  {"wall_s", r.wall_s},
                                  {"load", loadJson(r.load)},
                                  {"removed_mm3", r.removed_mm3},
                                  {"voxels_changed", r.voxels_changed},
                                  {"deferred_cuts", r.deferred_cuts},
                                  {"edits_drained", r.edits_drained},
                                  {"drains", r.drains},
                                  {"mirror_checked", r.mirror_checked},
                                  {"mirror_equal", r.mirror_equal},
                                  {"budget", {{"on", r.budgeted},
                                              {"rate_hz", r.rate_hz},
                                              {"contact_overruns", r.contact_overruns},
                                              {"points_left_mean", r.load.points_left_mean},
                                              {"points_left_max", r.load.points_left_max},
                                              {"late_cut_steps", r.late_cut_steps},
                                              {"max_cut_lag_steps", r.max_cut_lag_steps},
                                              {"forced_cuts", r.forced_cuts},
                                              {"replay_checked", r.replay_checked},
                                              {"replay_equal", r.replay_equal}}}}},
                      {"step_error", r.replay_checked ? errorJson(r.step_error) : nlohmann::json(nullptr)},
                      {"force_error", r.has_step_only ? errorJson(r.force_error) : nlohmann::json(nullptr)},
                      {"path_error_floor", r.has_path_floor ? nlohmann::json{{"pen_offset_mm", r.path_floor_offset_mm},
                                                                             {"error", errorJson(r.path_floor)}}
                                                            : nlohmann::json(nullptr)},
                      {"bare_timer", r.has_bare_timer ? nlohmann::json{{"scheduler", r.bare_scheduler},
                                                                      {"steps", r.bare_steps},
                                                                      {"busy_us", r.bare_busy_us},
                                                                      {"missed_deadlines", r.bare_missed},
                                                                      {"max_wake_late_us", r.bare_max_wake_late_us}}
                                                      : nlohmann::json(nullptr)},
                      {"step_only", step_only},
                      {"after_idle", after_idle},
                      {"p99_met", r.p99_met},
                      {"max_met", r.max_met}});
    if (r.level == s.goal_level) goal = {{"p99_met", r.p99_met}, {"max_met", r.max_met}};
  }
  return {{"benchmark", "haptic"},
          {"model", info.model},
          {"command", info.command},
          {"machine", {{"cpu", info.cpu},
                       {"cpu_threads", info.cpu_threads},
                       {"voxelizer", info.voxelizer},
                       {"loadavg_before", info.load_before},
                       {"loadavg_after", info.load_after}}},
          {"settings", {{"tool", s.tool},
                        {"rate_hz", s.rate_hz > 0 ? s.rate_hz : defaultSimParams().device.rate_hz},
                        {"budget", s.budget},
                        {"contact_budget", s.contact_budget > 0 ? s.contact_budget : defaultSimParams().device.contact_budget},
                        {"cut_budget", s.cut_budget > 0 ? s.cut_budget : defaultSimParams().device.cut_budget},
                        {"step_only", s.step_only},
                        {"floor_offset_mm", s.floor_offset_mm},
                        {"bare_timer", s.bare_timer},
                        {"after_idle", s.after_idle},
                        {"idle_latency_us", s.idle_latency_us},
                        {"replay_edits", s.replay_edits},
                        {"drain_period_ms", s.drain_period_ms},
                        {"poll_period_ms", s.poll_period_ms},
                        {"path", {{"bur_radius_mm", p.bur_radius_mm},
                                  {"approach_mm", p.approach_mm},
                                  {"press_mm", p.press_mm},
                                  {"step_down_mm", p.step_down_mm},
                                  {"oval_mm", {p.oval_x_mm, p.oval_y_mm}},
                                  {"speed_mm_s", p.speed_mm_s},
                                  {"laps", p.laps},
                                  {"hold_s", p.hold_s},
                                  {"descent_s", p.descent_s},
                                  {"dwell_s", p.dwell_s},
                                  {"lift_s", p.lift_s},
                                  {"sample_s", p.sample_s}}},
                        {"statistic", "percentiles of all steps, 0.5 us bins (upper edge)"}}},
          {"levels", levels},
          {"goals", {{"level", s.goal_level},
                     {"p99_under_us", s.goal_p99_us},
                     {"max_under_us", s.goal_max_us},
                     {"met", goal}}}};
}

// ---- 4. Markdown -----------------------------------------------------------------------------------
namespace {

std::string count(uint64_t v) { return std::to_string(v); }

}  // namespace

std::string hapticRowsTable(const std::vector<HapticBenchRow>& rows, const HapticBenchSettings& s) {
  std::ostringstream o;
  o << "| level | voxel [mm] | run | steps | missed deadlines | p50 [us] | p99 [us] | max [us] | mean [us] | "
       "points sampled / step (mean, max) | points skipped / step | contacts / step (mean, max) | removed [mm^3] | "
       "edits | deferred | goals |\n"
       "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const HapticBenchRow& r : rows) {
    const bool goal_row = r.level == s.goal_level;
    o << "| " << r.level << " | " << formatted("%.4f", r.voxel_mm) << " | thread (" << r.scheduler << ") | "
      << count(r.thread.steps) << " | " << count(r.missed_deadlines) << " | " << formatted("%.1f", r.thread.p50_us) << " | "
      << formatted("%.1f", r.thread.p99_us) << " | " << formatted("%.1f", r.thread.max_us) << " | "
      << formatted("%.1f", r.thread.mean_us) << " | " << formatted("%.0f", r.load.points_mean) << ", " << r.load.points_max
      << " | " << formatted("%.0f", r.load.clear_mean) << " | " << formatted("%.0f", r.load.contacts_mean) << ", " << r.load.contacts_max << " | "
      << formatted("%.3f", r.removed_mm3) << " | " << count(r.voxels_changed) << " | " << count(r.deferred_cuts) << " | ";
    if (goal_row)
      o << "p99 " << (r.p99_met ? "met" : "missed") << ", max " << (r.max_met ? "met" : "missed");
    else
      o << "(level " << s.goal_level << " only)";
    o << " |\n";
    if (r.has_bare_timer)
      o << "| " << r.level << " | " << formatted("%.4f", r.voxel_mm) << " | bare timer (" << r.bare_scheduler << ", "
        << formatted("%.1f", r.bare_busy_us) << " us busy) | " << count(r.bare_steps) << " | " << count(r.bare_missed)
        << " | - | - | - | - | - | - | - | - | - | - | - |\n";
    if (r.has_step_only)
      o << "| " << r.level << " | " << formatted("%.4f", r.voxel_mm) << " | step only | " << count(r.step_only.steps)
        << " | - | " << formatted("%.1f", r.step_only.p50_us) << " | " << formatted("%.1f", r.step_only.p99_us) << " | "
        << formatted("%.1f", r.step_only.max_us) << " | " << formatted("%.1f", r.step_only.mean_us) << " | "
        << formatted("%.0f", r.step_only_load.points_mean) << ", " << r.step_only_load.points_max << " | "
        << formatted("%.0f", r.step_only_load.clear_mean) << " | "
        << formatted("%.0f", r.step_only_load.contacts_mean) << ", " << r.step_only_load.contacts_max << " | "
        << formatted("%.3f", r.step_only_removed_mm3) << " | " << count(r.step_only_voxels_changed) << " | - | - |\n"
        << "| " << r.level << " | " << formatted("%.4f", r.voxel_mm) << " | step only, guided | " << count(r.step_only_guided.steps)
        << " | - | " << formatted("%.1f", r.step_only_guided.p50_us) << " | " << formatted("%.1f", r.step_only_guided.p99_us) << " | "
        << formatted("%.1f", r.step_only_guided.max_us) << " | " << formatted("%.1f", r.step_only_guided.mean_us)
        << " | - | - | - | - | - | - | - |\n";
    if (r.has_after_idle)  // the same steps as step only: their load is that run's
      o << "| " << r.level << " | " << formatted("%.4f", r.voxel_mm) << " | after idle | " << count(r.after_idle.steps)
        << " | - | " << formatted("%.1f", r.after_idle.p50_us) << " | " << formatted("%.1f", r.after_idle.p99_us) << " | "
        << formatted("%.1f", r.after_idle.max_us) << " | " << formatted("%.1f", r.after_idle.mean_us) << " | (as step only) | | | "
        << formatted("%.3f", r.after_idle_removed_mm3) << " | " << count(r.after_idle_voxels_changed) << " | - | - |\n";
  }
  return o.str();
}

std::string hapticReportMarkdown(const HapticReportInfo& info, const std::vector<HapticBenchRow>& rows) {
  const HapticBenchSettings& s = info.settings;
  const CavityPathSettings& p = s.path;
  std::ostringstream o;
  o << "Model: " << info.model << ", voxelized by " << info.voxelizer << ". CPU " << info.cpu << ", "
    << info.cpu_threads << " hardware threads; load average before " << info.load_before << ", after "
    << info.load_after << ".\n\n"
    << "A scripted class I preparation with " << s.tool << " held vertically (a ScriptedPen, samples every "
    << formatted("%g", p.sample_s * 1000) << " ms): the central fossa is where the bur rests lowest within "
    << formatted("%g", p.fossa_search_mm) << " mm of the crown's centre; the pen starts " << formatted("%g", p.approach_mm)
    << " mm above the bur's resting height over the +x end of a " << formatted("%g", p.oval_x_mm) << " x "
    << formatted("%g", p.oval_y_mm) << " mm oval around the fossa, the pedal goes to 1, the target comes down to "
    << formatted("%g", p.press_mm) << " mm below the resting height (coupling 1 N/mm), then traces " << formatted("%g", p.laps)
    << " laps of the oval at " << formatted("%g", p.speed_mm_s) << " mm/s, " << formatted("%g", p.press_mm)
    << " mm below the untouched surface and " << formatted("%g", p.step_down_mm)
    << " mm deeper per lap; then pedal up and lift. The cutting rate does not depend on the force, so the bur "
       "sinks toward the target as fast as it removes tissue: the force shown drops below the press as it does.\n\n"
    << "Thread: HapticLoop::start(), the loop on its own thread at "
    << formatted("%g", s.rate_hz > 0 ? s.rate_hz : defaultSimParams().device.rate_hz)
    << " Hz with absolute deadlines" << (s.budget ? ", keeping to the step budget (contact pass and cuts)" : ", no step budget")
    << ", until its time "
       "passes the path's end; a second thread drains the voxel edits every "
    << formatted("%g", s.drain_period_ms) << " ms" << (s.replay_edits ? " into a mirror copy, as the renderer would" : "")
    << ". Step times are HapticLoop::stepTimes() (0.5 us bins; a percentile is its bin's upper edge); a missed "
       "deadline is a step that ended after its slot. Bare timer: right after the thread, a thread at the same "
       "policy on the same clock whose every step is a busy wait as long as the thread's mean step: its misses "
       "are the machine's late wake-ups, which no step budget can shorten. Points sampled / step: shell points "
       "sampled against the "
       "field, from every step's snapshot. Points skipped: those still within the clearance of their last sample "
       "(the contacts are exactly those of a full test); points in clusters of empty 64^3 chunks count in neither. "
       "Step only: the same steps on the "
       "bench thread, back to back, no deadlines: the compute alone. After idle: the same steps on the bench "
       "thread at its normal priority, without the drain thread, each started 1 ms after the last began, so "
       "the thread idles between them as the loop's does: what idling alone costs the next step. Goals (level "
    << s.goal_level << "): p99 under " << formatted("%g", s.goal_p99_us) << " us and max under " << formatted("%g", s.goal_max_us)
    << " us on the thread.\n\n";
  if (!info.command.empty()) o << "Command: `" << info.command << "`\n\n";
  o << hapticRowsTable(rows, s) << "\n";
  o << "| level | shell points (cutting) | fossa tip [mm] | path [s] | contact steps | force in contact (mean, max) "
       "[N] | lowest tip [mm] | drained edits | mirror | wall [s] |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const HapticBenchRow& r : rows)
    o << "| " << r.level << " | " << r.shell_points << " (" << r.shell_cutting_points << ") | ("
      << formatted("%.2f", r.path.fossa_mm.x) << ", " << formatted("%.2f", r.path.fossa_mm.y) << ", "
      << formatted("%.2f", r.path.fossa_mm.z) << ") | " << formatted("%.2f", r.path.duration_s) << " | " << r.load.contact_steps
      << " | " << formatted("%.2f", r.load.force_mean_n) << ", " << formatted("%.2f", r.load.force_max_n) << " | "
      << formatted("%.3f", r.load.lowest_tip_mm) << " | " << r.edits_drained << " | "
      << (r.mirror_checked ? (r.mirror_equal ? "equal" : "DIFFERS") : "not checked") << " | "
      << formatted("%.2f", r.wall_s) << " |\n";
  o << "\nThe step budget on the thread. Step error: each of the thread's steps replayed from its "
       "schedule, the force it showed against the force an unbudgeted step shows from the same state (the "
       "proxy as the step found it, the same voxels, the same reading). Path error: the force shown by the "
       "thread against step only's (no budget) on the same pen path, each cutting its own tooth. Its floor: "
       "step only again with the pen path moved "
    << formatted("%g", s.floor_offset_mm * 1000.0)
    << " um, against step only; a force that is not the reference's bit for bit cuts a cavity that drifts "
       "from it, and the pen-to-proxy spring turns that drift into force. All over the "
       "steps where the reference exceeds 0.01 N; percentages of the reference's mean.\n\n"
       "| level | rate [Hz] | budget | passes cut short | points left / step (mean, max) | steps leaving cuts | "
       "longest cut wait [steps] | forced cuts | replay of the schedules | step error RMS [N] (% of mean) | "
       "max [N] (%) | path error RMS [N] (% of mean) | max [N] (%) | its floor RMS [N] (% of mean) | max [N] (%) |\n"
       "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const HapticBenchRow& r : rows)
    o << "| " << r.level << " | " << formatted("%g", r.rate_hz) << " | " << (r.budgeted ? "on" : "off") << " | "
      << r.contact_overruns << " | " << formatted("%.0f", r.load.points_left_mean) << ", " << r.load.points_left_max << " | "
      << r.late_cut_steps << " | " << r.max_cut_lag_steps << " | " << r.forced_cuts << " | "
      << (r.replay_checked ? (r.replay_equal ? "same voxels" : "OTHER VOXELS") : "not checked") << " | "
      << (r.replay_checked ? errorCells(r.step_error) : std::string("- | -")) << " | "
      << (r.has_step_only ? errorCells(r.force_error) : std::string("- | -")) << " | "
      << (r.has_path_floor ? errorCells(r.path_floor) : std::string("- | -")) << " |\n";
  o << "\nIdle CPUs while the thread and the after-idle run ran (requested: "
    << (s.idle_latency_us < 0 ? std::string("nothing") : "wake within " + std::to_string(s.idle_latency_us) + " us")
    << "):";
  for (const HapticBenchRow& r : rows) o << " level " << r.level << ": " << r.idle_latency_note << ".";
  o << "\n";
  return o.str();
}

// ---- 5. SVG and files ------------------------------------------------------------------------------

std::string hapticRowsSvg(const std::vector<HapticBenchRow>& rows, const HapticBenchSettings& s) {
  std::vector<PlotSeries> series;
  double nines_max = 4.0;
  for (size_t i = 0; i < rows.size(); ++i) {
    const HapticBenchRow& r = rows[i];
    PlotSeries thread{"level " + std::to_string(r.level) + ", thread", r.thread.tail, int(i), ""};
    series.push_back(std::move(thread));
    if (r.has_step_only)
      series.push_back({"level " + std::to_string(r.level) + ", step only", r.step_only.tail, int(i), "7,4"});
    if (r.has_after_idle)
      series.push_back({"level " + std::to_string(r.level) + ", after idle", r.after_idle.tail, int(i), "2,2"});
    for (auto [n, us] : r.thread.tail) nines_max = std::max(nines_max, n);
  }
  series.push_back({"p99 goal", {{2.0, s.goal_p99_us}, {nines_max, s.goal_p99_us}}, 4, "2,3"});
  series.push_back({"max goal", {{0.0, s.goal_max_us}, {nines_max, s.goal_max_us}}, 5, "2,3"});
  return svgLinePlot("Haptic step time, " + s.tool + " preparing a cavity",
                     "percentile 100 (1 - 10^-x): 0 = min, 1 = p90, 2 = p99, 3 = p99.9", "step time [us] (log)", series,
                     /*log_y=*/true);
}

Status writeHapticReport(const std::string& dir, const HapticReportInfo& info, const std::vector<HapticBenchRow>& rows) {
  const std::vector<std::pair<std::string, std::string>> files{
      {"haptic.json", hapticReportJson(info, rows).dump(2) + "\n"},
      {"haptic.md", hapticReportMarkdown(info, rows)},
      {"haptic.svg", hapticRowsSvg(rows, info.settings)}};
  for (const auto& [name, text] : files) {
    const auto* bytes = reinterpret_cast<const uint8_t*>(text.data());
    if (auto st = writeFileAtomic(dir + "/" + name, std::span<const uint8_t>(bytes, text.size())); !st) return st;
  }
  return Ok{};
}

}  // namespace dentsim::bench
