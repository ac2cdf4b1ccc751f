// The overlay picture, unlit and opaque.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "render_common.inc.glsl"

layout(set = DS_RENDER_SET_TEXTURE, binding = 0) uniform sampler2D overlayImage;

layout(location = 0) in vec2 inUv;
layout(location = 0) out vec4 outColour;

void main() {
  outColour = vec4(texture(overlayImage, inUv).rgb, 1.0);
}
