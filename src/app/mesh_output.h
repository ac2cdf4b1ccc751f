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
// Writes `surface` atomically; `label` goes into the file's header or comment.
Status writeSurface(const std::string& path, MeshFormat format, const SurfaceMesh& surface, const std::string& label);

}  // namespace dentsim::app
