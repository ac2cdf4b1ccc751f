// Rigid-body math for the tools: 3-vectors, unit quaternions and poses, in double precision, header-only.
//
// Units are the caller's (the simulation uses mm, s, N). A Pose maps a tool's own frame into the
// simulation frame: world = position + rotation * local.
#pragma once

#include <array>
#include <cmath>

namespace dentsim {

struct Vec3 {
  double x = 0, y = 0, z = 0;

  constexpr Vec3() = default;
  constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}

  constexpr double operator[](int a) const { return a == 0 ? x : (a == 1 ? y : z); }
  constexpr double& operator[](int a) { return a == 0 ? x : (a == 1 ? y : z); }
  constexpr Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
  constexpr Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
  constexpr Vec3 operator-() const { return {-x, -y, -z}; }
  constexpr Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
  constexpr Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
  constexpr Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
  constexpr Vec3& operator-=(const Vec3& o) { x -= o.x; y -= o.y; z -= o.z; return *this; }
  constexpr Vec3& operator*=(double s) { x *= s; y *= s; z *= s; return *this; }
  constexpr bool operator==(const Vec3&) const = default;
};

constexpr Vec3 operator*(double s, const Vec3& v) { return v * s; }
constexpr double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& v) { return std::sqrt(dot(v, v)); }
// v / |v|, or the zero vector when |v| is zero.
inline Vec3 normalized(const Vec3& v) {
  const double n = norm(v);
  return n > 0 ? v / n : Vec3{};
}
inline bool finite(const Vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// A unit quaternion w + xi + yj + zk; the identity by default.
struct Quat {
  double w = 1, x = 0, y = 0, z = 0;

  constexpr Quat operator*(const Quat& o) const {
    return {w * o.w - x * o.x - y * o.y - z * o.z, w * o.x + x * o.w + y * o.z - z * o.y,
            w * o.y - x * o.z + y * o.w + z * o.x, w * o.z + x * o.y - y * o.x + z * o.w};
  }
  constexpr Quat conjugate() const { return {w, -x, -y, -z}; }
  constexpr bool operator==(const Quat&) const = default;

  // Rotates v (q v q*), expanded so that it costs two cross products.
  constexpr Vec3 rotate(const Vec3& v) const {
    const Vec3 u{x, y, z};
    const Vec3 t = 2.0 * cross(u, v);
    return v + w * t + cross(u, t);
  }
  // The same rotation as a row-major 3x3 matrix, for rotating many vectors by one quaternion.
  constexpr std::array<double, 9> matrix() const {
    return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
            2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
            2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
  }
  Quat normalized() const {
    const double n = std::sqrt(w * w + x * x + y * y + z * z);
    return n > 0 ? Quat{w / n, x / n, y / n, z / n} : Quat{};
  }
  bool finite() const { return std::isfinite(w) && std::isfinite(x) && std::isfinite(y) && std::isfinite(z); }

  // Rotation by |r| radians about r's direction (the exponential map).
  static Quat fromRotationVector(const Vec3& r) {
    const double angle = norm(r);
    if (angle < 1e-12) return Quat{1, 0.5 * r.x, 0.5 * r.y, 0.5 * r.z}.normalized();
    const double s = std::sin(0.5 * angle) / angle;
    return {std::cos(0.5 * angle), r.x * s, r.y * s, r.z * s};
  }
  static Quat fromAxisAngle(const Vec3& axis, double radians) {
    return fromRotationVector(::dentsim::normalized(axis) * radians);
  }
  // The rotation of a row-major 3x3 rotation matrix (matrix()'s inverse). Shepperd's method: the
  // largest of the trace and the diagonal is the divisor, which keeps the root well conditioned
  // for any rotation.
  static Quat fromMatrix(const std::array<double, 9>& m) {
    const double trace = m[0] + m[4] + m[8];
    Quat q;
    if (trace > 0) {
      const double s = 2.0 * std::sqrt(1.0 + trace);
      q = {0.25 * s, (m[7] - m[5]) / s, (m[2] - m[6]) / s, (m[3] - m[1]) / s};
    } else if (m[0] > m[4] && m[0] > m[8]) {
      const double s = 2.0 * std::sqrt(1.0 + m[0] - m[4] - m[8]);
      q = {(m[7] - m[5]) / s, 0.25 * s, (m[1] + m[3]) / s, (m[2] + m[6]) / s};
    } else if (m[4] > m[8]) {
      const double s = 2.0 * std::sqrt(1.0 + m[4] - m[0] - m[8]);
      q = {(m[2] - m[6]) / s, (m[1] + m[3]) / s, 0.25 * s, (m[5] + m[7]) / s};
    } else {
      const double s = 2.0 * std::sqrt(1.0 + m[8] - m[0] - m[4]);
      q = {(m[3] - m[1]) / s, (m[2] + m[6]) / s, (m[5] + m[7]) / s, 0.25 * s};
    }
    return q.normalized();
  }
  // The rotation whose columns are the unit, right-handed axes x, y, z.
  static Quat fromAxes(const Vec3& x, const Vec3& y, const Vec3& z) {
    return fromMatrix({x.x, y.x, z.x, x.y, y.y, z.y, x.z, y.z, z.z});
  }
  // The rotation vector of this rotation, angle in [0, pi] (the logarithm map).
  Vec3 rotationVector() const {
    const Quat q = w < 0 ? Quat{-w, -x, -y, -z} : *this;
    const double s = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
    if (s < 1e-12) return {2 * q.x, 2 * q.y, 2 * q.z};
    const double angle = 2 * std::atan2(s, q.w);
    return Vec3{q.x, q.y, q.z} * (angle / s);
  }
};

// Spherical interpolation between unit quaternions, t in [0,1], along the shorter arc.
inline Quat slerp(const Quat& a, Quat b, double t) {
  double c = a.w * b.w + a.x * b.x + a.y * b.y + a.z * b.z;
  if (c < 0) {
    b = {-b.w, -b.x, -b.y, -b.z};
    c = -c;
  }
  if (c > 0.9995) {  // nearly equal: a normalized lerp is exact to double rounding here
    return Quat{a.w + t * (b.w - a.w), a.x + t * (b.x - a.x), a.y + t * (b.y - a.y), a.z + t * (b.z - a.z)}
        .normalized();
  }
  const double theta = std::acos(c);
  const double sa = std::sin((1 - t) * theta) / std::sin(theta), sb = std::sin(t * theta) / std::sin(theta);
  return {sa * a.w + sb * b.w, sa * a.x + sb * b.x, sa * a.y + sb * b.y, sa * a.z + sb * b.z};
}

// Where a rigid body is: world = position + rotation.rotate(local).
struct Pose {
  Vec3 position;   // origin of the body frame in the simulation frame [mm]
  Quat rotation;   // body frame to simulation frame
  constexpr Vec3 apply(const Vec3& local) const { return position + rotation.rotate(local); }
  constexpr Vec3 applyDirection(const Vec3& local) const { return rotation.rotate(local); }
  constexpr bool operator==(const Pose&) const = default;
};

// A force and a moment [N], [N mm]; the point the moment is taken about is stated where one is used.
struct Wrench {
  Vec3 force;   // [N]
  Vec3 moment;  // [N mm]
};

}  // namespace dentsim
