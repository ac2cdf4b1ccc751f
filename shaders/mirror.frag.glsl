// The mirror's face: the mirror pass's image, looked up where the reflected camera saw this point (projective texturing).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "render_common.inc.glsl"

layout(set = DS_RENDER_SET_TEXTURE, binding = 0) uniform sampler2D mirrorImage;

layout(location = 0) in vec3 inWorld;

layout(location = 0) out vec4 outColour;

void main() {
  mat4 mirrorViewProj = mat4(frame.mirrorViewProj[0], frame.mirrorViewProj[1], frame.mirrorViewProj[2],
                             frame.mirrorViewProj[3]);
  vec4 clip = mirrorViewProj * vec4(inWorld, 1.0);
  // Vulkan clip y points down, as the image's rows do.
  vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
  outColour = vec4(texture(mirrorImage, uv).rgb * frame.mirrorTint.rgb, 1.0);
}
