// Shared by the renderer's shaders: the frame uniforms, the per-draw push constants and the Phong model.
#ifndef DENTSIM_RENDER_COMMON_INC
#define DENTSIM_RENDER_COMMON_INC

#include "../src/render/render_layout.h"

// A read-only storage buffer (the gpu library's buffers have no uniform usage); std430 places these
// vec4s where std140 would.
layout(std430, set = DS_RENDER_SET_FRAME, binding = 0) readonly buffer FrameBlock {
  FrameUniforms frame;
};

layout(push_constant) uniform DrawBlock {
  DrawConstants draw;
};

mat4 viewProjMatrix() {
  return mat4(frame.viewProj[0], frame.viewProj[1], frame.viewProj[2], frame.viewProj[3]);
}

mat4 modelMatrix() {
  return mat4(draw.model[0], draw.model[1], draw.model[2], draw.model[3]);
}

// One white directional light of intensity 1: ambient + diffuse (N.L) + specular (R.V)^shininess.
// The renderer's tests evaluate the same formula on the CPU.
vec3 phong(vec3 normal, vec3 worldPos) {
  vec3 n = normalize(normal);
  vec3 l = frame.lightDir.xyz;
  vec3 v = normalize(frame.eye.xyz - worldPos);
  float nl = max(dot(n, l), 0.0);
  float rv = max(dot(reflect(-l, n), v), 0.0);
  float spec = nl > 0.0 ? pow(rv, draw.specular.w) : 0.0;
  return draw.ambient.rgb + draw.diffuse.rgb * nl + draw.specular.rgb * spec;
}

// The mirror pass keeps only what lies in front of the glass.
bool clipped(vec3 worldPos) {
  return dot(frame.clipPlane, vec4(worldPos, 1.0)) < 0.0;
}

#endif
