#!/usr/bin/env python3
"""Makes hostile input files for every dentsim reader, runs dentsim on each under /usr/bin/time -v,
and prints the table of docs/RELIABILITY.md: each case's exit code, max RSS, elapsed time and first
line of output. Every input is under 10 MB; the budget is 1 GB and 30 s for each.

    scripts/hostile-inputs.py [--dentsim build/src/app/dentsim] [--keep DIR] [--only READER[,READER...]]

Needs gzip and zstd on PATH. Generating the bombs streams gigabytes of zeros through gzip and zstd,
which takes a minute or so; nothing is held in memory.

The scan readers' cases (dicom, nrrd, nifti) and the learning records' (learning) are also checked for
what dentsim must do with them: a refusal is one line and an exit code of 1 to 123 (not a signal,
not the timeout), and no credential reaches stdout or stderr. A failed check is listed after the
table, and the script exits 1, as it does when a case is over the budget.
"""
import argparse
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile

BUDGET_RSS_MB = 1000.0  # [MB]
BUDGET_S = 30.0  # [s]
SAFETY_TIMEOUT_S = 120  # a hung case is killed and reported, never waited on for ever


# ---- file makers -------------------------------------------------------------------------------

def write(path, data):
    with open(path, "wb") as f:
        f.write(data)
    return path


def piped_zeros(path, count, compressor, header=b""):
    """`header`, then `count` zero bytes, through a compressor, streamed."""
    with open(path, "wb") as out:
        p = subprocess.Popen(compressor, stdin=subprocess.PIPE, stdout=out)
        p.stdin.write(header)
        block = bytes(1 << 20)
        left = count
        while left > 0:
            n = min(left, len(block))
            p.stdin.write(block[:n])
            left -= n
        p.stdin.close()
        p.wait()
    return path


def nifti_header(dims, datatype, bitpix):
    h = bytearray(352)
    struct.pack_into("<i", h, 0, 348)
    struct.pack_into("<8h", h, 40, 3, dims[0], dims[1], dims[2], 1, 1, 1, 1)
    struct.pack_into("<hh", h, 70, datatype, bitpix)
    struct.pack_into("<8f", h, 76, 1, 0.034, 0.034, 0.034, 1, 1, 1, 1)
    struct.pack_into("<f", h, 108, 352.0)  # vox_offset
    h[123] = 2  # mm
    h[344:348] = b"n+1\0"
    return bytes(h)


def nifti_gz(path, dims, datatype, bitpix, zeros_bytes):
    """A .nii.gz of a header then zeros, compressed as it streams."""
    return piped_zeros(path, zeros_bytes, ["gzip", "-9", "-c"], nifti_header(dims, datatype, bitpix))


# DICOM as dentsim's writer makes it: explicit VR little endian after the 128-byte preamble and "DICM".
DICOM_LONG_VRS = {b"OB", b"OD", b"OF", b"OL", b"OV", b"OW", b"SQ", b"SV", b"UC", b"UN", b"UR", b"UT", b"UV"}


def dicom_elements(data):
    """A flat file's elements, in order, as [(group, element, VR, value)]."""
    at, out = 132, []
    while at < len(data):
        group, element = struct.unpack_from("<HH", data, at)
        vr = data[at + 4:at + 6]
        if vr in DICOM_LONG_VRS:
            length, at = struct.unpack_from("<I", data, at + 8)[0], at + 12
        else:
            length, at = struct.unpack_from("<H", data, at + 6)[0], at + 8
        out.append((group, element, vr, data[at:at + length]))
        at += length
    return out


def dicom_element(group, element, vr, value):
    if len(value) % 2:
        value += b"\0" if vr == b"UI" else b" "
    if vr in DICOM_LONG_VRS:
        return struct.pack("<HH", group, element) + vr + b"\0\0" + struct.pack("<I", len(value)) + value
    return struct.pack("<HH", group, element) + vr + struct.pack("<H", len(value)) + value


def dicom_edit(path, changes=None, insert=b""):
    """Rewrites a slice with some elements' values changed ({(group, element): value}) and `insert`
    (encoded elements) placed before the first element after (0008,1140)."""
    data = open(path, "rb").read()
    out, inserted = bytearray(data[:132]), not insert
    for group, element, vr, value in dicom_elements(data):
        if not inserted and (group, element) > (0x0008, 0x1140):
            out += insert
            inserted = True
        out += dicom_element(group, element, vr, (changes or {}).get((group, element), value))
    write(path, bytes(out))


def nested_sequence(depth):
    """(0008,1140) sequences nested `depth` deep, each in one item, all of undefined length."""
    body = dicom_element(0x0008, 0x1150, b"UI", b"1.2.840.10008.5.1.4.1.1.2")
    for _ in range(depth):
        item = struct.pack("<HHI", 0xFFFE, 0xE000, 0xFFFFFFFF) + body + struct.pack("<HHI", 0xFFFE, 0xE00D, 0)
        body = (struct.pack("<HH", 0x0008, 0x1140) + b"SQ\0\0" + struct.pack("<I", 0xFFFFFFFF) + item
                + struct.pack("<HHI", 0xFFFE, 0xE0DD, 0))
    return body


def dicom_series_copy(good, path):
    shutil.rmtree(path, ignore_errors=True)
    shutil.copytree(good, path)
    return sorted(os.path.join(path, n) for n in os.listdir(path))


def label_nifti(path):
    """A 12 x 10 x 6 uint8 label volume of 0.2 mm voxels with a block of label 2: make-scan's input."""
    n = (12, 10, 6)
    labels = bytes(2 if 2 <= i < 10 and 2 <= j < 8 and 1 <= k < 5 else 0
                   for k in range(n[2]) for j in range(n[1]) for i in range(n[0]))
    h = bytearray(nifti_header(n, 2, 8))
    struct.pack_into("<3f", h, 80, 0.2, 0.2, 0.2)
    return write(path, bytes(h) + labels)


def ascii_stl_giant_token(path, size):
    with open(path, "wb") as f:
        f.write(b"solid x\nfacet normal 0 0 1\nouter loop\nvertex ")
        f.write(b"9" * (size - 64))
        f.write(b"\n")
    return path


def binary_stl(path, triangles, claimed=None):
    import random
    rng = random.Random(27)
    with open(path, "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", triangles if claimed is None else claimed))
        for _ in range(triangles):
            v = [rng.uniform(-5, 5) for _ in range(9)]
            f.write(struct.pack("<12fH", 0, 0, 0, *v, 0))
    return path


def deep_json(path, depth):
    write(path, b'{"a":' * depth + b"1" + b"}" * depth)
    return path


def wav_claiming(path, samples_claimed, real_bytes):
    h = b"RIFF" + struct.pack("<I", 36 + samples_claimed * 2) + b"WAVEfmt " + struct.pack(
        "<IHHIIHH", 16, 1, 1, 44100, 88200, 2, 16) + b"data" + struct.pack("<I", samples_claimed * 2)
    write(path, h + bytes(real_bytes))
    return path


# ---- running -----------------------------------------------------------------------------------

def run_case(cmd, cwd, env=None):
    # time's report goes to a file of its own: its "Command being timed" line repeats the command,
    # which must not count as dentsim printing what is on its command line.
    with tempfile.NamedTemporaryFile("r", prefix="dentsim-hostile-time-") as timing:
        full = ["/usr/bin/time", "-v", "-o", timing.name, "timeout", str(SAFETY_TIMEOUT_S)] + cmd
        p = subprocess.run(full, cwd=cwd, capture_output=True, text=True, errors="replace", env=env)
        err = p.stderr + timing.read()
    rss_kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", err).group(1))
    el = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([\d:.]+)", err).group(1)
    parts = [float(x) for x in el.split(":")]
    seconds = parts[-1] + 60 * parts[-2] + (3600 * parts[-3] if len(parts) > 2 else 0)
    lines = [l for l in (p.stdout + err).splitlines() if l.strip() and not l.startswith("\t")
             and not l.startswith("Command ") and "Command being timed" not in l]
    first = next((l for l in lines if l.startswith("dentsim:")), lines[0] if lines else "")
    return p.returncode, rss_kb / 1024.0, seconds, first, lines, p.stdout + p.stderr


# ---- checks: what dentsim must do with a case, beyond the budget -----------------------------------
# Each takes (exit code, dentsim's output lines) and returns what is wrong, or None.

def refused(code, lines):
    """One line, and an exit code dentsim chose: 124 is the timeout's, 125 and above a signal's."""
    if not 1 <= code <= 123:
        return f"exit {code}, not a refusal (1..123)"
    if len(lines) != 1:
        return f"{len(lines)} lines, not one: " + " / ".join(lines[:4])[:200]
    if not lines[0].startswith("dentsim: "):
        return "the line does not start 'dentsim: '"
    return None


def refused_saying(*words):
    """refused, and the line says each of `words` (the problem is named, not a generic failure)."""
    def check(code, lines):
        problem = refused(code, lines)
        missing = [w for w in words if not problem and w not in lines[0]]
        return problem or (f"the line does not say '{missing[0]}'" if missing else None)
    return check


def recorded_with_one_warning(outbox):
    """Exit 0, exactly one warning (the bad line moved aside), and the statement in the outbox."""
    def check(code, lines):
        warnings = [l for l in lines if "warning" in l]
        if code != 0:
            return f"exit {code}: a bad outbox line must not stop the score from being recorded"
        if len(warnings) != 1 or ".bad" not in warnings[0]:
            return f"{len(warnings)} warning lines, not one naming the .bad file"
        if not os.path.exists(outbox + ".bad") or '"actor"' not in open(outbox).read():
            return "the bad line was not moved aside, or the new statement is not in the outbox"
        return None
    return check


def sent_nowhere(code, lines):
    """An LRS that does not answer: the score is still written (exit 0 for score, 1 for outbox send)."""
    return None if code in (0, 1) else f"exit {code}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dentsim", default=os.path.join(os.path.dirname(__file__), "..", "build", "src", "app", "dentsim"))
    ap.add_argument("--keep", help="make the files in this folder and keep them")
    ap.add_argument("--only", help="run only these readers' cases, comma-separated (json, dvol, nifti, stl, voxelizer, wav, pen, dicom, nrrd, learning)")
    ap.add_argument("--skip", action="append", help="leave this reader's cases out (repeatable; e.g. voxelizer, whose case runs into the 120 s timeout)")
    a = ap.parse_args()
    dentsim = os.path.abspath(a.dentsim)
    work = a.keep or tempfile.mkdtemp(prefix="dentsim-hostile-")
    os.makedirs(work, exist_ok=True)
    f = lambda name: os.path.join(work, name)
    out = f("out")
    os.makedirs(out, exist_ok=True)

    # A real small tooth, and files of each kind to hand to the wrong reader.
    subprocess.run([dentsim, "voxelize", "--tooth", os.path.join(os.path.dirname(dentsim), "..", "..", "..", "..",
                    "shared", "data", "teeth", "chai3d_molar_tooth.stl"), "--cpu", "--level", "7", "-o", f("good.dvol")],
                   capture_output=True)
    write(f("mesh.ply"), b"ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                         b"property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
                         b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    fifo = f("pipe")
    if not os.path.exists(fifo):
        os.mkfifo(fifo)

    cases = []  # (reader, case, cmd, check, secrets, env)
    def case(reader, what, *args, check=None, secrets=(), env=None):
        cases.append((reader, what, [dentsim] + list(args), check, secrets, env))

    # JSON: task and preset files.
    deep_json(f("deep.json"), 100000)
    case("json", "task nested 100 000 deep (600 KB)", "task", "check", f("deep.json"))
    case("json", "preset nested 100 000 deep (600 KB)", "demo", "--headless", "--params", f("deep.json"), "--out", out)
    write(f("unclosed.json"), b'{"name": "' + b"x" * 9_000_000)
    case("json", "task with a 9 MB unclosed string", "task", "check", f("unclosed.json"))
    write(f("brackets.json"), b"[" * 9_000_000)
    case("json", "9 MB of '['", "task", "check", f("brackets.json"))
    # Just under the task reader's 1 MiB file limit, so that the parser itself meets them.
    write(f("unclosed-1M.json"), b'{"name": "' + b"x\x01" * 500_000)
    case("json", "task with a 1 MB unclosed string of control bytes", "task", "check", f("unclosed-1M.json"))
    write(f("brackets-1M.json"), b"[" * 1_000_000)
    case("json", "1 MB of '['", "task", "check", f("brackets-1M.json"))
    case("json", "a FIFO as the task", "task", "check", fifo)

    # .dvol: bombs whose counts or frames claim gigabytes.
    piped_zeros(f("frame-7.9G.zst"), 7_900_000_000, ["zstd", "-1", "-q", "-c", "--stream-size=7900000000"])
    piped_zeros(f("frame-7.9G-unsized.zst"), 7_900_000_000, ["zstd", "-1", "-q", "-c"])
    # Counts just under the budget and a real frame of zeros that fills them: the most a .dvol may
    # cost without the flag (the payload checksum then refuses it).
    raw = dvol_raw(500 << 20)
    piped_zeros(f("frame-500M.zst"), raw, ["zstd", "-1", "-q", "-c", f"--stream-size={raw}"])
    for name, frame, claim in [("bomb.dvol", "frame-7.9G.zst", 7_900_000_000),
                               ("bomb-unsized.dvol", "frame-7.9G-unsized.zst", 400 << 20),
                               ("full-500M.dvol", "frame-500M.zst", 500 << 20),
                               ("full-500M-hashed.dvol", "frame-500M.zst", -(500 << 20))]:
        # The tool rewrites the counts and fixes the header checksum itself.
        subprocess.run([sys.executable, __file__, "--forge-dvol", f("good.dvol"), f(frame), str(claim), f(name)], check=True)
    case("dvol", "header claims 7.9 GB of bricks; 7.9 GB zstd frame", "info", f("bomb.dvol"))
    case("dvol", "header claims 400 MiB; frame of unknown size inflating to 7.9 GB", "info", f("bomb-unsized.dvol"))
    case("dvol", "header claims 500 MiB (under the budget); frame of 500 MiB of zeros", "info", f("full-500M.dvol"))
    case("dvol", "the same with its payload checksum right (the volume's own checks then run)", "info",
         f("full-500M-hashed.dvol"))
    case("dvol", "a PLY given as .dvol", "info", f("mesh.ply"))
    case("dvol", "a FIFO given as .dvol", "info", fifo)

    # NIfTI: gzip bombs and a volume of zeros.
    nifti_gz(f("zeros-1G.nii.gz"), (1024, 1024, 1024), 2, 8, 1 << 30)
    nifti_gz(f("zeros-int32-4G.nii.gz"), (1024, 1024, 1024), 8, 32, 4 << 30)
    nifti_gz(f("zeros-int32-576M.nii.gz"), (600, 600, 400), 8, 32, 600 * 600 * 400 * 4)
    for name, what in [("zeros-1G.nii.gz", "1 MB .nii.gz: 1 GiB of uint8 zeros"),
                       ("zeros-int32-4G.nii.gz", "4 MB .nii.gz: 4 GiB of int32 zeros"),
                       ("zeros-int32-576M.nii.gz", "600x600x400 int32 zeros (under the budget, streamed)")]:
        case("nifti", what, "voxelize", "--labels", f(name), "--label-map", "1=enamel", "-o", f("n.dvol"))
    case("nifti", "a FIFO as labels", "voxelize", "--labels", fifo, "--label-map", "1=enamel", "-o", f("n.dvol"))

    # STL.
    binary_stl(f("claim-20M.stl"), 4, claimed=20_000_000)
    case("stl", "284 bytes claiming 20 000 000 triangles", "voxelize", "--tooth", f("claim-20M.stl"), "--cpu", "--level", "7", "-o", f("s.dvol"))
    binary_stl(f("big.stl"), 199_000)
    # Level 3 (an 8^3 grid), so that the reader, welding and the topology report are what is measured.
    case("stl", "9.9 MB binary STL of 199 000 random triangles (level 3)", "voxelize", "--tooth", f("big.stl"), "--cpu", "--level", "3", "-o", f("s.dvol"))
    ascii_stl_giant_token(f("token.stl"), 9_900_000)
    case("stl", "9.9 MB ASCII STL, one giant number", "voxelize", "--tooth", f("token.stl"), "--cpu", "--level", "7", "-o", f("s.dvol"))
    shutil.copyfile(f("mesh.ply"), f("mesh-ply.stl"))
    case("stl", "a PLY named .stl", "voxelize", "--tooth", f("mesh-ply.stl"), "--cpu", "--level", "7", "-o", f("s.dvol"))
    case("stl", "a one-triangle PLY (no tooth inside)", "voxelize", "--tooth", f("mesh.ply"), "--cpu", "--level", "7", "-o", f("s.dvol"))
    case("stl", "a .nii.gz as STL", "voxelize", "--tooth", f("zeros-1G.nii.gz"), "--cpu", "--level", "7", "-o", f("s.dvol"))
    case("stl", "a .dvol as STL", "voxelize", "--tooth", f("good.dvol"), "--cpu", "--level", "7", "-o", f("s.dvol"))
    case("stl", "a FIFO as STL", "voxelize", "--tooth", fifo, "--cpu", "--level", "7", "-o", f("s.dvol"))

    # DICOM series: a small phantom scan from dentsim's own writer, each case damaging a copy of it.
    # Read by voxelize --dicom; the checking child (io/dicom_series.h) must turn each into a line.
    label_nifti(f("phantom-labels.nii"))
    good_scan = f("scan-good")
    shutil.rmtree(good_scan, ignore_errors=True)
    subprocess.run([dentsim, "make-scan", "--labels", f("phantom-labels.nii"), "--label-map", "2=enamel",
                    "--noise-hu", "0", "-o", good_scan], check=True, capture_output=True)
    scan = ["--level", "3", "-o", f("d.dvol")]
    for name, what, cut in [("scan-cut-header", "a slice cut at 60 %, before its Pixel Data", lambda n: n * 6 // 10),
                            ("scan-cut-pixels", "a slice cut 100 bytes short, in its Pixel Data", lambda n: n - 100)]:
        slices = dicom_series_copy(good_scan, f(name))
        data = open(slices[2], "rb").read()
        write(slices[2], data[:cut(len(data))])
        case("dicom", what, "voxelize", "--dicom", f(name), *scan, check=refused)
    for name, what, changes in [
            ("scan-rows", "every slice's Rows forged to 65535", {(0x0028, 0x0010): struct.pack("<H", 65535)}),
            ("scan-spacing", "Pixel Spacing 1e15 mm", {(0x0028, 0x0030): b"1e15\\1e15"})]:
        for path in dicom_series_copy(good_scan, f(name)):
            dicom_edit(path, changes)
        case("dicom", what, "voxelize", "--dicom", f(name), *scan, check=refused)
    for n, path in enumerate(dicom_series_copy(good_scan, f("scan-mixed"))):
        if n % 2:
            dicom_edit(path, {(0x0008, 0x0060): b"MR"})
    case("dicom", "Modality MR and CT in one series", "voxelize", "--dicom", f("scan-mixed"), *scan,
         check=refused_saying("mixed"))
    slices = dicom_series_copy(good_scan, f("scan-nested"))
    dicom_edit(slices[3], insert=nested_sequence(100))
    case("dicom", "one slice with sequences nested 100 deep", "voxelize", "--dicom", f("scan-nested"), *scan,
         check=refused)

    # NRRD headers (voxelize --ct): a data file format Teem would hand to sprintf, and a FIFO that
    # would block Teem hidden behind 10 000 comments or as the 10 401st of 10 500 listed files.
    nrrd_head = b"NRRD0004\ntype: short\ndimension: 3\nsizes: 4 3 2\nendian: little\nencoding: raw\n"
    ct = ["--dentin-above", "0", "--level", "3", "-o", f("c.dvol")]
    for name, what, fmt in [("format-n.nhdr", "data file format with %n", b"x%n%n%n%n.raw 1 2 1"),
                            ("format-s.nhdr", "data file format with %s", b"x%s%s%s.raw 1 2 1")]:
        write(f(name), nrrd_head + b"data file: " + fmt + b"\n\n")
        case("nrrd", what, "voxelize", "--ct", f(name), *ct, check=refused)
    write(f("comments.nhdr"), nrrd_head + b"# comment\n" * 10000 + b"data file: pipe\n\n")
    case("nrrd", "10 000 comment lines, then a FIFO as the data file", "voxelize", "--ct", f("comments.nhdr"), *ct,
         check=refused_saying("FIFO"))
    listed = f("listed")
    os.makedirs(listed, exist_ok=True)
    if not os.path.exists(os.path.join(listed, "pipe")):
        os.mkfifo(os.path.join(listed, "pipe"))
    names = []
    for n in range(1, 10501):
        names.append(b"pipe" if n == 10401 else b"s%d.raw" % n)
        if n != 10401:
            write(os.path.join(listed, "s%d.raw" % n), b"")
    write(os.path.join(listed, "list.nhdr"), nrrd_head.replace(b"sizes: 4 3 2", b"sizes: 4 3 10500")
          + b"data file: LIST\n" + b"\n".join(names) + b"\n")
    case("nrrd", "a LIST of 10 500 data files, the 10 401st a FIFO", "voxelize", "--ct",
         os.path.join(listed, "list.nhdr"), *ct, check=refused_saying("FIFO"))

    # NIfTI headers whose dims are forged, as labels and as grey values.
    for name, what, dims in [("dims-huge.nii", "dims 32767^3 int16 in a 400 B file", (32767, 32767, 32767)),
                             ("dims-negative.nii", "a negative dim", (4, -3, 2)),
                             ("dims-zero.nii", "a zero dim", (4, 0, 2))]:
        write(f(name), nifti_header(dims, 4, 16) + bytes(48))
        case("nifti", what + " (labels)", "voxelize", "--labels", f(name), "--label-map", "1=enamel",
             "-o", f("n.dvol"), check=refused)
        case("nifti", what + " (grey values)", "voxelize", "--ct", f(name), *ct, check=refused)

    # Learning records: a damaged outbox line must not stop recording; a password in the LRS's URL
    # is never printed. HOME is the work folder, so that no user's config or outbox is touched.
    home = f("home")
    os.makedirs(home, exist_ok=True)
    learning_env = dict(os.environ, HOME=home)
    learning_env.pop("DENTSIM_CONFIG", None)
    score = ["score", "--task", "caries", "--initial", f("good.dvol"), "--final", f("good.dvol"),
             "-o", f("out/score.json"), "--student", "bob"]
    write(f("outbox-bad.jsonl"), b'{"id": "half a statement\n')
    case("learning", "an outbox with a bad line, then score --student", *score, "--outbox", f("outbox-bad.jsonl"),
         check=recorded_with_one_warning(f("outbox-bad.jsonl")), env=learning_env)
    secret_url = "http://bob:PW-40-secret@127.0.0.1:9/?token=PW-40-token#PW-40-fragment"
    secrets = ("PW-40-secret", "PW-40-token", "PW-40-fragment")
    case("learning", "score --lrs with a password in the URL (no LRS listening)", *score,
         "--outbox", f("outbox-pw.jsonl"), "--lrs", secret_url, check=sent_nowhere, secrets=secrets, env=learning_env)
    case("learning", "outbox send --lrs with a password in the URL", "outbox", "send", "--outbox",
         f("outbox-pw.jsonl"), "--lrs", secret_url, check=sent_nowhere, secrets=secrets, env=learning_env)
    write(f("learning.json"), b'{"lrs": "' + secret_url.encode() + b'", "oops": }')
    case("learning", "a config whose LRS URL has a password, and a JSON error after it", *score,
         "--config", f("learning.json"), "--outbox", f("outbox-pw.jsonl"), check=sent_nowhere, secrets=secrets,
         env=learning_env)

    # Not the reader's: the CPU voxelizer on the same file at level 7 (reported to its owner).
    case("voxelizer", "the same 9.9 MB STL at level 7 (CPU voxelizer)", "voxelize", "--tooth", f("big.stl"), "--cpu", "--level", "7", "-o", f("s.dvol"))

    # WAV and pen paths: read by `run` while it sets up (a headless run reads the WAV only when it
    # renders the sound, hence --audio-out).
    wav_claiming(f("claim.wav"), 1 << 30, 1000)
    run = ["run", "--headless", "--level", "7", "--exit-after", "0.05", "--out", out, "--audio-out", f("out/s.wav")]
    case("wav", "WAV claiming 2 GiB of samples in 1 KB", *run, "--turbine-wav", f("claim.wav"))
    case("wav", "a .dvol as WAV", *run, "--turbine-wav", f("good.dvol"))
    case("wav", "a FIFO as WAV", *run, "--turbine-wav", fifo)
    write(f("pen.csv"), b"t_s,pen,x_mm,y_mm,z_mm,qw,qx,qy,qz,buttons,pedal\n" + b"0," * 3_000_000)
    case("pen", "6 MB pen path: the header, then one row of 3 000 000 fields", *run, "--pen-script", f("pen.csv"))
    case("pen", "a .nii.gz as pen path", *run, "--pen-script", f("zeros-1G.nii.gz"))
    case("pen", "a FIFO as pen path", *run, "--pen-script", fifo)

    print("| reader | hostile case | input [B] | exit | max RSS [MB] | elapsed [s] | first line |")
    print("|---|---|---|---|---|---|---|")
    over = 0
    failed, checked = [], 0
    for reader, what, cmd, check, secrets, env in cases:
        if (a.only and reader not in a.only.split(",")) or reader in (a.skip or []):
            continue
        inputs = [x for i, x in enumerate(cmd[1:]) if x.startswith(work) and not os.path.isdir(x)
                  and cmd[i] not in ("-o", "--out", "--audio-out")]
        size = max((os.path.getsize(x) for x in inputs if os.path.isfile(x)), default=0)
        code, rss, secs, first, lines, output = run_case(cmd, work, env)
        over += rss > BUDGET_RSS_MB or secs > BUDGET_S
        if check:
            checked += 1
            problem = check(code, lines) or next((f"prints the credential '{x}'" for x in secrets if x in output), None)
            if problem:
                failed.append(f"{reader}: {what}: {problem}")
        first = first.replace(work + "/", "").replace("|", "\\|")
        if len(first) > 140:
            first = first[:140] + "..."
        print(f"| {reader} | {what} | {size} | {code} | {rss:.0f} | {secs:.2f} | `{first}` |", flush=True)
    print(f"\n{checked} cases checked for their outcome: " + ("all pass" if not failed else f"{len(failed)} FAIL"))
    for line in failed:
        print("  FAIL " + line)
    if not a.keep:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if over or failed else 0


def dvol_raw(claimed_raw):
    """The raw payload bytes of a forged level-13 file whose brick pool claims about claimed_raw."""
    return 4 * (128 ** 3 + 512 + dvol_bricks(claimed_raw))


def dvol_bricks(claimed_raw):
    return (claimed_raw - 4 * 128 ** 3) // 4 // 128 * 128


def forge_dvol(good_path, frame_path, claimed_raw, out_path):
    """Rewrites a real .dvol's header to claim `claimed_raw` bytes of bricks (at level 13) and puts
    the frame after it, with the header checksum made right: the reader must refuse it on its
    counts, or stop its frame, not trip over a checksum first."""
    import ctypes
    import ctypes.util
    lib = ctypes.CDLL(ctypes.util.find_library("xxhash") or "libxxhash.so.0")
    lib.XXH64.restype = ctypes.c_uint64
    lib.XXH64.argtypes = [ctypes.c_char_p, ctypes.c_size_t, ctypes.c_uint64]
    # A negative claim: also make the payload checksum right, for a raw payload of zeros.
    zeros_hashed = claimed_raw < 0
    claimed_raw = abs(claimed_raw)
    h = bytearray(open(good_path, "rb").read()[:352])
    frame = open(frame_path, "rb").read()
    struct.pack_into("<i", h, 16, 13)
    struct.pack_into("<Q", h, 176, 128 ** 3)  # the chunk table of level 13
    bricks = dvol_bricks(claimed_raw)
    struct.pack_into("<Q", h, 184, 512)
    struct.pack_into("<Q", h, 192, bricks)
    struct.pack_into("<Q", h, 200, len(frame))
    if zeros_hashed:
        lib.XXH64_createState.restype = ctypes.c_void_p
        lib.XXH64_reset.argtypes = [ctypes.c_void_p, ctypes.c_uint64]
        lib.XXH64_update.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_size_t]
        lib.XXH64_digest.argtypes = [ctypes.c_void_p]
        lib.XXH64_digest.restype = ctypes.c_uint64
        state = lib.XXH64_createState()
        lib.XXH64_reset(state, 0)
        block = bytes(1 << 20)
        left = dvol_raw(claimed_raw)
        while left > 0:
            n = min(left, len(block))
            lib.XXH64_update(state, block, n)
            left -= n
        struct.pack_into("<Q", h, 208, lib.XXH64_digest(state))
    struct.pack_into("<Q", h, 216, lib.XXH64(bytes(h[:216]), 216, 0))
    write(out_path, bytes(h) + frame)


if __name__ == "__main__":
    if len(sys.argv) == 6 and sys.argv[1] == "--forge-dvol":
        forge_dvol(sys.argv[2], sys.argv[3], int(sys.argv[4]), sys.argv[5])
        sys.exit(0)
    sys.exit(main())
