// The embedded assets/ files: lookup, parsing into meshes, and regeneration of every file.
#include "model/builtin_assets.h"

#include "io/stl_file.h"
#include "model/embedded_assets.h"
#include "model/tool_generator.h"

namespace dentsim {
namespace {

// STL headers name the frame, so a file says what it holds wherever it ends up.
constexpr const char* kMolarHeaders[4] = {
    "dentsim lower first molar: enamel shell; mm; CEJ at z=0, crown +z",
    "dentsim lower first molar: dentin incl. pulp space; mm; CEJ at z=0, crown +z",
    "dentsim lower first molar: pulp; mm; CEJ at z=0, crown +z",
    "dentsim lower first molar: caries; mm; CEJ at z=0, crown +z",
};

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
  TriangleMesh* out[4] = {&layers.enamel, &layers.dentin, &layers.pulp, &layers.caries};
  for (int i = 0; i < 4; ++i) {
    auto mesh = parseEmbedded(kMolarLayerFiles[i]);
    if (!mesh) return mesh.error();
    *out[i] = std::move(*mesh);
  }
  return layers;
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
  const TriangleMesh* layers[4] = {&g.molar.enamel, &g.molar.dentin, &g.molar.pulp, &g.molar.caries};
  for (int i = 0; i < 4; ++i) g.files.push_back({kMolarLayerFiles[i], encodeStlBinary(*layers[i], kMolarHeaders[i])});
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
