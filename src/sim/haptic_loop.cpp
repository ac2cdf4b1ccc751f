// HapticLoop: the haptic step as a table of contents, and the real-time thread with absolute deadlines.
#include "sim/haptic_loop.h"

#include <algorithm>
#include <cmath>
#include <system_error>

#include "core/percentile.h"
#include "core/steady_clock.h"
#include "sim/deadline_clock.h"
#include "sim/idle_latency.h"

namespace dentsim {

namespace {
// Spare storage reserved in the volume before the loop runs, so cutting never allocates: enough
// for a bur to open this many new bricks and chunk blocks before the reserve must be renewed.
constexpr size_t kSpareBricks = 16384;  // 8 MiB of bricks
constexpr size_t kSpareBlocks = 4096;   // 8 MiB of index blocks
}  // namespace

// ---- step times ---------------------------------------------------------------------------------------

void StepTimes::add(int64_t ns) {
  const int64_t bin = std::clamp<int64_t>(ns / 500, 0, kBins - 1);
  ++bins_[size_t(bin)];
  ++count_;
  sum_ns_ += ns;
  max_ns_ = std::max(max_ns_, ns);
}

double StepTimes::percentileUs(double p) const {
  if (count_ == 0) return 0.0;
  const size_t bin = percentileBin<uint32_t>(bins_, std::clamp(p, 0.0, 100.0));
  // The bin's upper edge bounds every step in it; the slowest step bounds the last, open-ended bin.
  return std::min(0.5 * double(bin + 1), maxUs());
}

// ---- set-up -------------------------------------------------------------------------------------------

HapticLoop::HapticLoop(BrickVolume& volume, const VolumeFrame& frame, const SimParams& params, const ToolModel& drill,
                       const ToolModel* mirror, EditChannel* edits)
    : volume_(volume),
      field_(volume, frame),
      params_(ParamsUpdate{params, 0}),
      cutter_(size_t{1} << 17),
      // Room for several steps' whole contact sets: a queue that fills runs its oldest job first.
      cut_pool_(std::max<size_t>(4 * drill.shell.size(), 4096)),
      edits_(edits),
      state_(HapticState{}) {
  tools_ = {&drill, mirror};
  activate(params_.read());
  proxies_[0] = std::make_unique<ToolProxy>(drill);
  if (mirror != nullptr) proxies_[1] = std::make_unique<ToolProxy>(*mirror);
  volume_.reserveSpare(kSpareBlocks, kSpareBricks);
  totals_.tools[0].present = true;
  totals_.tools[1].present = mirror != nullptr;
}

HapticLoop::~HapticLoop() { stop(); }

void HapticLoop::attach(PenRole role, PenSource* pen) { pens_[size_t(role)] = pen; }

void HapticLoop::placeTool(PenRole role, const Pose& grip) {
  if (proxies_[size_t(role)]) proxies_[size_t(role)]->reset(grip);
}

uint32_t HapticLoop::setParams(const SimParams& params) {
  const uint32_t serial = next_serial_.fetch_add(1, std::memory_order_relaxed);
  params_.publish(ParamsUpdate{params, serial});
  return serial;
}

void HapticLoop::activate(const ParamsUpdate& update) {
  active_params_ = &update.params;
  active_serial_ = update.serial;
  drill_ability_ = update.params.cuttingAbility(tools_[0]->name);  // a map lookup: once per change, not per step
}

void HapticLoop::record(const std::array<PenReading, 2>& readings, int64_t now_ns) {
  SessionStep* r = record_->reserve();
  if (r == nullptr) {
    dropped_records_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  r->step = step_.load(std::memory_order_relaxed);
  r->wall_ns = now_ns;
  r->params_serial = active_serial_;
  r->pens = 0;
  for (size_t p = 0; p < 2; ++p) {
    const bool stepped = report_.stepped[p];
    r->pens |= uint8_t(stepped ? 1u << p : 0u);
    SessionPenReading& out = r->reading[p];
    out = SessionPenReading{};
    if (stepped) {
      const PenReading& in = readings[p];
      out.grip = in.grip;
      out.velocity = in.velocity;
      out.angular_velocity = in.angular_velocity;
      out.buttons = in.buttons;
      out.pedal = in.pedal;
    }
    r->force_n[p] = stepped ? report_.tools[p].display.force : Vec3{};
    r->contacts[p] = stepped ? report_.tools[p].stats.contacts : 0;
  }
  r->schedule = report_.schedule;
  record_->push();
}

// ---- the cut stage ------------------------------------------------------------------------------------

void HapticLoop::runCut(std::span<const ContactPoint> contacts, double speed, double dt, uint64_t step) {
  report_.cut += cutter_.cut(volume_, field_, contacts, *active_params_, drill_ability_, speed, dt, step, edits_);
  ++report_.cuts_run;
}

void HapticLoop::bookCut(const CutStep& cut) {
  totals_.removed_mm3 += cut.removed_mm3;
  for (size_t m = 0; m < totals_.removed_by_material_mm3.size(); ++m)
    totals_.removed_by_material_mm3[m] += cut.removed_by_material_mm3[m];
  totals_.voxels_changed += cut.voxels_changed;
}

void HapticLoop::runOldestCut(bool forced) {
  const CutJob& job = cut_jobs_[cut_head_];
  runCut(std::span<const ContactPoint>(cut_pool_.data() + job.first, job.count), job.speed, job.dt, job.step);
  cut_head_ = (cut_head_ + 1) % kCutJobs;
  --cut_count_;
  report_.cuts_forced += forced ? 1 : 0;
}

void HapticLoop::enqueueCut(std::span<const ContactPoint> contacts, double speed, double dt, uint64_t step) {
  const uint32_t n = uint32_t(contacts.size());
  const uint32_t pool = uint32_t(cut_pool_.size());
  // Where the job's contacts go: after the newest job's, or from the start of the ring; the oldest
  // waiting job's contacts must not be overwritten.
  auto place = [&]() -> int64_t {
    if (cut_count_ == kCutJobs || n > pool) return -1;
    if (cut_count_ == 0) return 0;
    const uint32_t oldest = cut_jobs_[cut_head_].first;
    if (cut_write_ > oldest) {  // the waiting contacts lie in [oldest, cut_write_): room after them, or before
      if (cut_write_ + n <= pool) return int64_t{cut_write_};
      return n <= oldest ? int64_t{0} : int64_t{-1};
    }
    // They wrap: room between the newest and the oldest.
    return cut_write_ + n <= oldest ? int64_t{cut_write_} : int64_t{-1};
  };
  int64_t at = place();
  while (at < 0 && cut_count_ > 0) {
    runOldestCut(/*forced=*/true);
    at = place();
  }
  if (at < 0) return;  // a contact set larger than the ring: cannot happen (the ring holds four shells)
  std::copy(contacts.begin(), contacts.end(), cut_pool_.begin() + at);
  cut_jobs_[(cut_head_ + cut_count_) % kCutJobs] = CutJob{step, uint32_t(at), n, speed, dt};
  ++cut_count_;
  cut_write_ = uint32_t(at) + n;
}

// ---- the step -----------------------------------------------------------------------------------------

const StepReport& HapticLoop::step() {
  const int64_t start_ns = steadyNowNs();
  if (hook_ != nullptr) hook_(step_.load(std::memory_order_relaxed), hook_user_);
  if (params_.fresh()) activate(params_.read());
  const SimParams& p = *active_params_;
  const double dt = 1.0 / p.device.rate_hz;
  const double t = totals_.t_s;
  const uint64_t step_index = step_.load(std::memory_order_relaxed);
  report_.stepped = {false, false};
  report_.force_limited = {false, false};
  report_.cut = CutStep{};
  report_.cuts_run = 0;
  report_.cuts_forced = 0;
  report_.schedule = SessionSchedule{};

  // 1. Read the pens.
  std::array<PenReading, 2> readings{};
  for (size_t r = 0; r < 2; ++r) {
    if (tools_[r] == nullptr || pens_[r] == nullptr) continue;
    report_.stepped[r] = pens_[r]->read(t, &readings[r]);
    if (!report_.stepped[r]) counters_.pen_dropouts.fetch_add(1, std::memory_order_relaxed);
  }

  // 2. Contact and coupling, each tool against the voxels as they are now, within the budget.
  const double period_ns = 1e9 * dt;
  for (size_t r = 0; r < 2; ++r) {
    if (!report_.stepped[r]) continue;
    ContactBudget budget;
    const ContactBudget* use = nullptr;
    if (follow_ != nullptr) {
      // Replay: a pass the recording says was whole is whole here too, whatever the budget.
      if (follow_->clusters[r] != SessionSchedule::kAll) {
        budget.clusters = follow_->clusters[r];
        use = &budget;
      }
    } else if (budget_ == StepBudget::Clock) {
      budget.deadline_ns = start_ns + int64_t(p.device.contact_budget * period_ns);
      use = &budget;
    } else if (budget_ == StepBudget::Points) {
      budget.max_points = std::max<uint32_t>(budget_points_, 1);
      use = &budget;
    }
    report_.tools[r] = proxies_[r]->step(field_, p, readings[r], dt, use);
    if (report_.tools[r].stats.clusters_left > 0) report_.schedule.clusters[r] = report_.tools[r].stats.clusters_reached;
  }
  if (!report_.schedule.isDefault()) {
    ++totals_.contact_overruns;
    counters_.contact_overruns.fetch_add(1, std::memory_order_relaxed);
  }

  // 2b. The guide's spring joins the drill's force under the device's clamp: what the hand feels,
  // never what moves the proxy.
  report_.guide_n = {};
  if (guide_ != nullptr && report_.stepped[0]) {
    report_.guide_n = guide_->force(proxies_[0]->grip().position);
    ProxyStep& d = report_.tools[0];
    d.display.force += report_.guide_n;
    if (clampLength(&d.display.force, p.device.max_force_n)) d.force_clamped = true;
  }

  // 2c. No jolt: the force shown moves toward the new one by a bounded step (a pen without a reading
  // is shown zero, and comes back from zero the same way).
  const double max_change = p.device.max_force_change_n_per_ms * dt * 1e3;
  for (size_t r = 0; r < 2; ++r) {
    if (!report_.stepped[r]) {
      last_force_[r] = {};
      continue;
    }
    Vec3& f = report_.tools[r].display.force;
    Vec3 change = f - last_force_[r];
    if (clampLength(&change, max_change)) {
      f = last_force_[r] + change;
      report_.force_limited[r] = true;
    }
    last_force_[r] = f;
  }

  // 3. Command the forces: a pen without a reading this step gets zero.
  const int64_t now = steadyNowNs();
  for (size_t r = 0; r < 2; ++r) {
    const Wrench w = report_.stepped[r] ? report_.tools[r].display : Wrench{};
    forces_[r].publish(w, now);
    if (pens_[r] != nullptr) pens_[r]->display(w, t);
  }

  // 4. Cut under the drill's head, after the forces are out; the next step's contact feels it. The
  // step's own cut runs at once when nothing waits and the budget allows; otherwise it queues, and
  // the queue runs oldest first for as long as the budget (or the recorded schedule) says.
  report_.speed = report_.stepped[0] ? std::clamp(readings[0].pedal, 0.0, 1.0) : 0.0;
  const bool cutting = report_.stepped[0] && tools_[0]->cuts && report_.speed > 0;
  const bool clocked = follow_ == nullptr && budget_ == StepBudget::Clock;
  const int64_t cut_deadline = start_ns + int64_t((p.device.contact_budget + p.device.cut_budget) * period_ns);
  const uint32_t allowed = follow_ != nullptr ? follow_->cuts : SessionSchedule::kAll;
  auto mayRunAnother = [&] {
    if (report_.cuts_run - report_.cuts_forced >= allowed) return false;
    return !clocked || steadyNowNs() < cut_deadline;
  };
  while (cut_count_ > 0 && step_index - cut_jobs_[cut_head_].step >= kMaxCutLagSteps) {
    runOldestCut(/*forced=*/true);
  }
  if (cutting) {
    if (cut_count_ == 0 && mayRunAnother())
      runCut(report_.tools[0].contacts, report_.speed, dt, step_index);
    else
      enqueueCut(report_.tools[0].contacts, report_.speed, dt, step_index);
  }
  while (cut_count_ > 0 && mayRunAnother()) runOldestCut();
  report_.cuts_waiting = uint32_t(cut_count_);
  report_.cut_lag_steps = cut_count_ > 0 ? step_index - cut_jobs_[cut_head_].step : 0;
  if (cut_count_ > 0) report_.schedule.cuts = report_.cuts_run - report_.cuts_forced;

  // 5. Hand off the state (and the step's record, when a session is being recorded).
  for (size_t r = 0; r < 2; ++r) {
    ToolState& ts = totals_.tools[r];
    ts.pen_ok = report_.stepped[r];
    if (report_.stepped[r]) ts.pen = readings[r].grip;
    if (proxies_[r]) ts.tool = proxies_[r]->toolPose();
    ts.display = report_.stepped[r] ? report_.tools[r].display : Wrench{};
    ts.contacts = report_.stepped[r] ? report_.tools[r].stats.contacts : 0;
    ts.points_tested = report_.stepped[r] ? report_.tools[r].stats.points_tested : 0;
    ts.points_clear = report_.stepped[r] ? report_.tools[r].stats.points_clear : 0;
    ts.points_left = report_.stepped[r] ? report_.tools[r].stats.points_left : 0;
  }
  if (record_ != nullptr) record(readings, now);
  totals_.step = step_.fetch_add(1, std::memory_order_release) + 1;
  totals_.t_s = t + dt;
  totals_.pedal = report_.speed;
  totals_.guide_n = report_.guide_n;
  totals_.rpm = report_.speed * p.turbine.max_rpm;
  bookCut(report_.cut);
  totals_.deferred_cuts += report_.cut.deferred ? 1 : 0;
  totals_.cut_queue = report_.cuts_waiting;
  totals_.cut_lag_steps = report_.cut_lag_steps;
  if (report_.cuts_waiting > 0) counters_.late_cuts.fetch_add(1, std::memory_order_relaxed);
  counters_.forced_cuts.fetch_add(report_.cuts_forced, std::memory_order_relaxed);
  if (report_.cut_lag_steps > counters_.max_cut_lag_steps.load(std::memory_order_relaxed))
    counters_.max_cut_lag_steps.store(report_.cut_lag_steps, std::memory_order_relaxed);
  state_.publish(totals_);
  return report_;
}

// ---- the thread ---------------------------------------------------------------------------------------

Status HapticLoop::start() {
  if (running()) return makeError("haptic loop", "already running");
  stop_requested_.store(false);
  try {
    thread_ = std::thread([this] { run(); });
  } catch (const std::system_error& e) {
    return makeError("haptic loop", std::string("cannot start its thread: ") + e.what());
  }
  return Ok{};
}

void HapticLoop::stop() {
  if (!running()) return;
  stop_requested_.store(true);
  thread_.join();
  flushCuts();
}

uint32_t HapticLoop::flushCuts() {
  if (cut_count_ == 0) return 0;
  // Booked to the last step's report, as if that step had had the time to run them.
  const CutStep before = report_.cut;
  const uint32_t runs = report_.cuts_run;
  report_.cut = CutStep{};
  while (cut_count_ > 0) runOldestCut();
  bookCut(report_.cut);
  report_.cut += before;
  report_.cuts_waiting = 0;
  report_.cut_lag_steps = 0;
  totals_.cut_queue = 0;
  totals_.cut_lag_steps = 0;
  state_.publish(totals_);
  return report_.cuts_run - runs;
}

void HapticLoop::run() {
  (void)enterRealTime();

  // Held until run() returns; set up before the first step, read by others after stop() joins.
  const IdleLatencyRequest idle(idle_latency_us_);
  idle_latency_note_ = idle.note();
  idle_latency_held_ = idle.held();
  idle_latency_denied_ = idle.denied();

  // The thread's steps keep to the clock's budget; step() called directly keeps its own.
  const StepBudget direct = budget_;
  budget_ = thread_budget_;
  DeadlineClock clock(steadyNowNs());
  while (!stop_requested_.load(std::memory_order_relaxed)) {
    // The rate in force when the slot opens holds for the whole slot, even if the step activates new parameters.
    const auto period_ns = int64_t(std::llround(1e9 / active_params_->device.rate_hz));
    const int64_t t0 = steadyNowNs();
    const int64_t late = clock.open(period_ns, t0);
    if (late > counters_.max_wake_late_ns.load(std::memory_order_relaxed))
      counters_.max_wake_late_ns.store(late, std::memory_order_relaxed);
    step();
    const int64_t t1 = steadyNowNs();
    times_.add(t1 - t0);
    counters_.steps.fetch_add(1, std::memory_order_relaxed);
    if (t1 - t0 > counters_.max_step_ns.load(std::memory_order_relaxed)) {
      counters_.max_step_ns.store(t1 - t0, std::memory_order_relaxed);
      counters_.max_step_at.store(totals_.step - 1, std::memory_order_relaxed);
    }
    if (t1 - t0 > period_ns) counters_.long_steps.fetch_add(1, std::memory_order_relaxed);
    if (!clock.close(t1, period_ns)) {
      counters_.missed_deadlines.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    clock.sleep();
  }
  budget_ = direct;
}

}  // namespace dentsim
