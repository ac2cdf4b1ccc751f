// The embedded assets/ files: lookup, parsing into meshes, and regeneration of every file.
#include "model/builtin_assets.h"

#include "io/stl_file.h"
#include "model/embedded_assets.h"
#include "model/tool_generator.h"

namespace dentsim {
namespace {

// STL headers name the frame, so a file says what it holds wherever it ends up.
std::string molarHeader(const MolarLayerRow& row) {
  return "dentsim lower first molar: " + std::string(row.description) + "; mm; CEJ at z=0, crown +z";
}

std::string neighbourHeader(const NeighbourRow& row) {
  return "dentsim " + std::string(row.description) + "; mm; the molar's frame, CEJ at z=0, crown +z";
}

Result<TriangleMesh> parseEmbedded(const std::string& path) {
  const std::span<const uint8_t> bytes = builtinAssetBytes(path);
  if (bytes.empty())
    return makeError("builtin " + path, "not embedded; run `dentsim make-tooth --out assets` and rebuild");
  auto stl = parseStl(bytes, "builtin " + path);
  if (!stl) return stl.error();
  return std::move(stl->mesh);
}

}  // namespace

std::span<const uint8_t> builtinAssetBytes(std::string_view relative_path) {
  for (const embedded::Asset* a = embedded::kAssets; a->path; ++a)
    if (relative_path == a->path) return {a->data, a->size};
  return {};
}

std::vector<std::string> builtinAssetPaths() {
  std::vector<std::string> paths;
  for (const embedded::Asset* a = embedded::kAssets; a->path; ++a) paths.emplace_back(a->path);
  return paths;
}

Result<MolarLayers> loadBuiltinMolar() {
  MolarLayers layers;
  for (const MolarLayerRow& row : kMolarLayers) {
    auto mesh = parseEmbedded(molarLayerFile(row));
    if (!mesh) return mesh.error();
    layers.*row.mesh = std::move(*mesh);
  }
  return layers;
}

Result<NeighbourTeeth> loadBuiltinNeighbours() {
  NeighbourTeeth teeth;
  for (const NeighbourRow& row : kNeighbourTeeth) {
    auto mesh = parseEmbedded(neighbourFile(row));
    if (!mesh) return mesh.error();
    teeth.*row.mesh = std::move(*mesh);
  }
  return teeth;
}

Result<TriangleMesh> loadBuiltinTool(std::string_view name) {
  for (const ToolSpec& t : toolCatalog())
    if (name == t.name) return parseEmbedded("tools/" + std::string(name) + ".stl");
  std::string known;
  for (const ToolSpec& t : toolCatalog()) known += (known.empty() ? "" : ", ") + std::string(t.name);
  return makeError("builtin tool " + std::string(name), "unknown (known: " + known + ")");
}

GeneratedAssets generateAssets(const MolarOptions& options) {
  GeneratedAssets g;
  g.molar = generateMolar(options);
  for (const MolarLayerRow& row : kMolarLayers)
    g.files.push_back({molarLayerFile(row), encodeStlBinary(g.molar.*row.mesh, molarHeader(row))});
  g.neighbours = generateNeighbours();
  for (const NeighbourRow& row : kNeighbourTeeth)
    g.files.push_back({neighbourFile(row), encodeStlBinary(g.neighbours.*row.mesh, neighbourHeader(row))});
  for (const ToolSpec& t : toolCatalog()) {
    g.tools.push_back(generateTool(t));
    const std::string header = std::string("dentsim tool ") + t.name + " (" + toolKindName(t.kind) +
                               "); mm; see assets/tools/README.md for its frame";
    g.files.push_back({"tools/" + std::string(t.name) + ".stl", encodeStlBinary(g.tools.back(), header)});
  }
  const std::string json = toolCatalogJson();
  g.files.push_back({"tools/tools.json", std::vector<uint8_t>(json.begin(), json.end())});
  return g;
}

}  // namespace dentsim
