// Surface files with tissue colours (STL or PLY) for `dentsim mesh` and `dentsim demo`.
#include "app/mesh_output.h"

#include <algorithm>
#include <vector>

#include "io/stl_file.h"
#include "volume/tissue_table.h"
#include "volume/tooth_frame.h"

namespace dentsim::app {

bool meshFormatOf(const std::string& path, MeshFormat* format) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return false;
  std::string ext = path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](char c) { return c >= 'A' && c <= 'Z' ? char(c - 'A' + 'a') : c; });
  if (ext == "stl") *format = MeshFormat::Stl;
  else if (ext == "ply") *format = MeshFormat::Ply;
  else return false;
  return true;
}

// Vertex colours per tissue from the tissue table's mesh_rgb; grey for anything else (the spare codes).
Rgb8 tissueColour(Material m) {
  const TissueRow* row = findTissue(m);
  if (!row) return {128, 128, 128};
  return {row->mesh_rgb[0], row->mesh_rgb[1], row->mesh_rgb[2]};
}

Status writeSurface(const std::string& path, MeshFormat format, const SurfaceMesh& in_simulation, const VolumeFrame& frame,
                    const std::string& label) {
  SurfaceMesh turned_back;
  if (frame.tooth.turned()) {
    turned_back = in_simulation;
    for (Vec3f& p : turned_back.positions) {
      const Vec3 q = sourcePointMm(frame, Vec3{p[0], p[1], p[2]});
      p = {float(q.x), float(q.y), float(q.z)};
    }
    for (Vec3f& n : turned_back.normals) {
      const Vec3 q = sourceDirection(frame, Vec3{n[0], n[1], n[2]});
      n = {float(q.x), float(q.y), float(q.z)};
    }
  }
  const SurfaceMesh& surface = frame.tooth.turned() ? turned_back : in_simulation;
  if (format == MeshFormat::Stl) return writeStl(path, surface.geometry(), "dentsim mesh " + label);
  std::vector<Rgb8> colours(surface.tissue.size());
  std::transform(surface.tissue.begin(), surface.tissue.end(), colours.begin(), tissueColour);
  return writePly(path, PlyView{surface.positions, surface.normals, colours, surface.triangles}, "dentsim mesh " + label);
}

}  // namespace dentsim::app
