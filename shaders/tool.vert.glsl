// Tool and mirror-face vertices: position and normal in the tool's own frame [mm], posed by the model matrix.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "render_common.inc.glsl"

layout(location = 0) in vec3 inPosition;  // [mm], tool frame
layout(location = 1) in vec3 inNormal;    // unit, tool frame

layout(location = 0) out vec3 outWorld;   // [mm]
layout(location = 1) out vec3 outNormal;  // world

void main() {
  mat4 model = modelMatrix();
  vec4 world = model * vec4(inPosition, 1.0);
  outWorld = world.xyz;
  outNormal = mat3(model) * inNormal;  // rigid poses only
  gl_Position = viewProjMatrix() * world;
}
