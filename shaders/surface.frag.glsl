// Phong shading of the tooth's tissues and the tools, with the draw's opacity; the mirror pass clips at the glass.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "render_common.inc.glsl"

layout(location = 0) in vec3 inWorld;
layout(location = 1) in vec3 inNormal;

layout(location = 0) out vec4 outColour;

void main() {
  if (clipped(inWorld)) discard;
  outColour = vec4(clamp(phong(inNormal, inWorld), 0.0, 1.0), draw.ambient.a);
}
