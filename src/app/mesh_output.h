// Writing a tooth's surface as STL or PLY with tissue colours: shared by `dentsim mesh` and `dentsim demo`.
#pragma once

#include <string>

#include "core/result.h"
#include "io/ply_file.h"
#include "volume/brick_volume.h"
#include "volume/surface_mesher.h"

namespace dentsim::app {

enum class MeshFormat { Stl, Ply };

// The output format from the extension, case-insensitively; false for anything else.
bool meshFormatOf(const std::string& path, MeshFormat* format);
// Vertex colour of a tissue.
Rgb8 tissueColour(Material m);
// Writes `surface`, meshed from a volume with `frame`, atomically, in the source's own frame (undoing
// the quarter turn voxelize stood the tooth up with, so the mesh overlays the source in other
// tools); `label` goes into the file's header or comment.
Status writeSurface(const std::string& path, MeshFormat format, const SurfaceMesh& surface, const VolumeFrame& frame,
                    const std::string& label);

}  // namespace dentsim::app
