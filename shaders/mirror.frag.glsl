// The mirror's face: the mirror pass's image, taken texel for pixel where it was drawn at the size it is shown at, else looked up where the reflected camera saw this point (projective texturing).
#version 450
#extension GL_GOOGLE_include_directive : require
#include "render_common.inc.glsl"

layout(set = DS_RENDER_SET_TEXTURE, binding = 0) uniform sampler2D mirrorImage;

layout(location = 0) in vec3 inWorld;

layout(location = 0) out vec4 outColour;

void main() {
  vec3 seen;
  if (frame.mirrorRect.z > 0.0) {
    // The pass drew this very pixel of the screen: its texel, unfiltered, so the reflection is as
    // sharp as the main view (no resampling blurs or stair-steps it).
    ivec2 texel = ivec2(gl_FragCoord.xy - frame.mirrorRect.xy);
    texel = clamp(texel, ivec2(0), ivec2(frame.mirrorRect.zw) - 1);
    seen = texelFetch(mirrorImage, texel, 0).rgb;
  } else {
    mat4 mirrorViewProj = mat4(frame.mirrorViewProj[0], frame.mirrorViewProj[1], frame.mirrorViewProj[2],
                               frame.mirrorViewProj[3]);
    vec4 clip = mirrorViewProj * vec4(inWorld, 1.0);
    // Vulkan clip y points down, as the image's rows do.
    vec2 uv = clip.xy / clip.w * 0.5 + 0.5;
    seen = texture(mirrorImage, uv).rgb;
  }
  outColour = vec4(seen * frame.mirrorTint.rgb, 1.0);
}
