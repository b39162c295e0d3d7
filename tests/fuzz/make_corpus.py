#!/usr/bin/env python3
"""Writes the tiny seed corpus of the fuzz targets into tests/fuzz/corpus/<format>/.

Valid small files of each format (layouts: docs/formats.md), so libFuzzer starts from inputs
that get past the headers. Re-run after a format change; the files are committed."""
import math
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))


def write(fmt, name, data):
    d = os.path.join(HERE, "corpus", fmt)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def trk(big, version, tracks, n_scalars, n_props, n_count=None):
    e = ">" if big else "<"
    h = bytearray(1000)
    h[0:6] = b"TRACK\0"
    struct.pack_into(e + "3h", h, 6, 4, 4, 4)
    struct.pack_into(e + "3f", h, 12, 2.0, 2.0, 2.0)
    struct.pack_into(e + "h", h, 36, n_scalars)
    h[38:43] = b"fa\0\0\0"
    if n_scalars > 1:
        h[58:63] = b"rgb\x003"
    struct.pack_into(e + "h", h, 238, n_props)
    h[240:243] = b"len"
    struct.pack_into(e + "16f", h, 440, 2, 0, 0, 10, 0, 2, 0, 20, 0, 0, 2, 30, 0, 0, 0, 1)
    h[948:951] = b"LPS"
    struct.pack_into(e + "iii", h, 988, len(tracks) if n_count is None else n_count, version, 1000)
    out = bytes(h)
    for pts in tracks:
        out += struct.pack(e + "i", len(pts))
        for i, p in enumerate(pts):
            out += struct.pack(e + "3f", *p)
            out += struct.pack(e + "%df" % n_scalars, *[0.1 * (i + k) for k in range(n_scalars)])
        out += struct.pack(e + "%df" % n_props, *[float(k) for k in range(n_props)])
    return out


def tck(tracks, fmt, magic="mrtrix tracks", scalar=False, count=None, extra="", end_marker=True):
    """`count` overrides the header's count (None: the number of tracks); `extra` is inserted
    after the first line; without `end_marker` the data ends after the last track's NaN."""
    big = fmt.endswith("BE")
    code = (">" if big else "<") + ("d" if fmt.startswith("Float64") else "f")
    nan, inf = float("nan"), float("inf")
    vals = []
    for t in tracks:
        for p in t:
            vals += list(p) if not scalar else [p]
        vals += [nan] * (1 if scalar else 3)
    if end_marker:
        vals += [inf] * (1 if scalar else 3)
    head = "%s\n%sdatatype: %s\ncount: %d\nfile: . " % (magic, extra, fmt, len(tracks) if count is None else count)
    offset = len(head) + 4 + 1 + 4
    head += "%4d\nEND\n" % offset
    return head.encode() + b"".join(struct.pack(code, v) for v in vals)


def tcb(tracks, attrs):
    names = b"".join(struct.pack("<I", len(n)) + n.encode() for n, _ in attrs)
    v = sum(len(t) for t in tracks)
    out = b"TCBLINES" + struct.pack("<IIQQQ", 1, len(attrs), v, len(tracks), len(names)) + names
    out += b"\0" * (-len(out) % 8)
    off = [0]
    for t in tracks:
        off.append(off[-1] + len(t))
    out += struct.pack("<%dI" % len(off), *off)
    for t in tracks:
        for p in t:
            out += struct.pack("<3f", *p)
    for _, values in attrs:
        out += struct.pack("<%df" % v, *values)
    return out


lines = [[(0, 0, 0), (1, 0, 0), (1, 1, 0)], [(5, 5, 5), (6, 6, 6)]]
write("trk", "le_v2_scalars_props.trk", trk(False, 2, lines, 4, 2))
write("trk", "be_v1.trk", trk(True, 1, lines, 0, 0))
write("trk", "le_v2_one_scalar.trk", trk(False, 2, lines[:1], 1, 1))
write("trk", "v3_stale_n_count.trk", trk(False, 3, lines, 4, 2, n_count=5))
write("trk", "empty.trk", trk(True, 2, [], 0, 0))
write("tck", "le32.tck", tck(lines, "Float32LE"))
write("tck", "be64.tck", tck(lines, "Float64BE"))
write("tck", "le32_scalars.tsf", tck([[1.0, 2.0, 3.0], [4.0, 5.0]], "Float32LE", "mrtrix track scalars", True))
# What the reader tolerates (docs/formats.md): a stale count, multi-line values and comments, no
# end marker after the last track, an empty tractogram.
write("tck", "stale_count.tck", tck(lines, "Float32LE", count=7))
write("tck", "multi_line.tck", tck(lines, "Float32BE", extra="# comment\ncommand_history: tckgen a b\ntckedit b c\n"
                                                       "Comment: one # two\n"))
write("tck", "no_end_marker.tck", tck(lines, "Float32LE", end_marker=False))
write("tck", "empty.tck", tck([], "Float32LE"))
write("tcb", "two_attrs.tcb", tcb(lines, [("speed", [1, 2, 3, 4, 5]), ("fa", [0.5] * 5)]))
write("tcb", "no_attrs.tcb", tcb(lines, []))
write("obj", "linevis.obj",
      b"a vorticity speed\nv 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nvt 1 2\nvt 3 4\nvt 5 6\nvt 7 8\n"
      b"g line0\nl 1 2 3\nl -1 -2\n")
write("obj", "explicit_vt.obj", b"# standard\nv 0 0 0\nv 1 0 0 1\nvt 5\nvt 6\nl 1/2 2/1\nl 2//1 1\nf 1 2 1\n")
