// loadToolModel and makeToolModel: tool meshes to point shells with their grip and cutting head.
#include "sim/tool_library.h"

#include <algorithm>

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

Result<ToolModel> loadToolModel(const std::string& name, const PointShellParams& spacing) {
  for (const ToolSpec& spec : toolCatalog()) {
    if (name != spec.name) continue;
    const bool bur = spec.kind == ToolKind::RoundBur || spec.kind == ToolKind::FissureBur;
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

}  // namespace dentsim
