// Render layout: the uniform block and push constants that the renderer's C++ and its GLSL shaders both include.
//
// Only defines and structs of vec4s appear here, so that GLSL compiles it unchanged (shaders include
// it as "../src/render/render_layout.h"). Matrices are four vec4 columns. A test pins the offsets.
#ifndef DENTSIM_RENDER_LAYOUT_H
#define DENTSIM_RENDER_LAYOUT_H

#ifdef __cplusplus
namespace dentsim::render::layout {
struct vec4 {
  float x, y, z, w;
};
#endif

// Descriptor sets of the graphics pipelines.
#define DS_RENDER_SET_FRAME 0    // binding 0: FrameUniforms (uniform buffer)
#define DS_RENDER_SET_TEXTURE 1  // binding 0: the sampled image (mirror image or overlay)

// What one pass shares: camera, light and clip plane.                                  size 208
struct FrameUniforms {
  vec4 viewProj[4];        // offset   0: world [mm] to clip space, columns
  vec4 mirrorViewProj[4];  // offset  64: world to the mirror image's clip space (main pass), columns
  vec4 eye;                // offset 128: eye position [mm], w = 1
  vec4 lightDir;           // offset 144: unit direction toward the light, w = 0
  vec4 clipPlane;          // offset 160: fragments with dot(clipPlane, (x, 1)) < 0 are discarded
  vec4 mirrorTint;         // offset 176: rgb the mirror's reflectance, a unused
  vec4 mirrorRect;         // offset 192: the mirror image's place on the target: x, y its top-left, z, w its
                           //             size [px], texel (i, j) under pixel (x + i, y + j); z = 0: an image
                           //             of its own size, looked up through mirrorViewProj (main pass)
};

// Per draw: object placement and Phong material (push constants).                      size 128
struct DrawConstants {
  vec4 model[4];  // offset   0: object to world [mm], columns
  vec4 ambient;   // offset  64: rgb ambient colour, a opacity [0..1]
  vec4 diffuse;   // offset  80: rgb diffuse colour
  vec4 specular;  // offset  96: rgb specular colour, w Phong exponent
  vec4 rect;      // offset 112: overlay rectangle in NDC (x0, y0, x1, y1); unused by the 3D draws
};

#ifdef __cplusplus
static_assert(sizeof(FrameUniforms) == 208, "FrameUniforms layout is pinned for GLSL");
static_assert(sizeof(DrawConstants) == 128, "DrawConstants layout is pinned for GLSL (128 B: the guaranteed push-constant size)");
}  // namespace dentsim::render::layout
#endif

#endif  // DENTSIM_RENDER_LAYOUT_H
