// The exact separable Euclidean distance transform (Felzenszwalb & Huttenlocher).
#include "volume/distance_transform.h"

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <limits>

namespace dentsim {
namespace {

// Squared distance along one line to the nearest site: d[p] = min_q ((p - q) s)^2 + f[q], f[q]
// infinite where q is no site. v holds the parabolas of the lower envelope and z the boundaries
// between them; both are scratch of at least n (z: n + 1).
void distanceLine(const std::vector<double>& f, std::vector<double>& d, size_t n, double s, std::vector<size_t>& v,
                  std::vector<double>& z) {
  const double inf = std::numeric_limits<double>::infinity();
  const double s2 = s * s;
  int64_t k = -1;
  for (size_t q = 0; q < n; ++q) {
    if (!(f[q] < inf)) continue;
    double cross = -inf;
    while (k >= 0) {
      const size_t r = v[size_t(k)];
      const double dq = double(q), dr = double(r);
      cross = ((f[q] + s2 * dq * dq) - (f[r] + s2 * dr * dr)) / (2.0 * s2 * (dq - dr));
      if (cross <= z[size_t(k)]) --k;
      else break;
    }
    ++k;
    v[size_t(k)] = q;
    z[size_t(k)] = k == 0 ? -inf : cross;
  }
  if (k < 0) {
    std::fill(d.begin(), d.begin() + int64_t(n), inf);
    return;
  }
  z[size_t(k) + 1] = inf;
  size_t j = 0;
  for (size_t p = 0; p < n; ++p) {
    while (z[j + 1] < double(p)) ++j;
    const double t = (double(p) - double(v[j])) * s;
    d[p] = t * t + f[v[j]];
  }
}

}  // namespace

// One axis after another: after axis a, each voxel holds the squared distance to the nearest
// outside voxel among those reachable by moves along the axes done so far.
std::vector<float> squaredDistanceToOutside(const std::vector<uint8_t>& inside, const std::array<int32_t, 3>& d,
                                            const std::array<double, 3>& pitch) {
  assert(inside.size() == size_t(d[0]) * size_t(d[1]) * size_t(d[2]));
  assert(pitch[0] > 0 && pitch[1] > 0 && pitch[2] > 0);
  const float finf = std::numeric_limits<float>::infinity();
  std::vector<float> out(inside.size());
  for (size_t i = 0; i < inside.size(); ++i) out[i] = inside[i] ? finf : 0.0f;
  const size_t longest = size_t(std::max({d[0], d[1], d[2]}));
  std::vector<double> f(longest), g(longest), z(longest + 1);
  std::vector<size_t> v(longest);
  const size_t stride[3] = {1, size_t(d[0]), size_t(d[0]) * size_t(d[1])};
  for (size_t a = 0; a < 3; ++a) {
    const size_t n = size_t(d[a]);
    const size_t b1 = a == 0 ? 1 : 0, b2 = a == 2 ? 1 : 2;  // the two other axes
    for (int64_t u = 0; u < d[b2]; ++u)
      for (int64_t w = 0; w < d[b1]; ++w) {
        const size_t base = size_t(w) * stride[b1] + size_t(u) * stride[b2];
        for (size_t p = 0; p < n; ++p) f[p] = double(out[base + p * stride[a]]);
        distanceLine(f, g, n, pitch[a], v, z);
        for (size_t p = 0; p < n; ++p) out[base + p * stride[a]] = float(g[p]);
      }
  }
  return out;
}

}  // namespace dentsim
