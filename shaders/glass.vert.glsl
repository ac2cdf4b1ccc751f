// The mirror's glass disc: world position only, for mirror.frag.glsl's projective lookup.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "render_common.inc.glsl"

layout(location = 0) in vec3 inPosition;  // [mm], mirror frame

layout(location = 0) out vec3 outWorld;   // [mm]

void main() {
  vec4 world = modelMatrix() * vec4(inPosition, 1.0);
  outWorld = world.xyz;
  gl_Position = viewProjMatrix() * world;
}
