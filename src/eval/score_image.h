// The score picture (like the paper's Figure 20): the cut tooth, the cut that should not have been made in red and under-cut in blue, ray cast on the CPU into a PNG.
//
// Orthographic views of the final tooth: each pixel's ray stops at the first voxel whose final fill
// is at least half (16 of 31); that voxel is shaded Lambert (normal from the central-difference
// gradient of fill) in its tissue's colour, tinted blue by its under-cut (remaining material that
// the ideal removes). The red voxels the caller marks (the over-cut of a cavity, the healthy tissue
// cut outside the allowed zone of a caries removal, and in either what was cut of an adjacent tooth;
// ToothDiff holds all three) add red fog where the ray passes them before the surface, so they show
// red over whatever lies behind. Without an ideal
// there is no blue; remaining caries shows in its brown. A caller may instead paint chosen surface
// voxels green, red or blue (the deviation picture). Rays skip bricks that hold neither surface nor red.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/result.h"
#include "core/rigid.h"
#include "eval/cut_marks.h"
#include "io/png_file.h"
#include "volume/brick_volume.h"

namespace dentsim {

struct ScoreImageOptions {
  int width = 800;             // whole image [px], 16..8192
  int height = 600;            // [px], 16..8192
  Vec3 view_dir{0, 0, -1};     // where the camera looks, in the grid's axes: occlusal, from +z down
  bool oblique = false;        // a second, oblique view to the right; each view then gets half the width
  bool fit_paint = false;      // fit the views to the painted bricks (a margin around them), not the whole tooth
};

// One view's camera, so that a caller (or a test) can find where a voxel appears.
struct ScoreView {
  Vec3 dir;                    // looking direction (unit), grid axes
  Vec3 right, up;              // image axes (unit)
  double voxels_per_pixel = 1.0;
  double u_centre = 0.0, v_centre = 0.0;  // view centre along right and up [voxels]
  int x0 = 0, width = 0, height = 0;      // the view's rectangle in the image [px]
  // Pixel (column, row) where point p appears; p in voxel units, voxel (i,j,k)'s centre at (i+.5, j+.5, k+.5).
  std::array<double, 2> pixelOf(const Vec3& p) const;
};

struct ScoreImage {
  RgbImage image;
  std::vector<ScoreView> views;  // left to right
};

// Paint: a surface voxel that `paint` marks is drawn in the mark's colour in place of its tissue's
// (and of the under-cut tint); the deviation picture (eval/surface_agreement.h) and the crown's
// picture (eval/crown_score.h: reduction map, finish line, undercut) paint this way.
inline constexpr uint32_t kPaintGreen = 1;
inline constexpr uint32_t kPaintRed = 2;
inline constexpr uint32_t kPaintBlue = 3;
inline constexpr uint32_t kPaintYellow = 4;   // a crown's finish line
inline constexpr uint32_t kPaintMagenta = 5;  // a crown's undercut

// Renders the views. The volumes must share the level (compareTeeth checks frames); ideal, red and
// paint may be null (no blue, no red, no paint). red's amounts are fill units removed per voxel;
// paint's are kPaint* codes (others are ignored).
ScoreImage renderScoreImage(const ToothVolume& initial, const ToothVolume& final_, const ToothVolume* ideal,
                            const CutMarks* red, const ScoreImageOptions& options = {}, const CutMarks* paint = nullptr);

}  // namespace dentsim
