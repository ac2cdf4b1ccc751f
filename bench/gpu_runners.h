// The GPU voxelizer and mesher in the shapes the benchmarks time: a DentsimVoxelizer, a VolumeMaker and a MeshRunner.
#pragma once

#include <vector>

#include "bench/mesh_bench.h"
#include "bench/voxelize_bench.h"
#include "core/triangle_mesh.h"
#include "gpu/context.h"
#include "gpu/mesher_kind.h"
#include "volume/mesh_voxelizer.h"

namespace dentsim::bench {

// dentsim's side of a voxelize run: ray set-up and GPU voxelization into bricks mirrored on the
// CPU, timed by the host clock from the meshes to the CPU bricks. `context` must outlive it.
DentsimVoxelizer gpuVoxelizer(gpu::Context& context, const VoxelizeOptions& options);

// The layers at a level in a grid fitted to `bounds`: the GPU voxelizer on `context`, or the CPU
// reference when it is null (the same voxels). `context` and `layers` must outlive the maker.
VolumeMaker layersVolumeMaker(gpu::Context* context, const std::vector<MeshLayer>& layers, Bounds3 bounds);

// GpuSurface as a bench runner, with the mesher asked for (Auto resolved for the context's device):
// the compute kernel or the CPU threads. `context` must outlive it.
MeshRunner gpuMeshRunner(gpu::Context& context, gpu::MesherKind mesher = gpu::MesherKind::Gpu);

}  // namespace dentsim::bench
