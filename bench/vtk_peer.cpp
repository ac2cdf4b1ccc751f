// The VTK peer: the brick volume copied into a dense vtkImageData and contoured by vtkFlyingEdges3D, timed.
#include <unistd.h>

#include <array>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include <vtkFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkVersion.h>

#include "bench/peers.h"
#include "bench/voxelize_bench.h"

namespace dentsim::bench {

// In vtk_smp_info.cpp, compiled as C++17 (vtkSMPTools.h is not valid C++20).
std::string vtkSmpBackend();
int vtkSmpThreads();

namespace {

// Memory the kernel could hand out now [B]: MemAvailable, or the free pages where /proc is missing.
uint64_t availableBytes() {
  std::ifstream in("/proc/meminfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("MemAvailable:", 0) == 0) return std::stoull(line.substr(13)) * 1024;
  const long pages = ::sysconf(_SC_AVPHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && page > 0 ? uint64_t(pages) * uint64_t(page) : 0;
}

// What a run holds at its peak [B]: the image, Flying Edges' edge case per x-edge (one byte each, as
// many as voxels), its per-row metadata (six ids per row) and the output, guessed from the dense
// bricks at a few hundred triangles each (32 B per triangle in the cell array, 24 B per point for
// position and normal, half a point per triangle).
uint64_t peakBytes(const BrickVolume& volume) {
  const uint64_t dim = volume.dim();
  const uint64_t triangles = volume.stats().dense_bricks * 400;
  return 2 * dim * dim * dim + dim * dim * 6 * sizeof(vtkIdType) + triangles * (32 + 12);
}

double msSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

std::string gib(uint64_t bytes) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.1f GiB", double(bytes) / double(1ull << 30));
  return buf;
}

// The dense image: each brick's 8 rows of 8 voxels per slice written in place; every brick is
// visited (tiles too), so the image needs no clearing first.
void fillImage(const BrickVolume& volume, Material tissue, uint8_t* image) {
  std::array<uint8_t, 256> scalar{};  // voxel byte -> fill that counts for `tissue`
  for (uint32_t b = 0; b < 256; ++b) {
    const Voxel v = Voxel(b);
    scalar[b] = (tissue == Material::Empty || voxelMaterial(v) == tissue) ? uint8_t(voxelFill(v)) : uint8_t(0);
  }
  const size_t dim = volume.dim();
  volume.forEachBrick([&](const BrickView& b) {
    for (uint32_t z = 0; z < DS_BRICK_DIM; ++z)
      for (uint32_t y = 0; y < DS_BRICK_DIM; ++y) {
        const size_t gz = size_t(b.coord.z) * DS_BRICK_DIM + z, gy = size_t(b.coord.y) * DS_BRICK_DIM + y;
        uint8_t* row = image + (gz * dim + gy) * dim + size_t(b.coord.x) * DS_BRICK_DIM;
        if (b.uniform) {
          std::memset(row, scalar[b.value], DS_BRICK_DIM);
          continue;
        }
        for (uint32_t x = 0; x < DS_BRICK_DIM; ++x) row[x] = scalar[b.voxels[layout::brickCoordToOffset(x, y, z)]];
      }
  });
}

}  // namespace

PeerMesh vtkFlyingEdges(const BrickVolume& volume, Material tissue, int repeats) {
  PeerMesh p;
  p.name = std::string("VTK ") + vtkVersion::GetVTKVersion() + " vtkFlyingEdges3D (" + vtkSmpBackend() + ")";
  p.threads = vtkSmpThreads();
  const uint64_t dim = volume.dim();
  p.image_bytes = dim * dim * dim;
  const uint64_t need = peakBytes(volume), have = availableBytes();
  if (need + need / 4 > have) {
    p.skipped = "level " + std::to_string(volume.level()) + " needs about " + gib(need) + " and " + gib(have) +
                " is available";
    return p;
  }

  const auto build_start = std::chrono::steady_clock::now();
  vtkNew<vtkImageData> image;
  image->SetDimensions(int(dim), int(dim), int(dim));
  // Point (i,j,k) is voxel (i,j,k)'s centre, in the voxel units dentsim's MeshVertex uses.
  image->SetOrigin(0.5, 0.5, 0.5);
  image->SetSpacing(1.0, 1.0, 1.0);
  image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
  fillImage(volume, tissue, static_cast<uint8_t*>(image->GetScalarPointer()));
  p.image_ms = msSince(build_start);

  for (int i = 0; i < repeats; ++i) {
    // A new filter each run, so every run allocates its output as the first one does.
    vtkNew<vtkFlyingEdges3D> filter;
    filter->SetInputData(image);
    filter->SetNumberOfContours(1);
    filter->SetValue(0, 0.5 * DS_FILL_FULL);  // between fills 15 and 16: phi = 0.5, never on a sample
    filter->ComputeNormalsOn();               // gradient normals, as dentsim's are
    filter->ComputeGradientsOff();
    filter->ComputeScalarsOff();              // it would repeat 15.5 at every point
    const auto start = std::chrono::steady_clock::now();
    filter->Update();
    p.runs_ms.push_back(msSince(start));
    vtkPolyData* out = filter->GetOutput();
    p.triangles = uint64_t(out->GetNumberOfPolys());
    p.points = uint64_t(out->GetNumberOfPoints());
  }
  p.available = !p.runs_ms.empty();
  if (p.available) p.ms = median(p.runs_ms);
  return p;
}

}  // namespace dentsim::bench
