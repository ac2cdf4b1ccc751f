// A screen-space rectangle (two triangles from the vertex index) for the overlay picture.
#version 450
#extension GL_GOOGLE_include_directive : require
#include "render_common.inc.glsl"

layout(location = 0) out vec2 outUv;

void main() {
  // Corners of triangles (0,1,2) and (2,1,3) of the quad, as (u, v) in [0,1].
  const vec2 corners[6] = vec2[](vec2(0, 0), vec2(1, 0), vec2(0, 1), vec2(0, 1), vec2(1, 0), vec2(1, 1));
  vec2 c = corners[gl_VertexIndex];
  outUv = c;
  gl_Position = vec4(mix(draw.rect.xy, draw.rect.zw, c), 0.0, 1.0);
}
