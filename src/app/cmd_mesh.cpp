// dentsim mesh: extracts a .dvol tooth's surface (all tissue or one) and writes it as STL or as PLY with normals and tissue colours.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.h"
#include "app/terminal_progress.h"
#include "io/ply_file.h"
#include "io/stl_file.h"
#include "volume/surface_mesher.h"
#include "volume/tooth_file.h"

namespace dentsim::app {
namespace {

struct MeshOptions {
  std::string input;     // .dvol path
  std::string output;    // .stl or .ply path
  std::string normals = "8";  // gradient neighbourhood [voxels]: "8", "64" or "216"
  std::string tissue;    // empty: the outer surface of all tissue
};

enum class MeshFormat { Stl, Ply };

// The output format from the extension, case-insensitively; false for anything else.
bool formatOf(const std::string& path, MeshFormat* format) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return false;
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; });
  if (ext == "stl") *format = MeshFormat::Stl;
  else if (ext == "ply") *format = MeshFormat::Ply;
  else return false;
  return true;
}

// Vertex colours per tissue, chosen to read like the stained sections in dental atlases: enamel
// near-white ivory, dentin yellowish, pulp red, caries brown; grey for anything else (the spare codes).
Rgb8 tissueColour(Material m) {
  switch (m) {
    case Material::Enamel: return {240, 238, 228};
    case Material::Dentin: return {222, 196, 128};
    case Material::Pulp: return {200, 40, 50};
    case Material::Caries: return {110, 70, 35};
    default: return {128, 128, 128};
  }
}

Status writeSurface(const std::string& path, MeshFormat format, const SurfaceMesh& surface, const std::string& label) {
  if (format == MeshFormat::Stl) return writeStl(path, surface.geometry(), "dentsim mesh " + label);
  std::vector<Rgb8> colours(surface.tissue.size());
  std::transform(surface.tissue.begin(), surface.tissue.end(), colours.begin(), tissueColour);
  return writePly(path, PlyView{surface.positions, surface.normals, colours, surface.triangles}, "dentsim mesh " + label);
}

int runMesh(const MeshOptions& o) {
  // Every argument is checked before the volume is read, so a typo costs nothing.
  MeshFormat format{};
  if (!formatOf(o.output, &format)) return fail(o.output + ": unknown mesh format (expected .stl or .ply)");
  SurfaceOptions so;
  if (o.normals == "8") so.normal_neighbours = 8;
  else if (o.normals == "64") so.normal_neighbours = 64;
  else if (o.normals == "216") so.normal_neighbours = 216;
  else return fail("--normals " + o.normals + ": expected 8, 64 or 216 voxels");
  if (!o.tissue.empty() && (!parseMaterial(o.tissue, &so.tissue) || so.tissue == Material::Empty))
    return fail("--tissue: unknown tissue '" + o.tissue + "' (expected enamel, dentin, pulp or caries)");
  const std::string label = o.tissue.empty() ? "all tissue" : materialName(so.tissue);

  Result<ToothVolume> tooth = loadTooth(o.input);
  if (!tooth) return fail(tooth.message());
  TerminalProgress progress;
  const auto t0 = std::chrono::steady_clock::now();
  Result<SurfaceMesh> surface = meshVolumeCpu(*tooth, so, progress);
  if (!surface) return fail(o.input + ": " + surface.message());
  const double mesh_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (surface->triangles.empty())
    return fail(o.input + ": no surface to write (the volume holds no " + (o.tissue.empty() ? "tissue" : label) + ")");
  if (Status written = writeSurface(o.output, format, *surface, label); !written) return fail(written.message());
  std::printf("%s: %zu triangles, %zu vertices (%s, normals from %d voxels), meshed in %.0f ms\n", o.output.c_str(),
              surface->triangleCount(), surface->positions.size(), label.c_str(), so.normal_neighbours, mesh_ms);
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
  cmd->add_option("--tissue", opts->tissue, "Mesh only this tissue: enamel, dentin, pulp or caries (default: all)");
  cmd->add_option("-o,--output", opts->output, "Output mesh (.stl, or .ply with normals and colours)")->required();
  cmd->callback([opts, &action] { action = [opts] { return runMesh(*opts); }; });
}

}  // namespace dentsim::app
