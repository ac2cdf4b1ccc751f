// The VTK peer when dentsim is built without VTK: reports the peer as absent.
#include "bench/peers.h"

namespace dentsim::bench {

PeerMesh vtkFlyingEdges(const BrickVolume&, Material, int) {
  PeerMesh p;
  p.name = "VTK vtkFlyingEdges3D";
  p.skipped = "VTK not installed at build time";
  return p;
}

}  // namespace dentsim::bench
