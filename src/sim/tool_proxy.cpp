// ToolProxy: one implicit step of the 6-DOF virtual coupling against the contact set.
#include "sim/tool_proxy.h"

#include <array>
#include <cmath>

namespace dentsim {

bool solveSpd6(const Mat6& m, const double* b, double* x) {
  double l[36] = {};
  for (int i = 0; i < 6; ++i) {
    for (int j = 0; j <= i; ++j) {
      double s = m[size_t(6 * i + j)];
      for (int k = 0; k < j; ++k) s -= l[6 * i + k] * l[6 * j + k];
      if (i == j) {
        if (!(s > 0)) return false;
        l[6 * i + i] = std::sqrt(s);
      } else {
        l[6 * i + j] = s / l[6 * j + j];
      }
    }
  }
  double y[6];
  for (int i = 0; i < 6; ++i) {
    double s = b[i];
    for (int k = 0; k < i; ++k) s -= l[6 * i + k] * y[k];
    y[i] = s / l[6 * i + i];
  }
  for (int i = 5; i >= 0; --i) {
    double s = y[i];
    for (int k = i + 1; k < 6; ++k) s -= l[6 * k + i] * x[k];
    x[i] = s / l[6 * i + i];
  }
  return true;
}

bool clampLength(Vec3* v, double max_len) {
  const double n = norm(*v);
  if (!(n > max_len)) return false;
  *v *= max_len / n;
  return true;
}

ToolProxy::ToolProxy(const ToolModel& tool) : tool_(tool), finder_(tool.shell.size()) {
  for (const Vec3& q : tool.shell.positions) reach_mm_ = std::max(reach_mm_, norm(q - tool.grip_local));
}

void ToolProxy::reset(const Pose& grip) {
  grip_ = grip;
  finder_.forgetClearances();  // a new start: the tissue may have changed since the last
  velocity_ = {};
  angular_velocity_ = {};
}

ProxyStep ToolProxy::step(VoxelField& field, const SimParams& params, const PenReading& pen, double dt,
                          const ContactBudget* budget) {
  const CouplingParams& k = params.coupling;
  ProxyStep out;

  // Contact at the proxy's current pose, with its last velocity for damping and friction.
  out.contacts = finder_.find(field, tool_.shell, toolPose(), &out.stats, budget);
  out.detail = contactForce(out.contacts, params, ToolMotion{grip_.position, velocity_, angular_velocity_});
  out.contact = out.detail.wrench;

  // Residual of the balance at the new pose, linearized: H delta = r.
  const Vec3 rot_error = (pen.grip.rotation * grip_.rotation.conjugate()).rotationVector();
  const Vec3 f = (pen.grip.position - grip_.position) * k.stiffness_n_per_mm + pen.velocity * k.damping_n_s_per_mm +
                 out.detail.wrench.force;
  const Vec3 t = rot_error * k.rot_stiffness_n_mm_per_rad + pen.angular_velocity * k.rot_damping_n_mm_s_per_rad +
                 out.detail.wrench.moment;
  double r[6] = {f.x, f.y, f.z, t.x, t.y, t.z};
  Mat6 h = out.detail.stiffness;
  // Friction, implicit in the velocity: F(v_new) ~ F(v_old) - C (v_new - v_old), v_new = delta / dt.
  const double v_old[6] = {velocity_.x, velocity_.y, velocity_.z,
                           angular_velocity_.x, angular_velocity_.y, angular_velocity_.z};
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const double c = out.detail.friction_damping[size_t(6 * i + j)];
      h[size_t(6 * i + j)] += c / dt;
      r[i] += c * v_old[j];
    }
  const double lin = k.stiffness_n_per_mm + (k.damping_n_s_per_mm + k.proxy_damping_n_s_per_mm) / dt;
  const double ang = k.rot_stiffness_n_mm_per_rad + k.rot_damping_n_mm_s_per_rad / dt;
  for (int i = 0; i < 3; ++i) {
    h[size_t(7 * i)] += lin;
    h[size_t(7 * (i + 3))] += ang;
  }
  double delta[6] = {};
  if (!solveSpd6(h, r, delta)) {
    // Cannot happen with positive coupling gains; fall back to the diagonal rather than stall.
    for (int i = 0; i < 6; ++i) delta[i] = r[i] / h[size_t(7 * i)];
  }
  Vec3 dp{delta[0], delta[1], delta[2]};
  Vec3 dtheta{delta[3], delta[4], delta[5]};
  // The proxy never outruns collision detection: a bounded step cannot skip through tissue.
  clampLength(&dp, k.max_proxy_speed_mm_per_s * dt);
  clampLength(&dtheta, 10.0 * dt);  // 10 rad/s
  if (!finite(dp) || !finite(dtheta)) {
    dp = {};
    dtheta = {};
  }
  // A pass the budget cut short moves the proxy at most half a voxel (any shell point): the clusters
  // it did not reach may hold new contact (the leading edge of a sliding bur), and a longer move
  // without their springs would sink into tissue that the next, whole pass pushes back out of, a
  // bounce the hand would feel. Half a voxel stays within the field's linear ramp, where a missed
  // point's depth is small; the proxy still follows a hand moving 10 mm/s at level 10.
  if (out.stats.clusters_left > 0) {
    const double limit = kShortPassVoxels * field.voxelMm();
    const double move = norm(dp) + norm(dtheta) * reach_mm_;
    if (move > limit) {
      dp = dp * (limit / move);
      dtheta = dtheta * (limit / move);
      out.held = true;
    }
  }
  // The swept check: a move long enough to step over a thin wall is followed through sub-poses,
  // and ends at the first where a point not already in contact is in tissue. What starts it is the
  // grip's own travel, the way a fast bur goes through a wall; a turn alone sweeps the long shank
  // through far more voxels than any point of the head moves, and the springs of the next step
  // already stop a neck that turns into a wall (a sweep there held the scripted professional's
  // tilts back and changed its cavity on the micro-CT molar).
  const double travel = norm(dp) + norm(dtheta) * reach_mm_;
  const double sub_mm = kSweepVoxels * field.voxelMm();
  if (norm(dp) > sub_mm) {
    const uint32_t n = std::min<uint32_t>(kMaxSweepPoses, uint32_t(std::ceil(travel / sub_mm)));
    std::array<Pose, kMaxSweepPoses> poses;
    for (uint32_t j = 0; j < n; ++j) {
      const double along = double(j + 1) / double(n);
      const Quat rot = (Quat::fromRotationVector(dtheta * along) * grip_.rotation).normalized();
      poses[j] = {grip_.position + dp * along - rot.rotate(tool_.grip_local), rot};
    }
    // Not under the step's deadline: what the sweep took must not depend on the clock, or a replay
    // would move the proxy elsewhere. Its cost is bounded by the sub-poses (a fast move near tissue).
    out.sweep_poses = n;
    out.sweep_taken = finder_.sweep(field, tool_.shell, std::span<const Pose>(poses.data(), n));
    if (out.sweep_taken < n) {
      const double kept = double(out.sweep_taken) / double(n);
      dp = dp * kept;
      dtheta = dtheta * kept;
    }
  }
  grip_.position += dp;
  grip_.rotation = (Quat::fromRotationVector(dtheta) * grip_.rotation).normalized();
  velocity_ = dp / dt;
  angular_velocity_ = dtheta / dt;

  // The pen feels the coupling: pulled toward the proxy.
  const Vec3 back_rot = (grip_.rotation * pen.grip.rotation.conjugate()).rotationVector();
  out.coupling.force = (grip_.position - pen.grip.position) * k.stiffness_n_per_mm +
                       (velocity_ - pen.velocity) * k.damping_n_s_per_mm;
  out.coupling.moment = back_rot * k.rot_stiffness_n_mm_per_rad +
                        (angular_velocity_ - pen.angular_velocity) * k.rot_damping_n_mm_s_per_rad;
  out.display = out.coupling;
  out.force_clamped = clampLength(&out.display.force, params.device.max_force_n);
  clampLength(&out.display.moment, params.device.max_torque_n_mm);
  if (!finite(out.display.force) || !finite(out.display.moment)) out.display = {};
  return out;
}

}  // namespace dentsim
