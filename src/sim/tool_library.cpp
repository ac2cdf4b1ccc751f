// loadToolModel and makeToolModel: tool meshes to point shells with their grip and cutting head.
#include "sim/tool_library.h"

#include <algorithm>
#include <mutex>
#include <vector>

#include "model/builtin_assets.h"
#include "model/tool_generator.h"

namespace dentsim {

Result<ToolModel> makeToolModel(const std::string& name, const TriangleMesh& mesh, double cutting_length_mm,
                                const Vec3& grip_local, const PointShellParams& spacing) {
  PointShellOptions options;
  options.head_spacing_mm = spacing.head_spacing_mm;
  options.shank_spacing_mm = spacing.shank_spacing_mm;
  options.cutting_length_mm = cutting_length_mm;
  // A tool that never cuts (the mirror) is large and sparse: clusters of about 8 x 8 points keep
  // the per-cluster skip test from costing more than the points it skips (a size-4 mirror's 0.4 mm
  // clusters made the step 10 times slower while it hung in the air).
  if (cutting_length_mm <= 0) options.cluster_mm = std::max(options.cluster_mm, 8.0 * spacing.shank_spacing_mm);
  auto shell = buildPointShell(mesh, options);
  if (!shell) return makeError(name, shell.message());
  ToolModel tool;
  tool.name = name;
  tool.shell = std::move(*shell);
  tool.grip_local = grip_local;
  tool.cuts = cutting_length_mm > 0;
  return tool;
}

namespace {

Result<ToolModel> buildToolModel(const std::string& name, const PointShellParams& spacing) {
  for (const ToolSpec& spec : toolCatalog()) {
    if (name != spec.name) continue;
    const bool bur = isBur(spec.kind);
    if (!bur && spec.kind != ToolKind::Mirror)
      return makeError(name, "is not a bur or a mirror; the handpiece is drawn, not simulated");
    auto mesh = loadBuiltinTool(name);
    if (!mesh) return mesh.error();
    if (bur) return makeToolModel(name, *mesh, spec.cutting_length_mm, kBurGripLocal, spacing);
    PointShellParams mirror_spacing = spacing;
    mirror_spacing.shank_spacing_mm = spacing.mirror_spacing_mm;
    return makeToolModel(name, *mesh, 0.0, kMirrorGripLocal, mirror_spacing);
  }
  return makeError(name, "no such built-in tool (see assets/tools/tools.json)");
}

// Built tools by name and spacing. A point shell takes a second or more to build and is always the
// same for the same name and spacing, so a replay, a ghost or the next segment reuses the first one.
// Bounded: a session uses two or three tools, a picker a few more.
struct CachedTool {
  std::string name;
  PointShellParams spacing;
  ToolModel model;
};
constexpr size_t kMaxCachedTools = 8;
std::mutex g_tools_mutex;
std::vector<CachedTool> g_tools;

bool sameSpacing(const PointShellParams& a, const PointShellParams& b) {
  return a.head_spacing_mm == b.head_spacing_mm && a.shank_spacing_mm == b.shank_spacing_mm &&
         a.mirror_spacing_mm == b.mirror_spacing_mm;
}

}  // namespace

Result<ToolModel> loadToolModel(const std::string& name, const PointShellParams& spacing) {
  {
    std::lock_guard lock(g_tools_mutex);
    for (const CachedTool& c : g_tools)
      if (c.name == name && sameSpacing(c.spacing, spacing)) return c.model;
  }
  auto built = buildToolModel(name, spacing);
  if (!built) return built;
  std::lock_guard lock(g_tools_mutex);
  if (g_tools.size() >= kMaxCachedTools) g_tools.erase(g_tools.begin());
  g_tools.push_back(CachedTool{name, spacing, *built});
  return built;
}

}  // namespace dentsim
