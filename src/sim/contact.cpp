// ContactFinder and contactForce: the point-shell intersection set and its spring, damper and friction wrench.
#include "sim/contact.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>

#include "core/steady_clock.h"

namespace dentsim {

namespace {

// Gradients flatter than this [1/voxel] give no trustworthy normal: the point is deep in tissue.
constexpr double kMinGradient = 0.3;
// Beyond this field value the point is treated as deep (the ramp across the surface is saturating).
constexpr double kShallowPhi = 0.45;
constexpr double kMarchStep = 1.5;  // [voxel]
// Clearances are stored, tested and worked out from a field sampled in floats: shrunk by more than
// their rounding (below 1e-3 voxel for a tool within 2048 voxels of the origin).
constexpr double kClearanceMargin = 3e-3;  // [voxel]
// The clearance test runs on four points at once; the arrays are padded so that a group may read
// past the last point.
using Float4 = float __attribute__((vector_size(16)));
using Int4 = int32_t __attribute__((vector_size(16)));
constexpr size_t kLanes = 4;
Float4 load4(const float* p) {
  Float4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
// Looking around a point for a longer clearance costs up to ~100 ns; a step does it for at most
// this many points (a bur arriving from free space), the rest get the short bound and come back.
constexpr uint32_t kLookAroundsPerStep = 512;

// The upper triangle of a symmetric 6x6 matrix, row by row: contacts add to 21 entries, not 36.
using Sym6 = std::array<double, 21>;

void addOuter(Sym6& m, const double* j, double w) {
  size_t k = 0;
  for (int r = 0; r < 6; ++r) {
    const double jr = w * j[r];
    for (int c = r; c < 6; ++c) m[k++] += jr * j[c];
  }
}

void addSymmetric(Mat6& out, const Sym6& m, double sign) {
  size_t k = 0;
  for (int r = 0; r < 6; ++r)
    for (int c = r; c < 6; ++c, ++k) {
      out[size_t(6 * r + c)] += sign * m[k];
      if (c != r) out[size_t(6 * c + r)] += sign * m[k];
    }
}

}  // namespace

ContactFinder::ContactFinder(size_t max_points, double max_march_voxels)
    : clear_x_(max_points + kLanes),
      clear_y_(max_points + kLanes),
      clear_z_(max_points + kLanes),
      clear_r2_(max_points + kLanes, -1.0f),
      shell_x_(max_points + kLanes),
      shell_y_(max_points + kLanes),
      shell_z_(max_points + kLanes),
      due_(max_points),
      due_x_(max_points + kLanes),
      due_y_(max_points + kLanes),
      due_z_(max_points + kLanes),
      due_phi_(max_points + kLanes),
      in_contact_(max_points, 0),
      queued_(max_points, 0),
      max_march_voxels_(max_march_voxels) {
  contacts_.reserve(max_points);
  last_contacts_.reserve(max_points);
  order_.reserve(max_points);
  left_.reserve(max_points);
}

void ContactFinder::forgetClearances() {
  std::fill(clear_r2_.begin(), clear_r2_.end(), -1.0f);
  last_contacts_.clear();
  left_.clear();
}

void ContactFinder::adoptShell(const PointShell& shell) {
  for (size_t i = 0; i < shell.size(); ++i) {
    shell_x_[i] = float(shell.positions[i].x);
    shell_y_[i] = float(shell.positions[i].y);
    shell_z_[i] = float(shell.positions[i].z);
  }
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

struct ContactFinder::Placement {
  std::array<double, 9> rot;  // tool frame to simulation frame
  std::array<double, 9> m;    // the same over the voxel edge: tool frame [mm] to voxel coordinates
  Vec3 t;                     // the tool frame's origin in voxel coordinates
  std::array<Float4, 9> mf;
  Float4 tx, ty, tz;
  double inv_voxel = 0.0;
  Vec3 toVoxel(const Vec3& q) const {
    return Vec3{m[0] * q.x + m[1] * q.y + m[2] * q.z + t.x, m[3] * q.x + m[4] * q.y + m[5] * q.z + t.y,
                m[6] * q.x + m[7] * q.y + m[8] * q.z + t.z};
  }
  // Whole cluster in empty chunks: nothing to test.
  bool clear(const VoxelField& field, const ShellCluster& cluster) const {
    const Vec3 c = toVoxel(cluster.centre);
    const double r = cluster.radius * inv_voxel + 1.0;
    return field.chunksEmpty(c - Vec3{r, r, r}, c + Vec3{r, r, r});
  }
};

void ContactFinder::testCluster(VoxelField& field, const PointShell& shell, const ShellCluster& cluster,
                                const Placement& at, uint32_t* looks, ContactStats* st) {
  ++st->clusters_tested;
  // Four points at a time: which have left their clearance since they were last sampled.
  uint32_t n = 0;
  const uint32_t end = cluster.first + cluster.count;
  for (uint32_t i = cluster.first; i < end; i += kLanes) {
    const Float4 qx = load4(&shell_x_[i]), qy = load4(&shell_y_[i]), qz = load4(&shell_z_[i]);
    const Float4 ux = at.mf[0] * qx + at.mf[1] * qy + at.mf[2] * qz + at.tx;
    const Float4 uy = at.mf[3] * qx + at.mf[4] * qy + at.mf[5] * qz + at.ty;
    const Float4 uz = at.mf[6] * qx + at.mf[7] * qy + at.mf[8] * qz + at.tz;
    const Float4 dx = ux - load4(&clear_x_[i]), dy = uy - load4(&clear_y_[i]), dz = uz - load4(&clear_z_[i]);
    const Int4 left = dx * dx + dy * dy + dz * dz >= load4(&clear_r2_[i]);  // -1: sample it
    if ((left[0] | left[1] | left[2] | left[3]) == 0) continue;  // most groups, once the tool settles
    const uint32_t lanes = std::min<uint32_t>(kLanes, end - i);
    for (uint32_t k = 0; k < lanes; ++k) {
      due_[n] = i + k;
      due_x_[n] = ux[k], due_y_[n] = uy[k], due_z_[n] = uz[k];
      n += uint32_t(left[k] & 1);
    }
  }
  st->points_clear += cluster.count - n;
  st->points_tested += n;
  // The field at those points, four at a time in floats; a point it puts inside tissue is sampled
  // again exactly, in doubles, for its depth and normal.
  field.phiBatch(due_x_.data(), due_y_.data(), due_z_.data(), n, due_phi_.data());

  const std::array<double, 9>& rot = at.rot;
  for (uint32_t j = 0; j < n; ++j) {
    const uint32_t i = due_[j];
    const double phi = due_phi_[j];
    if (phi <= 0) {
      const Vec3 u{due_x_[j], due_y_[j], due_z_[j]};
      const bool look = *looks < kLookAroundsPerStep;
      *looks += look ? 1 : 0;
      const double reach = field.clearance(u, phi, look) - kClearanceMargin;
      clear_x_[i] = due_x_[j], clear_y_[i] = due_y_[j], clear_z_[i] = due_z_[j];
      clear_r2_[i] = reach > 0 ? float(reach * reach) : -1.0f;
      continue;
    }
    clear_r2_[i] = -1.0f;
    // From the float copy of the shell (to 1e-6 mm), whose cache lines the clearance test read.
    const Vec3 u = at.toVoxel(Vec3{shell_x_[i], shell_y_[i], shell_z_[i]});
    const FieldSample s = field.sample(u);
    if (s.phi <= 0) continue;  // on the surface, to float rounding: sampled again next step
    const Vec3& q = shell.inward[i];
    const Vec3 inward{rot[0] * q.x + rot[1] * q.y + rot[2] * q.z, rot[3] * q.x + rot[4] * q.y + rot[5] * q.z,
                      rot[6] * q.x + rot[7] * q.y + rot[8] * q.z};
    ContactPoint cp;
    cp.point = i;
    cp.position = field.toMm(u);
    cp.area_mm2 = shell.area_mm2[i];
    cp.material = s.material;
    cp.cutting = shell.cutting[i] != 0;
    if (!resolve(field, u, inward, s, &cp)) continue;
    contacts_.push_back(cp);
  }
}

void ContactFinder::orderClusters(const PointShell& shell) {
  ++pass_;
  order_.clear();
  auto put = [&](uint32_t c) {
    if (queued_[c] == pass_) return;
    queued_[c] = pass_;
    order_.push_back(c);
  };
  for (uint32_t c : left_) put(c);
  // The last contacts are by point and the clusters partition the points in order: one walk.
  const uint32_t n = uint32_t(shell.clusters.size());
  uint32_t c = 0;
  for (const ContactPoint& cp : last_contacts_) {
    while (c < n && cp.point >= shell.clusters[c].first + shell.clusters[c].count) ++c;
    if (c < n) put(c);
  }
  for (c = 0; c < n; ++c) put(c);
}

std::span<const ContactPoint> ContactFinder::find(VoxelField& field, const PointShell& shell, const Pose& tool_pose,
                                                  ContactStats* stats, const ContactBudget* budget) {
  assert(shell.size() <= contacts_.capacity() && shell.size() <= due_.size());
  if (&shell != clearance_shell_ || &field != clearance_field_) {
    forgetClearances();
    adoptShell(shell);
    clearance_shell_ = &shell;
    clearance_field_ = &field;
  }
  contacts_.clear();
  ContactStats st;
  uint32_t looks = 0;
  // Tool frame straight to voxel coordinates: u = (R q) / voxel + origin's voxel coordinate.
  Placement at;
  at.inv_voxel = 1.0 / field.voxelMm();
  at.rot = tool_pose.rotation.matrix();
  at.m = at.rot;
  for (double& e : at.m) e *= at.inv_voxel;
  at.t = field.toVoxel(tool_pose.position);
  for (size_t k = 0; k < 9; ++k) at.mf[k] = Float4{} + float(at.m[k]);
  at.tx = Float4{} + float(at.t.x), at.ty = Float4{} + float(at.t.y), at.tz = Float4{} + float(at.t.z);

  const uint32_t n = uint32_t(shell.clusters.size());
  if (budget == nullptr) {
    for (const ShellCluster& cluster : shell.clusters) {
      if (at.clear(field, cluster)) {
        ++st.clusters_skipped;
        continue;
      }
      testCluster(field, shell, cluster, at, &looks, &st);
    }
    st.clusters_reached = n;
    left_.clear();
  } else {
    orderClusters(shell);
    const bool prescribed = budget->clusters != ContactBudget::kAll;
    uint32_t k = 0;
    for (; k < n; ++k) {
      if (prescribed && k >= budget->clusters) break;
      const ShellCluster& cluster = shell.clusters[order_[k]];
      if (at.clear(field, cluster)) {
        ++st.clusters_skipped;
        continue;
      }
      // The clock is read only before a cluster that costs something, and a pass tests at least one:
      // a step that starts past its deadline (a stall) still makes progress through the shell.
      if (!prescribed && st.clusters_tested > 0 &&
          ((budget->max_points != 0 && st.points_tested >= budget->max_points) ||
           (budget->deadline_ns != 0 && steadyNowNs() >= budget->deadline_ns)))
        break;
      testCluster(field, shell, cluster, at, &looks, &st);
    }
    st.clusters_reached = k;
    // The clusters not reached keep the last pass's contacts, and come first next time.
    left_.assign(order_.begin() + k, order_.end());
    for (uint32_t c : left_) {
      const ShellCluster& cluster = shell.clusters[c];
      st.points_left += cluster.count;
      auto first = std::lower_bound(last_contacts_.begin(), last_contacts_.end(), cluster.first,
                                    [](const ContactPoint& cp, uint32_t p) { return cp.point < p; });
      for (; first != last_contacts_.end() && first->point < cluster.first + cluster.count; ++first) {
        // Carried to where the point is now, its depth moved with it across the tangent plane it
        // was found under (VPS's local model); one that has left that plane is dropped.
        ContactPoint cp = *first;
        const Vec3 now = field.toMm(at.toVoxel(Vec3{shell_x_[cp.point], shell_y_[cp.point], shell_z_[cp.point]}));
        cp.depth_mm -= dot(now - cp.position, cp.normal);
        cp.position = now;
        if (cp.depth_mm <= 0) continue;
        contacts_.push_back(cp);
        ++st.contacts_carried;
      }
    }
    st.clusters_left = uint32_t(left_.size());
    std::sort(contacts_.begin(), contacts_.end(),
              [](const ContactPoint& a, const ContactPoint& b) { return a.point < b.point; });
  }
  last_contacts_.assign(contacts_.begin(), contacts_.end());
  st.contacts = uint32_t(contacts_.size());
  if (stats) *stats = st;
  return contacts_;
}

uint32_t ContactFinder::sweep(VoxelField& field, const PointShell& shell, std::span<const Pose> poses) {
  for (const ContactPoint& cp : contacts_) in_contact_[cp.point] = 1;
  uint32_t taken = 0;
  const double inv_voxel = 1.0 / field.voxelMm();
  for (const Pose& pose : poses) {
    Placement at;
    at.inv_voxel = inv_voxel;
    at.rot = pose.rotation.matrix();
    at.m = at.rot;
    for (double& e : at.m) e *= inv_voxel;
    at.t = field.toVoxel(pose.position);
    bool deep = false;
    for (const ShellCluster& cluster : shell.clusters) {
      if (at.clear(field, cluster)) continue;
      uint32_t n = 0;
      for (uint32_t i = cluster.first; i < cluster.first + cluster.count; ++i) {
        if (in_contact_[i] != 0) continue;
        const Vec3 u = at.toVoxel(Vec3{shell_x_[i], shell_y_[i], shell_z_[i]});
        due_x_[n] = float(u.x), due_y_[n] = float(u.y), due_z_[n] = float(u.z);
        ++n;
      }
      field.phiBatch(due_x_.data(), due_y_.data(), due_z_.data(), n, due_phi_.data());
      for (uint32_t j = 0; j < n && !deep; ++j) deep = due_phi_[j] >= kShallowPhi;
      if (deep) break;
    }
    ++taken;
    if (deep) break;
  }
  for (const ContactPoint& cp : contacts_) in_contact_[cp.point] = 0;
  return taken;
}

ContactForce contactForce(std::span<const ContactPoint> contacts, const SimParams& params, const ToolMotion& motion,
                          double friction_slip_mm_s) {
  ContactForce out;
  // Friction damps the tangential velocity of each point: its block is c J_t J_t^T summed over two
  // tangents, J_t = [t; r x t] = A t with A = [I; [r]x]. Since t1 t1^T + t2 t2^T = I - n n^T, that is
  // c A A^T - c J_n J_n^T, and A A^T = [[I, -[r]x], [[r]x, |r|^2 I - r r^T]] needs only the sums of
  // c, c r and c r r^T: no tangents per point.
  Sym6 springs{}, normal_friction{};
  double c_sum = 0;
  Vec3 cr_sum;
  double crr[6] = {};  // xx, xy, xz, yy, yz, zz
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
    addOuter(springs, jn, tissue.stiffness_n_per_mm3 * cp.area_mm2 * scale);
    if (c > 0) {
      addOuter(normal_friction, jn, c);
      c_sum += c;
      cr_sum += r * c;
      crr[0] += c * r.x * r.x, crr[1] += c * r.x * r.y, crr[2] += c * r.x * r.z;
      crr[3] += c * r.y * r.y, crr[4] += c * r.y * r.z, crr[5] += c * r.z * r.z;
    }
  }
  addSymmetric(out.stiffness, springs, 1.0);
  // c A A^T summed, then less its normal part.
  Mat6& fd = out.friction_damping;
  const double trace = crr[0] + crr[3] + crr[5];
  const double rr[3][3] = {{crr[0], crr[1], crr[2]}, {crr[1], crr[3], crr[4]}, {crr[2], crr[4], crr[5]}};
  const double s[3] = {cr_sum.x, cr_sum.y, cr_sum.z};
  const double skew[3][3] = {{0, -s[2], s[1]}, {s[2], 0, -s[0]}, {-s[1], s[0], 0}};  // [sum c r]x
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      fd[size_t(6 * i + j)] = i == j ? c_sum : 0.0;
      fd[size_t(6 * i + j + 3)] = -skew[i][j];
      fd[size_t(6 * (i + 3) + j)] = skew[i][j];
      fd[size_t(6 * (i + 3) + j + 3)] = (i == j ? trace : 0.0) - rr[i][j];
    }
  addSymmetric(fd, normal_friction, -1.0);
  return out;
}

}  // namespace dentsim
