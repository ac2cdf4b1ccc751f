// Mesh decimation with meshoptimizer: edge collapses first, cell clustering only when collapses stall.
#include "bench/mesh_decimate.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <vector>

#include <meshoptimizer.h>

namespace dentsim::bench {
namespace {

static_assert(sizeof(Vec3f) == 3 * sizeof(float), "meshoptimizer reads positions as packed float triples");

// Tolerated deviations tried in turn, relative to the mesh extent. 1% keeps a molar's cusps within
// about 0.1 mm; the larger ones are for the smallest fractions, where the count matters more.
constexpr float kSimplifyErrors[] = {0.01f, 0.05f, 0.25f};
// A result within this share above the target counts as reaching it.
constexpr double kCountSlack = 0.05;

TriangleMesh compacted(const TriangleMesh& mesh, std::vector<uint32_t> indices) {
  TriangleMesh out;
  out.positions.resize(mesh.positions.size());
  // Rewrites `indices` to the used vertices only, in first-use order.
  const size_t used = meshopt_optimizeVertexFetch(out.positions.data(), indices.data(), indices.size(),
                                                  mesh.positions.data(), mesh.positions.size(), sizeof(Vec3f));
  out.positions.resize(used);
  out.triangles.resize(indices.size() / 3);
  for (size_t t = 0; t < out.triangles.size(); ++t)
    out.triangles[t] = {indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
  return out;
}

}  // namespace

TriangleMesh decimateMesh(const TriangleMesh& mesh, double fraction, DecimateInfo* info) {
  assert(fraction > 0.0 && fraction <= 1.0);
  DecimateInfo local;
  DecimateInfo& d = info ? *info : local;
  d = DecimateInfo{};
  d.fraction = fraction;
  d.input_triangles = mesh.triangleCount();
  d.target_triangles = std::max<uint64_t>(1, uint64_t(std::llround(fraction * double(mesh.triangleCount()))));

  TriangleMesh out;
  if (fraction >= 1.0 || mesh.triangleCount() == 0) {
    out = mesh;
    d.method = "copy";
  } else {
    std::vector<uint32_t> indices;
    indices.reserve(3 * mesh.triangleCount());
    for (const auto& t : mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
    const float* xyz = mesh.positions.front().data();
    const size_t target_indices = 3 * d.target_triangles;
    const auto good_enough = [&](size_t n) { return double(n) <= double(target_indices) * (1.0 + kCountSlack); };
    // meshopt reports errors relative to this length.
    const double scale_mm = meshopt_simplifyScale(xyz, mesh.positions.size(), sizeof(Vec3f));

    // Worst case output is the input (meshoptimizer.h), not the target.
    std::vector<uint32_t> dst(indices.size());
    size_t n = indices.size();
    float error = 0.0f;
    for (float target_error : kSimplifyErrors) {
      n = meshopt_simplify(dst.data(), indices.data(), indices.size(), xyz, mesh.positions.size(), sizeof(Vec3f),
                           target_indices, target_error, 0, &error);
      d.method = "simplify";
      d.target_error = target_error;
      if (good_enough(n)) break;
    }
    if (!good_enough(n)) {
      // Collapses ran out (topology blocks the rest): cluster instead, which may open the surface.
      // A closed surface needs 4 triangles at least; below that clustering has erased the shape,
      // and the stalled collapse result is the better mesh.
      constexpr float kAnyError = 1.0f;  // let the target count, not the error, stop it
      constexpr size_t kFewestClosed = 3 * 4;
      std::vector<uint32_t> sloppy(indices.size());
      float sloppy_error = 0.0f;
      const size_t m = meshopt_simplifySloppy(sloppy.data(), indices.data(), indices.size(), xyz,
                                              mesh.positions.size(), sizeof(Vec3f), target_indices, kAnyError,
                                              &sloppy_error);
      if (m >= kFewestClosed) {
        dst.swap(sloppy);
        n = m;
        error = sloppy_error;
        d.method = "sloppy";
        d.target_error = kAnyError;
      }
    }
    d.error_mm = double(error) * scale_mm;
    dst.resize(n);
    out = compacted(mesh, std::move(dst));
  }
  d.output_triangles = out.triangleCount();
  d.topology = analyzeTopology(out);
  return out;
}

}  // namespace dentsim::bench
