// The virtual coupling: a pen dropped on stiff enamel never gains energy and comes to rest; without the coupling's limits it would.
#include "sim/tool_proxy.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "sim_fixtures.h"

namespace dentsim {
namespace {

using test::Block;
using test::flatBlock;
using test::sphereBur;

constexpr double kR = 0.5;         // bur radius [mm]
constexpr double kMassKg = 0.05;   // the pen's moving mass [kg]
constexpr double kG = 9810.0;      // gravity [mm/s^2]

struct DropResult {
  double start_energy = 0;   // [N mm]
  double max_energy = 0;     // highest total energy after release [N mm]
  double end_speed = 0;      // pen speed at the end [mm/s]
  double end_drift = 0;      // pen motion over the last 100 ms [mm]
  double min_tip_gap = 1e9;  // lowest proxy tip height above the surface [mm] (negative: inside)
  double rest_force = 0;     // force on the pen at the end [N]
};

// A pen of mass m released from rest with the bur's tip `height` above an enamel block, under
// gravity, for `seconds`. The pen is integrated finely (0.1 ms) with the loop's force held for each
// 1 ms step, as a real device's physics would see a 1 kHz loop.
DropResult drop(const SimParams& params, double height, double seconds) {
  Block b = flatBlock(Material::Enamel);
  VoxelField field(b.volume, b.frame);
  const ToolModel bur = sphereBur(kR, 0.03, {0, 0, kR});  // grip at the sphere's centre
  ToolProxy proxy(bur);
  Vec3 x{0.8, 0.8, b.surface_mm + height + kR};  // the pen's grip point [mm]
  Vec3 v{};
  proxy.reset(Pose{x, Quat{}});
  const double dt = 1.0 / params.device.rate_hz;
  const double k = params.coupling.stiffness_n_per_mm;
  auto energy = [&](const Vec3& pen, const Vec3& vel, const Vec3& tool) {
    const double kinetic = 0.5 * kMassKg * dot(vel, vel) * 1e-3;           // kg mm^2/s^2 -> N mm
    const double potential = kMassKg * 9.81 * (pen.z - b.surface_mm);        // [N mm]
    const Vec3 stretch = tool - pen;
    return kinetic + potential + 0.5 * k * dot(stretch, stretch);
  };
  DropResult out;
  out.start_energy = energy(x, v, proxy.grip().position);
  out.max_energy = out.start_energy;
  const int steps = int(seconds / dt);
  Vec3 drift_from;
  for (int s = 0; s < steps; ++s) {
    PenReading pen;
    pen.grip = Pose{x, Quat{}};
    pen.velocity = v;
    const ProxyStep st = proxy.step(field, params, pen, dt);
    out.min_tip_gap = std::min(out.min_tip_gap, proxy.grip().position.z - kR - b.surface_mm);
    for (int sub = 0; sub < 10; ++sub) {  // semi-implicit Euler, force held
      const Vec3 a = st.display.force * (1000.0 / kMassKg) - Vec3{0, 0, kG};
      v += a * (dt / 10);
      x += v * (dt / 10);
    }
    out.max_energy = std::max(out.max_energy, energy(x, v, proxy.grip().position));
    if (s == steps - 100) drift_from = x;
    out.rest_force = norm(st.display.force);
  }
  out.end_speed = norm(v);
  out.end_drift = norm(x - drift_from);
  return out;
}

TEST(ToolProxy, DropOnStiffEnamelNeverGainsEnergyAndEndsAtRest) {
  const SimParams params = defaultSimParams();
  const DropResult r = drop(params, 0.5, 3.0);
  // Passive: the total never rises above what the pen started with (tolerance: 0.1% of the drop).
  const double drop_energy = kMassKg * 9.81 * 0.5;
  EXPECT_LE(r.max_energy, r.start_energy + 1e-3 * drop_energy);
  // At rest, holding the pen's weight.
  EXPECT_LT(r.end_speed, 0.5);
  EXPECT_LT(r.end_drift, 1e-3);
  EXPECT_NEAR(r.rest_force, kMassKg * 9.81, 0.02 * kMassKg * 9.81);
  // The tool stays on the surface: it sinks only as deep as the weight presses it (~1 voxel), never through.
  EXPECT_GT(r.min_tip_gap, -0.05);
}

TEST(ToolProxy, TheEnergyCheckCatchesAnUnstableCoupling) {
  // A coupling far stiffer than a 1 kHz loop can render with this mass and no damping is the
  // classic sampled-data instability: the same check must see the energy grow.
  SimParams params = defaultSimParams();
  params.coupling.stiffness_n_per_mm = 400.0;
  params.coupling.damping_n_s_per_mm = 0.0;
  params.coupling.proxy_damping_n_s_per_mm = 0.0;
  params.device.max_force_n = 1e6;
  const DropResult r = drop(params, 0.5, 0.5);
  EXPECT_GT(r.max_energy, 2.0 * r.start_energy);
}

TEST(ToolProxy, FreeSpaceProxyFollowsThePenAndClampsTheForce) {
  Block b = flatBlock(Material::Enamel);
  VoxelField field(b.volume, b.frame);
  const ToolModel bur = sphereBur(kR, 0.03, {0, 0, kR});
  SimParams params = defaultSimParams();
  ToolProxy proxy(bur);
  const Vec3 above{0.8, 0.8, b.surface_mm + 1.0 + kR};
  proxy.reset(Pose{above, Quat{}});
  // In free space the proxy reaches a pen that stands still, with no force left.
  PenReading pen;
  pen.grip = Pose{above + Vec3{0.05, 0, 0}, Quat::fromAxisAngle({0, 1, 0}, 0.05)};
  ProxyStep st{};
  for (int i = 0; i < 200; ++i) st = proxy.step(field, params, pen, 1e-3);
  EXPECT_LT(norm(proxy.grip().position - pen.grip.position), 1e-6);
  EXPECT_LT(norm(st.display.force), 1e-6);
  // A pen deep in the tooth: the proxy stays on the surface, the pen feels at most the device's limit.
  pen.grip = Pose{{0.8, 0.8, b.surface_mm - 20.0}, Quat{}};
  for (int i = 0; i < 300; ++i) st = proxy.step(field, params, pen, 1e-3);
  EXPECT_TRUE(st.force_clamped);
  EXPECT_NEAR(norm(st.display.force), params.device.max_force_n, 1e-9);
  EXPECT_GT(st.display.force.z, 0.99 * params.device.max_force_n) << "clamped along its direction";
  EXPECT_GT(proxy.grip().position.z - kR, b.surface_mm - 0.1) << "the proxy does not tunnel";
  EXPECT_EQ(norm(st.display.moment), 0.0) << "a pen without torque output gets none";
}

TEST(ToolProxy, SolveSpd6InvertsAndRefusesIndefinite) {
  Mat6 m{};
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) m[size_t(6 * i + j)] = (i == j ? 10.0 : 0.0) + 1.0 / (1 + i + j);
  const double x_true[6] = {1, -2, 3, -4, 5, -6};
  double b[6] = {}, x[6] = {};
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) b[i] += m[size_t(6 * i + j)] * x_true[j];
  ASSERT_TRUE(solveSpd6(m, b, x));
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(x[i], x_true[i], 1e-12);
  m[0] = -1;
  EXPECT_FALSE(solveSpd6(m, b, x));
}

}  // namespace
}  // namespace dentsim
