// dentsim mesh: extracts a .dvol tooth's surface (all tissue, one, or every tissue's own for a layered view) as STL or PLY.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/cli_checks.h"
#include "app/commands.h"
#include "app/mesh_output.h"
#include "app/gpu_choice.h"
#include "app/terminal_progress.h"
#include "gpu/gpu_surface.h"
#include "gpu/mesher_kind.h"
#include "io/ply_file.h"
#include "io/stl_file.h"
#include "volume/surface_mesher.h"
#include "volume/tissue_table.h"
#include "volume/tooth_file.h"

namespace dentsim::app {
namespace {

struct MeshOptions {
  std::string input;     // .dvol path
  std::string output;    // .stl or .ply path
  std::string normals = "8";  // gradient neighbourhood [voxels]: "8", "64" or "216"
  std::string tissue;    // empty: the outer surface of all tissue
  bool interfaces = false;  // every tissue's own closed surface, interfaces included
  bool cpu = false;         // the CPU reference instead of the GPU
  std::string device;       // Vulkan device override
};

// One surface on the GPU when there is one, else by the CPU reference (the same triangles; the GPU
// stores normals packed to 12 bits per coordinate).
Result<SurfaceMesh> meshOnce(std::optional<gpu::Context>& ctx, const ToothVolume& tooth, const SurfaceOptions& so,
                             Interrupter& progress, std::vector<gpu::SurfaceUpdateStats>& stats) {
  if (!ctx) return meshVolumeCpu(tooth, so, progress);
  auto surface = gpu::GpuSurface::create(*ctx, {.normal_neighbours = normalNeighbours(so.normals), .tissue = so.tissue});
  if (!surface) return surface.error();
  if (Status built = surface->build(tooth.voxels, &stats.emplace_back()); !built) return built.error();
  auto blocks = surface->downloadBlocks();
  if (!blocks) return blocks.error();
  return weldBlockMeshes(*blocks, tooth.frame);
}

void appendSurface(SurfaceMesh& to, const SurfaceMesh& from) {
  const uint32_t base = uint32_t(to.positions.size());
  to.positions.insert(to.positions.end(), from.positions.begin(), from.positions.end());
  to.normals.insert(to.normals.end(), from.normals.begin(), from.normals.end());
  to.tissue.insert(to.tissue.end(), from.tissue.begin(), from.tissue.end());
  to.across.insert(to.across.end(), from.across.begin(), from.across.end());
  for (const auto& t : from.triangles) to.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

int runMesh(const MeshOptions& o) {
  // Every argument is checked before the volume is read, so a typo costs nothing.
  MeshFormat format{};
  if (!meshFormatOf(o.output, &format)) return fail(o.output + ": unknown mesh format (expected .stl or .ply)");
  SurfaceOptions so;
  if (auto mode = parseNormalMode(o.normals)) so.normals = *mode;
  else return fail("--normals " + o.normals + ": expected " + kNormalModeChoices + " voxels");
  if (!o.tissue.empty() && (!parseMaterial(o.tissue, &so.tissue) || so.tissue == Material::Empty))
    return fail("--tissue: unknown tissue '" + o.tissue + "' (expected " + tissueNameList() + ")");
  if (o.interfaces && !o.tissue.empty()) return fail("--interfaces meshes every tissue; it excludes --tissue");
  if (Status st = checkOutputsAreNotInputs({o.input}, {o.output}); !st) return fail(st.message());
  const std::string label = o.interfaces ? "each tissue" : o.tissue.empty() ? "all tissue" : materialName(so.tissue);

  Result<ToothVolume> tooth = loadTooth(o.input);
  if (!tooth) return fail(tooth.message());
  std::optional<gpu::Context> ctx;
  if (!o.cpu) {
    auto opened = openGpuOrFallBack(o.device, "meshing on the CPU");
    if (!opened) return fail(opened.message());
    ctx = std::move(*opened);
  }
  // GpuSurface picks its mesher for the device (auto): the kernel on a GPU, CPU threads on lavapipe.
  const gpu::MesherKind mesher = ctx ? gpu::resolveMesher(gpu::MesherKind::Auto, ctx->device().type) : gpu::MesherKind::Cpu;
  const std::string engine = !ctx                           ? "CPU reference"
                             : mesher == gpu::MesherKind::Gpu ? "GPU (" + ctx->device().name + ")"
                                                              : "CPU threads (the device, " + ctx->device().name + ", is a CPU)";
  TerminalProgress progress;
  const auto t0 = std::chrono::steady_clock::now();
  SurfaceMesh surface;
  std::vector<gpu::SurfaceUpdateStats> stats;  // per GPU build
  std::vector<std::string> parts;  // per tissue, for --interfaces
  if (o.interfaces) {
    // The layered view: each tissue's own closed surface. Where two tissues meet, both carry the
    // interface (e.g. the enamel-dentin junction), and each vertex names the tissue across it.
    const MaterialTotals totals = tooth->voxels.materialTotals();
    for (Material m : kTissues) {
      if (totals.voxels[size_t(m)] == 0) continue;
      SurfaceOptions one = so;
      one.tissue = m;
      Result<SurfaceMesh> part = meshOnce(ctx, *tooth, one, progress, stats);
      if (!part) return fail(o.input + ": " + part.message());
      const size_t inner = size_t(std::count_if(part->across.begin(), part->across.end(),
                                                [](Material a) { return a != Material::Empty; }));
      parts.push_back(materialName(m) + " " + std::to_string(part->triangleCount()) + " triangles (" +
                      std::to_string(part->positions.empty() ? 0 : 100 * inner / part->positions.size()) +
                      "% of vertices on an interface)");
      appendSurface(surface, *part);
    }
  } else {
    Result<SurfaceMesh> one = meshOnce(ctx, *tooth, so, progress, stats);
    if (!one) return fail(o.input + ": " + one.message());
    surface = std::move(*one);
  }
  const double mesh_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (surface.triangles.empty())
    return fail(o.input + ": no surface to write (the volume holds no " + (o.tissue.empty() ? "tissue" : label) + ")");
  if (Status written = writeSurface(o.output, format, surface, tooth->frame, label); !written) return fail(written.message());
  std::printf("%s: %zu triangles, %zu vertices (%s, normals from %d voxels), meshed on the %s in %.0f ms\n",
              o.output.c_str(), surface.triangleCount(), surface.positions.size(), label.c_str(), normalNeighbours(so.normals),
              engine.c_str(), mesh_ms);
  for (const std::string& p : parts) std::printf("  %s\n", p.c_str());
  for (const gpu::SurfaceUpdateStats& st : stats) {
    std::printf("  %s mesher: %u blocks; upload %.0f ms, count %.0f ms, emit %.0f ms", gpu::mesherKindName(mesher).c_str(),
                st.blocks_meshed, st.upload_ms, st.count_ms, st.emit_ms);
    if (st.timestamps) std::printf(" (kernels: count %.1f ms, emit %.1f ms)", st.count_kernel_ms, st.emit_kernel_ms);
    std::printf("; slots %s in a pool of %s\n", gpu::formatBytes(st.slot_bytes).c_str(),
                gpu::formatBytes(st.pool_bytes).c_str());
  }
  return 0;
}

}  // namespace

void addMeshCommand(CLI::App& root, Action& action) {
  auto opts = std::make_shared<MeshOptions>();
  CLI::App* cmd = root.add_subcommand("mesh", "Extract a .dvol tooth's surface as STL or as PLY with normals and tissue colours");
  cmd->add_option("input", opts->input, "Volume file (.dvol)")->required();
  // Taken as text and checked in runMesh rather than by CLI11, so that a bad value (even "abc") is a
  // one-line error like any other.
  cmd->add_option("--normals", opts->normals, "Gradient neighbourhood for the normals: 8, 64 or 216 voxels")
      ->capture_default_str();
  cmd->add_option("--tissue", opts->tissue, "Mesh only this tissue: " + tissueNameList() + " (default: all)");
  cmd->add_flag("--interfaces", opts->interfaces,
                "Each tissue's own surface, interfaces between tissues included (a layered view)");
  cmd->add_flag("--cpu", opts->cpu, "Mesh with the CPU reference instead of the GPU");
  cmd->add_option("--device", opts->device, "Vulkan device index or name substring (also DENTSIM_DEVICE)");
  cmd->add_option("-o,--output", opts->output, "Output mesh (.stl, or .ply with normals and colours)")->required();
  cmd->callback([opts, &action] { action = [opts] { return runMesh(*opts); }; });
}

}  // namespace dentsim::app
