// Segmented label images (CT) into the brick volume and back: label maps, import with optional clean-up and resampling, export.
//
// Contents
//   1. Label maps ("1=caries,2=enamel,3=dentin")
//   2. importLabels: a LabelImage into a ToothVolume (what it changed in a LabelImportReport);
//      cleanSmallPieces, its small-piece clean-up on its own (for ct_segment)
//   3. exportLabels: a ToothVolume back into a LabelImage (Material codes as labels)
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/interrupter.h"
#include "core/result.h"
#include "io/nifti_labels.h"
#include "volume/brick_volume.h"
#include "volume/voxelize_plan.h"

namespace dentsim {

// ---- 1. label maps --------------------------------------------------------------------------
// Label value in the image -> tissue. Label 0 is always empty and cannot be mapped; a label may
// map to "empty" to drop it on purpose.
using LabelMap = std::map<int32_t, Material>;

// Parses "LABEL=TISSUE[,LABEL=TISSUE...]" (spaces around items allowed). Errors: bad syntax, a
// label outside -32768..32767 or equal to 0, a label given twice, an unknown tissue name.
Result<LabelMap> parseLabelMap(const std::string& text);

// ---- 2. import ------------------------------------------------------------------------------
struct LabelImportOptions {
  LabelMap map;                             // every non-zero label in the data must appear here
  std::optional<double> voxel_mm;           // target voxel edge [mm]; unset: the source pitch
  std::optional<int> level;                 // fit the tissue into a 2^level grid (excludes voxel_mm)
  std::optional<double> source_pitch_mm;    // overrides the header pitch (isotropic) [mm]
  std::optional<Material> fill_enclosed;    // empty voxels enclosed by the tooth become this
  double seal_mm = 0.0;                     // closing radius for fill_enclosed; 0: plain flood [mm]
  int64_t min_piece_voxels = 0;             // relabel pieces smaller than this [source voxels]; 0: off
  std::string where;                        // names the source in errors (the file path)
  // Resampling fills a chunk or brick whose samples all read one tissue (or none) as one tile
  // without sampling its voxels. false: every voxel sampled, the reference the tests hold it to.
  bool uniform_shortcuts = true;
  // Resampling only: fit this box of source voxels (inclusive, lo and hi per axis) into the grid in place
  // of the tissue's own bounding box, so that two imports of one scanner space (its labels, and a
  // segmentation of its grey values) share a grid voxel for voxel. It may reach outside the image.
  std::optional<std::array<std::array<int64_t, 2>, 3>> fit_box;
  // Resampling only: called with the import's estimated cost once the level is known and before
  // any target voxel is made; an error from it ends the import (a job too large for the machine).
  std::function<Status(const VoxelizeCost&)> approve;
};

// What the small-piece clean-up relabelled. Arrays are indexed by Material code (0 empty .. 4 caries).
struct PieceCleanup {
  std::array<uint64_t, DS_MATERIAL_COUNT> pieces{};       // pieces relabelled, by their tissue before
  std::array<uint64_t, DS_MATERIAL_COUNT> voxels{};       // voxels in those pieces, by their tissue before
  std::array<uint64_t, DS_MATERIAL_COUNT> voxels_into{};  // the same voxels, by the tissue they became
};

struct LabelImportReport {
  PieceCleanup cleanup;  // all zero when min_piece_voxels is 0
  // Resampling only: target voxels sampled one by one. The rest were filled as whole chunk or
  // brick tiles, so this grows with the surface's bricks, not with the grid.
  uint64_t sampled_voxels = 0;
};

// Builds a tooth from labels.
//
// Without resampling (target voxel == source pitch, within 1e-9 relative): the grid is the smallest
// 2^L >= max(dims), L >= 3; source voxel (i,j,k) is grid voxel (i,j,k); every tissue voxel is full
// (fill 31); the frame records the source box, and scanner_from_grid is the source's scanner matrix
// with each column rescaled to the source pitch (direction and sign kept, offset unchanged).
//
// With resampling (a level, or a voxel size other than the pitch): the tissue's bounding box
// (non-empty voxels after mapping, cleaning and filling) is centred in the grid with a margin of 2 target
// voxels on every side. With `level` N the voxel is the largest box extent [mm] / (2^N - 4); with
// `voxel_mm` the level is the smallest that fits box + margin. Each target voxel takes n^3 point
// samples (n = clamp(ceil(voxel / pitch), 1, 4) per axis), nearest-neighbour into the source:
// material = the most frequent tissue among solid samples, ties going to the inner tissue
// (pulp > caries > dentin > enamel); fill = round(31 * solid samples / samples), at least 1 when any
// sample is solid; no solid sample: empty. The frame then has no source box (the grids differ),
// and scanner_from_grid maps target voxel centres into the source's scanner space.
//
// min_piece_voxels (> 0) cleans the segmentation first, on the source grid after mapping, before
// fill_enclosed and resampling. A piece is a 6-connected set of source voxels of one tissue (labels
// mapped to the same tissue count as one; empty is a tissue too, so small holes are pieces). Every
// piece with fewer voxels than min_piece_voxels takes the tissue that most of its faces touch outside
// the piece: each face between a piece voxel and a voxel outside it is one vote, faces on the image
// border do not vote, and ties go to the inner tissue (pulp > caries > dentin > enamel > empty), as
// in resampling. Pieces are taken in scan order of their first voxel (i fastest, then j, then k) and
// relabelled at once, so a piece relabelled earlier votes with its new tissue; a speck enclosed by a
// small shell is thus decided after the shell, and follows the shell's new tissue. A piece with no
// votes (the whole image) is kept. Memory: one bit per source voxel, the piece while it is below the
// limit, and a flood front. Single isolated voxels in a 34 um CT are segmentation noise that no
// surface holds (a lone voxel meshes to 1/6 of a voxel), which is what this is for.
//
// fill_enclosed works on the source grid before resampling: an empty voxel not 6-connected to the
// image border through empty voxels becomes that tissue (an explicit queue; no recursion). Real
// teeth have open root canals (apical foramina), so with seal_mm > 0 the dentin (or, with no dentin,
// every tissue) is first closed by a cube of that radius: openings narrower than about 2 x seal_mm
// are sealed for the flood, and only empty voxels deeper than the flood's reach back become filled.
//
// Errors (one line, naming options.where): a non-zero label not in the map (with its voxel count),
// an anisotropic pitch without a target size, a negative min_piece_voxels, a grid beyond
// DS_MAX_LEVEL, no tissue to fit, a cancel through `interrupter`. `report`, when given, receives
// what the clean-up changed (reset first, also on error).
Result<ToothVolume> importLabels(const LabelImage& image, const LabelImportOptions& options,
                                 Interrupter& interrupter = nullInterrupter(), LabelImportReport* report = nullptr);

// The small-piece clean-up of importLabels (min_piece_voxels, described above), for other makers of
// voxel grids (ct_segment). `codes` holds one voxel per grid cell, i fastest, each empty (0) or full
// (makeVoxel(tissue, DS_FILL_FULL)); min_voxels > 0. Progress goes to `interrupter` as [0, 1]; a cancel
// is an error "WHERE: import cancelled". `report` accumulates (it is not reset).
Status cleanSmallPieces(std::vector<Voxel>& codes, const std::array<int32_t, 3>& dims, int64_t min_voxels,
                        PieceCleanup& report, Interrupter& interrupter, const std::string& where);

// ---- 3. export ------------------------------------------------------------------------------
enum class ExportRegion {
  Auto,       // the source box when the frame has one, else the whole grid
  WholeGrid,  // always the whole 2^L grid
};

// Labels are the tissue table's nifti_label (today the material codes: 0 empty, 1 enamel, 2 dentin,
// 3 pulp, 4 caries; a spare code without a row keeps its code). A voxel with fill
// < 16 (less than half solid) exports as 0, so a cut surface lands where half the voxel remains,
// and a full-fill import exports its labels unchanged. The pitch is frame.voxel_mm and the scanner
// matrix is frame.scanner_from_grid shifted to the region's first voxel.
LabelImage exportLabels(const ToothVolume& tooth, ExportRegion region = ExportRegion::Auto);

}  // namespace dentsim
