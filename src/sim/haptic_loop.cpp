// HapticLoop: the haptic step as a table of contents, and the real-time thread with absolute deadlines.
#include "sim/haptic_loop.h"

#include <sys/prctl.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <system_error>

#include "core/percentile.h"
#include "core/steady_clock.h"
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
  record_->push();
}

// ---- the step -----------------------------------------------------------------------------------------

const StepReport& HapticLoop::step() {
  if (hook_ != nullptr) hook_(step_.load(std::memory_order_relaxed), hook_user_);
  if (params_.fresh()) activate(params_.read());
  const SimParams& p = *active_params_;
  const double dt = 1.0 / p.device.rate_hz;
  const double t = totals_.t_s;
  report_.stepped = {false, false};
  report_.cut = CutStep{};

  // 1. Read the pens.
  std::array<PenReading, 2> readings{};
  for (size_t r = 0; r < 2; ++r) {
    if (tools_[r] == nullptr || pens_[r] == nullptr) continue;
    report_.stepped[r] = pens_[r]->read(t, &readings[r]);
    if (!report_.stepped[r]) counters_.pen_dropouts.fetch_add(1, std::memory_order_relaxed);
  }

  // 2. Contact and coupling, each tool against the voxels as they are now.
  for (size_t r = 0; r < 2; ++r)
    if (report_.stepped[r]) report_.tools[r] = proxies_[r]->step(field_, p, readings[r], dt);

  // 2b. The guide's spring joins the drill's force under the device's clamp: what the hand feels,
  // never what moves the proxy.
  report_.guide_n = {};
  if (guide_ != nullptr && report_.stepped[0]) {
    report_.guide_n = guide_->force(proxies_[0]->grip().position);
    ProxyStep& d = report_.tools[0];
    d.display.force += report_.guide_n;
    if (clampLength(&d.display.force, p.device.max_force_n)) d.force_clamped = true;
  }

  // 3. Cut under the drill's head; the next step's contact already feels it.
  report_.speed = report_.stepped[0] ? std::clamp(readings[0].pedal, 0.0, 1.0) : 0.0;
  if (report_.stepped[0] && tools_[0]->cuts && report_.speed > 0) {
    report_.cut = cutter_.cut(volume_, field_, report_.tools[0].contacts, p, drill_ability_,
                              report_.speed, dt, step_.load(std::memory_order_relaxed), edits_);
  }

  // 4. Command the forces: a pen without a reading this step gets zero.
  const int64_t now = steadyNowNs();
  for (size_t r = 0; r < 2; ++r) {
    const Wrench w = report_.stepped[r] ? report_.tools[r].display : Wrench{};
    forces_[r].publish(w, now);
    if (pens_[r] != nullptr) pens_[r]->display(w, t);
  }

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
  }
  if (record_ != nullptr) record(readings, now);
  totals_.step = step_.fetch_add(1, std::memory_order_release) + 1;
  totals_.t_s = t + dt;
  totals_.pedal = report_.speed;
  totals_.guide_n = report_.guide_n;
  totals_.rpm = report_.speed * p.turbine.max_rpm;
  totals_.removed_mm3 += report_.cut.removed_mm3;
  for (size_t m = 0; m < totals_.removed_by_material_mm3.size(); ++m)
    totals_.removed_by_material_mm3[m] += report_.cut.removed_by_material_mm3[m];
  totals_.voxels_changed += report_.cut.voxels_changed;
  totals_.deferred_cuts += report_.cut.deferred ? 1 : 0;
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
}

void HapticLoop::run() {
  // Wake-ups as close to the deadline as the kernel allows; real-time priority where permitted.
  prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL);
  sched_param sp{};
  sp.sched_priority = 80;
  (void)pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);

  // Held until run() returns; set up before the first step, read by others after stop() joins.
  const IdleLatencyRequest idle(idle_latency_us_);
  idle_latency_note_ = idle.note();
  idle_latency_held_ = idle.held();
  idle_latency_denied_ = idle.denied();

  auto period_ns = [&] { return int64_t(std::llround(1e9 / active_params_->device.rate_hz)); };
  int64_t deadline = steadyNowNs();
  while (!stop_requested_.load(std::memory_order_relaxed)) {
    deadline += period_ns();
    const int64_t t0 = steadyNowNs();
    step();
    const int64_t t1 = steadyNowNs();
    times_.add(t1 - t0);
    counters_.steps.fetch_add(1, std::memory_order_relaxed);
    if (t1 - t0 > counters_.max_step_ns.load(std::memory_order_relaxed))
      counters_.max_step_ns.store(t1 - t0, std::memory_order_relaxed);
    if (t1 > deadline) {
      counters_.missed_deadlines.fetch_add(1, std::memory_order_relaxed);
      // Far behind (a stall): start a new schedule instead of running a burst of catch-up steps.
      if (t1 - deadline > 4 * period_ns()) deadline = t1;
      continue;
    }
    timespec ts{};
    ts.tv_sec = time_t(deadline / 1'000'000'000);
    ts.tv_nsec = long(deadline % 1'000'000'000);
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
  }
}

}  // namespace dentsim
