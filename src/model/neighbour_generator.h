// The built-in molar's two neighbours in the arch: a lower second premolar mesially and a lower second molar distally, each one closed outward mesh of its outer surface.
//
// Frame: the molar's (model/molar_generator.h, mm, mesial -x, buccal -y, crown +z, CEJ at z = 0).
// The neighbours stand on the molar's mesiodistal line, as a straight stretch of a lower arch, their
// CEJs at z = 0, each at its contact with the molar: the proximal heights of contour, where the
// middle third meets the occlusal third (z about 3.5 to 4.5), with a gap of about kContactGapMm
// between the surfaces (tests/model/neighbour_generator_test.cpp measures it), as a contact that a
// strip of floss passes.
//
// A neighbour is one tissue in the simulation (Material::Neighbour, the tissue table): whole, not
// treated, only in the way. So each is one surface, the whole tooth's, and has no inner layers.
//
// Entry points:
//   generateNeighbours()   the two meshes, welded, closed and outward, deterministic
//   kNeighbourTeeth        the neighbours by name, with their asset file's description
//   premolarToothField() / secondMolarToothField()   their fields, negative inside [mm]
#pragma once

#include "core/triangle_mesh.h"

namespace dentsim {

// The surfaces meet the molar's this far apart at the contact, by construction [mm].
inline constexpr double kContactGapMm = 0.1;

struct NeighbourTeeth {
  TriangleMesh premolar;      // lower second premolar, mesial of the molar: one root, two cusps [mm]
  TriangleMesh second_molar;  // lower second molar, distal of it: the first molar's shape at 94% [mm]
};

// The neighbours, one row each, mesial first.
struct NeighbourRow {
  const char* name;                    // "premolar": the asset is teeth/neighbour_premolar.stl
  TriangleMesh NeighbourTeeth::*mesh;  // the mesh in NeighbourTeeth
  const char* description;             // what the mesh is, for the asset's STL header
};
inline constexpr NeighbourRow kNeighbourTeeth[] = {
    {"premolar", &NeighbourTeeth::premolar, "lower second premolar, the molar's mesial neighbour"},
    {"second_molar", &NeighbourTeeth::second_molar, "lower second molar, the molar's distal neighbour"},
};

struct NeighbourOptions {
  // Lattice spacing [mm]. Coarser than the molar's 0.27: a neighbour is only seen and bumped, never
  // prepared, and the assets stay small (about 39k triangles for both, 2 MB).
  double grid_mm = 0.45;
};

// Samples each field on its own lattice and extracts the surface by marching tetrahedra;
// bit-identical on every run and build, as generateMolar().
NeighbourTeeth generateNeighbours(const NeighbourOptions& options = {});

// The fields in the molar's frame, negative inside and roughly a distance [mm] near the surface.
double premolarToothField(const Vec3d& p);
double secondMolarToothField(const Vec3d& p);

// The boxes that hold them, with a margin [mm].
Bounds3 premolarBounds();
Bounds3 secondMolarBounds();

}  // namespace dentsim
