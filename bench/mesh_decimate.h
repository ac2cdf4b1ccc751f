// Mesh decimation for the voxelization benchmark: fewer triangles, same shape, by meshoptimizer.
#pragma once

#include <cstdint>
#include <string>

#include "core/triangle_mesh.h"
#include "io/mesh_topology.h"

namespace dentsim::bench {

// What decimateMesh did, for the benchmark's report.
struct DecimateInfo {
  double fraction = 1.0;          // asked share of triangles, (0, 1]
  uint64_t input_triangles = 0;   // triangles in
  uint64_t target_triangles = 0;  // round(fraction x input)
  uint64_t output_triangles = 0;  // triangles out
  std::string method;             // "copy" (fraction 1), "simplify" or "sloppy"
  double target_error = 0.0;      // meshopt target error that reached the count, relative to the extent
  double error_mm = 0.0;          // meshopt's reported geometric deviation [mm]
  MeshTopology topology;          // of the result: open edges appear only where the method tore it
};

// Reduces `mesh` to about `fraction` of its triangles, fraction in (0, 1].
//
// First the topology-preserving edge collapser (meshopt_simplify), with a tolerated error that
// grows from 1% to 25% of the extent until the count is within 5% of the target; when collapses run
// out above that (topology blocks them), the clustering simplifier (meshopt_simplifySloppy), which
// reaches any count but may open the surface; unless it leaves fewer than 4 triangles, in which
// case the stalled collapse result stays. Vertices are compacted and stay in first-use order.
// Deterministic: the same input gives the same output. `info` may be null.
TriangleMesh decimateMesh(const TriangleMesh& mesh, double fraction, DecimateInfo* info = nullptr);

}  // namespace dentsim::bench
