// The OpenVDB peer when dentsim is built without OpenVDB: reports the peer as absent.
#include "bench/peers.h"

namespace dentsim::bench {

PeerMemory openvdbLabelTreeMemory(const BrickVolume&) {
  PeerMemory p;
  p.name = "OpenVDB (not installed at build time)";
  return p;
}

PeerVoxelize openvdbMeshToVolume(const TriangleMesh&, double, const Vec3d&, VdbInterior) {
  PeerVoxelize p;
  p.name = "OpenVDB (not installed at build time)";
  return p;
}

}  // namespace dentsim::bench
