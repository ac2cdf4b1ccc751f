#!/usr/bin/env python3
"""Writes the shared micro-CT molar tooth_2 as four STL layers (enamel, dentin, caries, pulp), lying on its side with the crown toward -y.

This is how a teacher's own tooth often arrives: surface layers from a segmentation program, in
whatever orientation the scan had. The README's exercise walkthrough starts from these files.
Usage: scripts/ct-molar-layers.py DENTSIM_BINARY DATA_DIR OUT_DIR
"""
import os
import struct
import subprocess
import sys


def turn_crown_to_minus_y(path):
    # The label grid holds the crown toward +x; a quarter turn about z, (x, y, z) -> (y, -x, z),
    # puts it toward -y. Binary STL: 80-byte header, a count, then 50 bytes per triangle.
    with open(path, "rb") as f:
        data = bytearray(f.read())
    (count,) = struct.unpack_from("<I", data, 80)
    for t in range(count):
        at = 84 + 50 * t
        for v in range(4):  # the normal, then the three corners
            x, y, z = struct.unpack_from("<3f", data, at + 12 * v)
            struct.pack_into("<3f", data, at + 12 * v, y, -x, z)
    with open(path, "wb") as f:
        f.write(data)


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__.strip().splitlines()[-1])
    dentsim, data, out = sys.argv[1:]
    os.makedirs(out, exist_ok=True)
    grid = os.path.join(out, "tooth_2_labels.dvol")
    subprocess.run([dentsim, "voxelize", "--labels", os.path.join(data, "ct", "tooth_2.nii.gz"),
                    "--label-map", "1=caries,2=enamel,3=dentin", "--voxel-size", "0.034", "--level", "8",
                    # The labels have no pulp: the space the dentin encloses is it, as a segmentation
                    # program's pulp layer would be.
                    "--fill-enclosed", "pulp",
                    "--keep-orientation", "-o", grid], check=True, stdout=subprocess.DEVNULL)
    for tissue in ("enamel", "dentin", "caries", "pulp"):
        stl = os.path.join(out, "ct_molar_" + tissue + ".stl")
        subprocess.run([dentsim, "mesh", grid, "--tissue", tissue, "--cpu", "-o", stl], check=True,
                       stdout=subprocess.DEVNULL)
        turn_crown_to_minus_y(stl)
        print("wrote", stl)
    os.remove(grid)


if __name__ == "__main__":
    main()
