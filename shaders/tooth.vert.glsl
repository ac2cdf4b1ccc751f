// Tooth vertices read straight from the mesher's slot pool (MeshVertex): voxel-unit position, octahedral normal.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "render_common.inc.glsl"

layout(location = 0) in vec3 inPosition;  // [voxel units of the grid]
layout(location = 1) in uint inPacked;    // MeshVertex.packed

layout(location = 0) out vec3 outWorld;   // [mm]
layout(location = 1) out vec3 outNormal;  // world, not normalized

// Inverse of the mesher's packOctahedral (12-bit u and v in the low 24 bits).
vec3 unpackOctahedral(uint packed) {
  vec2 f = vec2(float(packed & 4095u), float((packed >> 12u) & 4095u)) * (2.0 / 4095.0) - 1.0;
  vec3 n = vec3(f, 1.0 - abs(f.x) - abs(f.y));
  if (n.z < 0.0) {
    vec2 s = vec2(f.x >= 0.0 ? 1.0 : -1.0, f.y >= 0.0 ? 1.0 : -1.0);
    n.xy = (1.0 - abs(f.yx)) * s;
  }
  return normalize(n);
}

void main() {
  mat4 model = modelMatrix();
  vec4 world = model * vec4(inPosition, 1.0);
  outWorld = world.xyz;
  // The voxel-to-mm map is a uniform scale and a shift, so normals transform like directions.
  outNormal = mat3(model) * unpackOctahedral(inPacked);
  gl_Position = viewProjMatrix() * world;
}
