// Tool models for the haptic loop: a built-in bur or mirror, or any tool mesh, turned into its point shell.
#pragma once

#include <string>

#include "core/result.h"
#include "core/triangle_mesh.h"
#include "sim/sim_params.h"
#include "sim/tool_proxy.h"

namespace dentsim {

// Where the pen holds a bur, in the bur's frame (tip at the origin, axis +Z): the top of the shank,
// where the handpiece's head seats it [mm]. Moments on the drill are taken about this point.
inline constexpr Vec3 kBurGripLocal{0.0, 0.0, 19.0};
// Where the pen holds the mirror: on its handle, 25 mm from the face's centre [mm].
inline constexpr Vec3 kMirrorGripLocal{-25.0, 0.0, -5.1};

// A built-in tool by name ("round_bur_010", "fissure_bur_010", "mirror_size4"): burs cut with their
// head (the catalog's cutting length), the mirror only collides. Errors: an unknown name, a tool that
// is neither a bur nor a mirror.
Result<ToolModel> loadToolModel(const std::string& name, const PointShellParams& spacing);

// Any tool mesh in its own frame (mm; a bur along +Z with its tip lowest). cutting_length_mm = 0 for
// a tool that never cuts.
Result<ToolModel> makeToolModel(const std::string& name, const TriangleMesh& mesh, double cutting_length_mm,
                                const Vec3& grip_local, const PointShellParams& spacing);

}  // namespace dentsim
