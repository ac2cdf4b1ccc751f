// ContactFinder and contactForce: the point-shell intersection set and its spring, damper and friction wrench.
#include "sim/contact.h"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace dentsim {

namespace {

// Gradients flatter than this [1/voxel] give no trustworthy normal: the point is deep in tissue.
constexpr double kMinGradient = 0.3;
// Beyond this field value the point is treated as deep (the ramp across the surface is saturating).
constexpr double kShallowPhi = 0.45;
constexpr double kMarchStep = 1.5;  // [voxel]
// Clearances are stored in floats: shrunk by more than their rounding in a 2048-voxel grid.
constexpr double kClearanceMargin = 2e-3;  // [voxel]
// Looking around a point for a longer clearance costs up to ~100 ns; a step does it for at most
// this many points (a bur arriving from free space), the rest get the short bound and come back.
constexpr uint32_t kLookAroundsPerStep = 512;

void addOuter(Mat6& m, const double* j, double w) {
  for (int r = 0; r < 6; ++r) {
    const double jr = w * j[r];
    for (int c = 0; c < 6; ++c) m[size_t(6 * r + c)] += jr * j[c];
  }
}

// Two unit vectors completing n to an orthonormal basis.
void tangents(const Vec3& n, Vec3* t1, Vec3* t2) {
  const Vec3 a = std::abs(n.x) < 0.6 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  *t1 = normalized(cross(n, a));
  *t2 = cross(n, *t1);
}

}  // namespace

ContactFinder::ContactFinder(size_t max_points, double max_march_voxels)
    : clearance_(max_points), max_march_voxels_(max_march_voxels) {
  contacts_.reserve(max_points);
}

void ContactFinder::forgetClearances() {
  for (Clearance& c : clearance_) c.r2 = -1;
}

bool ContactFinder::resolve(VoxelField& field, const Vec3& u, const Vec3& inward, const FieldSample& s0,
                            ContactPoint* out) const {
  const double g0 = norm(s0.gradient);
  if (s0.phi < kShallowPhi && g0 > kMinGradient) {
    // Near the surface the field is linear across it: distance = phi / |grad|.
    out->normal = -s0.gradient / g0;
    out->depth_mm = s0.phi / g0 * field.voxelMm();
    return true;
  }
  // Deep: march along the inward normal, the way out of the tissue the tool came in by.
  double t_in = 0.0, t_out = -1.0, phi_in = s0.phi, phi_out = 0.0;
  for (double t = kMarchStep; t <= max_march_voxels_ + 1e-9; t += kMarchStep) {
    const double phi = field.sample(u + inward * t).phi;
    if (phi <= 0) {
      t_out = t;
      phi_out = phi;
      break;
    }
    t_in = t;
    phi_in = phi;
  }
  if (t_out < 0) {
    // Deeper than the march reaches: push along the inward normal with the largest depth we resolve.
    out->normal = inward;
    out->depth_mm = max_march_voxels_ * field.voxelMm();
    return true;
  }
  // The surface lies where the field crosses zero between the last two samples: interpolate it,
  // and the sample there corrects what the interpolation misses (its residual phi / |grad|).
  const double t_exit = t_in + (t_out - t_in) * phi_in / (phi_in - phi_out);
  const FieldSample exit = field.sample(u + inward * t_exit, true);
  const double ge = norm(exit.gradient);
  Vec3 n = ge > 1e-9 ? -exit.gradient / ge : inward;
  double along = dot(inward, n);
  if (along < 0.2) {  // a grazing or odd exit: trust the march direction instead
    n = inward;
    along = 1.0;
  }
  out->normal = n;
  // Distance from the point to the tangent plane at the exit, plus the small field residual there.
  out->depth_mm = (t_exit * along + (ge > kMinGradient ? exit.phi / ge : 0.0)) * field.voxelMm();
  return out->depth_mm > 0;
}

std::span<const ContactPoint> ContactFinder::find(VoxelField& field, const PointShell& shell, const Pose& tool_pose,
                                                  ContactStats* stats) {
  assert(shell.size() <= contacts_.capacity() && shell.size() <= clearance_.size());
  if (&shell != clearance_shell_ || &field != clearance_field_) {
    forgetClearances();
    clearance_shell_ = &shell;
    clearance_field_ = &field;
  }
  contacts_.clear();
  ContactStats st;
  uint32_t looks = 0;
  // Tool frame straight to voxel coordinates: u = (R q) / voxel + origin's voxel coordinate.
  const double inv_voxel = 1.0 / field.voxelMm();
  std::array<double, 9> m = tool_pose.rotation.matrix();
  for (double& e : m) e *= inv_voxel;
  const Vec3 t = field.toVoxel(tool_pose.position);
  auto toVoxel = [&](const Vec3& q) {
    return Vec3{m[0] * q.x + m[1] * q.y + m[2] * q.z + t.x, m[3] * q.x + m[4] * q.y + m[5] * q.z + t.y,
                m[6] * q.x + m[7] * q.y + m[8] * q.z + t.z};
  };
  for (const ShellCluster& cluster : shell.clusters) {
    // Whole cluster in empty chunks: nothing to test.
    const Vec3 c = toVoxel(cluster.centre);
    const double r = cluster.radius * inv_voxel + 1.0;
    if (field.chunksEmpty(c - Vec3{r, r, r}, c + Vec3{r, r, r})) {
      ++st.clusters_skipped;
      continue;
    }
    ++st.clusters_tested;
    for (uint32_t i = cluster.first; i < cluster.first + cluster.count; ++i) {
      const Vec3 u = toVoxel(shell.positions[i]);
      Clearance& cl = clearance_[i];
      const double dx = u.x - double(cl.x), dy = u.y - double(cl.y), dz = u.z - double(cl.z);
      if (dx * dx + dy * dy + dz * dz < double(cl.r2)) {
        ++st.points_clear;
        continue;
      }
      ++st.points_tested;
      const double phi = field.phi(u);
      if (phi <= 0) {
        const bool look = looks < kLookAroundsPerStep;
        looks += look ? 1 : 0;
        const double reach = field.clearance(u, phi, look) - kClearanceMargin;
        cl = {float(u.x), float(u.y), float(u.z), reach > 0 ? float(reach * reach) : -1.0f};
        continue;
      }
      cl.r2 = -1;
      const FieldSample s = field.sample(u);
      ContactPoint cp;
      cp.point = i;
      cp.position = field.toMm(u);
      cp.area_mm2 = shell.area_mm2[i];
      cp.material = s.material;
      cp.cutting = shell.cutting[i] != 0;
      if (!resolve(field, u, tool_pose.applyDirection(shell.inward[i]), s, &cp)) continue;
      contacts_.push_back(cp);
    }
  }
  st.contacts = uint32_t(contacts_.size());
  if (stats) *stats = st;
  return contacts_;
}

ContactForce contactForce(std::span<const ContactPoint> contacts, const SimParams& params, const ToolMotion& motion,
                          double friction_slip_mm_s) {
  ContactForce out;
  for (const ContactPoint& cp : contacts) {
    const TissueParams& tissue = params.tissue(cp.material);
    const Vec3 r = cp.position - motion.reference;
    const Vec3 v = motion.linear + cross(motion.angular, r);
    const Vec3& n = cp.normal;
    // Hunt-Crossley: spring k a d, scaled by (1 + damping * rate into the tissue); never pulls.
    const double rate_in = -dot(v, n);
    const double spring = tissue.stiffness_n_per_mm3 * cp.area_mm2 * cp.depth_mm;
    const double scale = std::max(0.0, 1.0 + tissue.damping_s_per_mm * rate_in);
    const double fn = spring * scale;
    Vec3 f = n * fn;
    out.spring_force_n += spring;
    out.normal_force_n += fn;
    out.impact_speed_mm_s = std::max(out.impact_speed_mm_s, rate_in);

    // Friction against the sliding of the point over the surface, viscous below the slip speed.
    const Vec3 vt = v - n * dot(v, n);
    const double slip = std::max(norm(vt), friction_slip_mm_s);
    const double c = tissue.friction * fn / slip;  // [N s/mm]
    f -= vt * c;

    out.wrench.force += f;
    out.wrench.moment += cross(r, f);

    // Linearizations for the implicit proxy step.
    const Vec3 rn = cross(r, n);
    const double jn[6] = {n.x, n.y, n.z, rn.x, rn.y, rn.z};
    addOuter(out.stiffness, jn, tissue.stiffness_n_per_mm3 * cp.area_mm2 * scale);
    if (c > 0) {
      Vec3 t1, t2;
      tangents(n, &t1, &t2);
      for (const Vec3& t : {t1, t2}) {
        const Vec3 rt = cross(r, t);
        const double jt[6] = {t.x, t.y, t.z, rt.x, rt.y, rt.z};
        addOuter(out.friction_damping, jt, c);
      }
    }
  }
  return out;
}

}  // namespace dentsim
