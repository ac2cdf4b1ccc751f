#!/usr/bin/env python3
"""Writes the scan readers' fuzz seeds (tests/fuzz/corpus/<fuzzer>/): a few small valid files each.

    tests/fuzz/corpus/make-seeds.py [--dicom-seeds build-fuzz/tests/fuzz/dicom_fuzz_seeds]

The DICOM seeds come from the project's own writer (dicom_fuzz_seeds, built with the fuzz preset),
as they must join the fuzzer's series; the NRRD, NIfTI and STL seeds are written here byte by byte.
Re-run it when a reader learns a new feature worth seeding; the files are committed as written.
"""
import argparse
import os
import struct
import subprocess
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def write(fuzzer, name, data):
    os.makedirs(os.path.join(HERE, fuzzer), exist_ok=True)
    with open(os.path.join(HERE, fuzzer, name), "wb") as f:
        f.write(data)


def shorts(n):
    """n int16 values, a ramp with negatives, little endian."""
    return struct.pack(f"<{n}h", *[(v * 37) % 2000 - 1000 for v in range(n)])


def nrrd_seeds():
    # The fuzzer writes its input to /tmp/dentsim-nrrd-fuzz-PID.nrrd: attached data reads whole;
    # a detached header names files that are not there, which still runs the data-file checks.
    head = "NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nendian: little\n"
    write("nrrd_fuzzer", "attached-raw.nrrd", (head + "encoding: raw\n\n").encode() + shorts(24))
    write("nrrd_fuzzer", "attached-space.nrrd",
          ("NRRD0004\n# a comment\ntype: short\ndimension: 3\nspace: left-posterior-superior\nsizes: 4 3 2\n"
           "space directions: (0,0.5,0) (0.25,0,0) (0,0,-2)\nspace origin: (1,2,3)\nendian: little\n"
           "encoding: raw\n\n").encode() + shorts(24))
    write("nrrd_fuzzer", "attached-ascii-um.nrrd",
          ("NRRD0004\ntype: float\ndimension: 3\nspace: RAS\nsizes: 2 2 2\nspace units: \"um\" \"um\" \"um\"\n"
           "space directions: (34,0,0) (0,34,0) (0,0,68)\nencoding: ascii\n\n"
           "0 1.5 -2 3\n4 5 6 7e2\n").encode())
    gz = zlib.compressobj(9, zlib.DEFLATED, 31)  # gzip framing, as Teem's gzip encoding
    write("nrrd_fuzzer", "attached-gzip.nrrd",
          (head + "spacings: 0.2 0.2 0.4\nencoding: gzip\n\n").encode() + gz.compress(shorts(24)) + gz.flush())
    write("nrrd_fuzzer", "detached-one.nhdr", (head + "encoding: raw\ndata file: scan.raw\n\n").encode())
    write("nrrd_fuzzer", "detached-format.nhdr", (head + "encoding: raw\ndata file: slice%03d.raw 1 2 1 2\n\n").encode())
    write("nrrd_fuzzer", "detached-list.nhdr",
          (head + "encoding: raw\ndata file: LIST 2\nslice-a.raw\nslice-b.raw\n").encode())


def nifti(dims, datatype, bitpix, data, slope=0.0, inter=0.0, pixdim=(0.034, 0.034, 0.034)):
    """A single-file NIfTI-1 (.nii): 348-byte header, 4 bytes of extension flag, then the data."""
    h = bytearray(352)
    struct.pack_into("<i", h, 0, 348)
    struct.pack_into("<8h", h, 40, 3, dims[0], dims[1], dims[2], 1, 1, 1, 1)
    struct.pack_into("<hh", h, 70, datatype, bitpix)
    struct.pack_into("<8f", h, 76, 1, *pixdim, 1, 1, 1, 1)
    struct.pack_into("<f", h, 108, 352.0)  # vox_offset
    struct.pack_into("<ff", h, 112, slope, inter)
    h[123] = 2  # xyzt_units: mm
    struct.pack_into("<hh", h, 252, 0, 1)  # qform_code 0, sform_code 1
    struct.pack_into("<12f", h, 280, pixdim[0], 0, 0, 0, 0, pixdim[1], 0, 0, 0, 0, pixdim[2], 0)
    h[344:348] = b"n+1\0"
    return bytes(h) + data


def nifti_seeds():
    labels = bytes((i * 7) % 4 for i in range(4 * 3 * 2))
    write("nifti_fuzzer", "labels-uint8.nii", nifti((4, 3, 2), 2, 8, labels))
    write("nifti_fuzzer", "labels-int16.nii", nifti((4, 3, 2), 4, 16, struct.pack("<24h", *labels)))
    write("nifti_fuzzer", "labels-scaled-float.nii",
          nifti((2, 2, 2), 16, 32, struct.pack("<8f", 0, 1, 2, 3, 0, 1, 2, 3), slope=1.0, inter=0.0, pixdim=(0.5, 0.5, 1)))


def stl_seeds():
    tri = b"solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
    write("stl_fuzzer", "two-triangles-ascii.stl",
          tri + b"facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n")
    body = b"".join(struct.pack("<12fH", 0, 0, 1, *v, 0) for v in
                    [(0, 0, 0, 1, 0, 0, 0, 1, 0), (1, 0, 0, 1, 1, 0, 0, 1, 0)])
    write("stl_fuzzer", "two-triangles-binary.stl", b"\0" * 80 + struct.pack("<I", 2) + body)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dicom-seeds", default=os.path.join(HERE, "..", "..", "..", "build-fuzz", "tests", "fuzz",
                                                          "dicom_fuzz_seeds"))
    a = ap.parse_args()
    nrrd_seeds()
    nifti_seeds()
    stl_seeds()
    subprocess.run([a.dicom_seeds, os.path.join(HERE, "dicom_fuzzer")], check=True)


if __name__ == "__main__":
    main()
