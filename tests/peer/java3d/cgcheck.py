#!/usr/bin/env python3
"""Check and compare the text CgTool prints (see README.md in this folder).

    cgcheck.py against-ply MESH.ply ENCODE.txt DECODED.txt
        Java 3D's decoded triangles (DECODED.txt: `CgTool decode` output, float or hex values,
        any layout) against the PLY it encoded (ENCODE.txt: `CgTool encode` stdout, for the
        bits, centre and scale). Drops the decoded triangles with two equal positions (the
        stripifier's joins), then requires the rest to be exactly the input triangles with
        positions quantized as Java 3D's CompressionStream does, winding kept; reports the
        largest normal angle and colour errors. Prints PASS/FAIL lines, then `N passed, M failed`.

    cgcompare: cgcheck.py compare A.txt B.txt [--keep-degenerate] [--ordered]
        Two decodes of the same stream (say Java 3D's and holo's, both in CgTool's text
        format) hold the same triangles: exactly the same float bits per vertex, compared as
        multisets of triangles (each rotated to start at its smallest vertex; winding kept).
        --ordered also requires the same order. Degenerate triangles are dropped unless
        --keep-degenerate.
"""
import math
import struct
import sys
from collections import Counter


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def parse_decoded(path):
    """Triangles as tuples of three vertices; a vertex is a tuple of 10 floats."""
    lines = open(path).read().splitlines()
    head = lines[0].split()
    if head[:3] != ["#", "CgTool", "decode"]:
        raise SystemExit(f"{path}: not CgTool decode output")
    mode, layout = head[3], head[4]
    if mode == "quantized" or layout == "stream":
        raise SystemExit(f"{path}: need float or hex values in triangles or indexed layout")

    def value(t):
        if mode == "hex":
            return struct.unpack(">f", bytes.fromhex(t))[0]
        return f32(float(t))  # Float.toString is the shortest text naming the float

    tris, corners, verts = [], [], []

    def flush():
        for k in range(0, len(corners) - 2, 3):
            tris.append(tuple(corners[k:k + 3]))
        corners.clear()

    for line in lines[1:]:
        w = line.split()
        if not w or w[0] in ("cg", "object", "end"):
            continue
        if w[0] == "segment":
            flush()
            verts = []
            continue
        if layout == "indexed":
            if w[0] == "v":
                verts.append(tuple(value(t) for t in w[2:12]))
            elif w[0] == "t":
                tris.append(tuple(verts[int(i)] for i in w[1:4]))
        else:
            corners.append(tuple(value(t) for t in w[:10]))
    flush()
    return tris


def degenerate(t):
    a, b, c = (v[:3] for v in t)
    return a == b or b == c or a == c


def rotated(t):
    k = min(range(3), key=lambda i: t[i])
    return t[k:] + t[:k]


class Report:
    def __init__(self):
        self.passed = self.failed = 0

    def check(self, ok, what):
        if ok:
            self.passed += 1
            print("PASS " + what)
        else:
            self.failed += 1
            print("FAIL " + what)

    def finish(self):
        print(f"{self.passed} passed, {self.failed} failed")
        sys.exit(0 if self.failed == 0 else 1)


def read_ply(path):
    lines = open(path).read().splitlines()
    props, nv, nf, i, element = [], 0, 0, 0, None
    while lines[i] != "end_header":
        w = lines[i].split()
        if w[0] == "element":
            element = w[1]
            if element == "vertex":
                nv = int(w[2])
            elif element == "face":
                nf = int(w[2])
        elif w[0] == "property" and element == "vertex":
            props.append((w[-1], w[1] in ("uchar", "uint8")))
        i += 1
    i += 1
    names = [p[0] for p in props]
    verts = []
    for k in range(nv):
        w = lines[i + k].split()
        d = {}
        for (name, is_byte), t in zip(props, w):
            d[name] = f32(float(t) / 255.0) if is_byte else f32(float(t))
        verts.append(d)
    faces = []
    for k in range(nf):
        w = [int(t) for t in lines[i + nv + k].split()]
        for j in range(2, w[0]):
            faces.append((w[1], w[j], w[j + 1]))
    return names, verts, faces


def java_int(x):
    """Java's (int) cast of a double: truncation toward zero."""
    return int(x)


def against_ply(mesh, encode, decoded):
    r = Report()
    enc = {}
    for line in open(encode):
        w = line.split()
        if w:
            enc[w[0]] = w[1:]
    pos_bits = int(enc["options"][1])
    centre = [float(t) for t in enc["center"][:3]]
    scale = float(enc["center"][4])
    mask = ~((1 << (16 - pos_bits)) - 1)
    step = 1 << (16 - pos_bits)
    # Java 3D truncates then masks (toward -inf); holo's encoder says
    # `quantization nearest`: round half away from zero (Rust's f64::round) to
    # a multiple of the step, clamped to [-32768, 32768 - step].
    nearest = enc.get("quantization") == ["nearest"]

    def rust_round(x):
        return math.copysign(math.floor(abs(x) + 0.5), x)

    def quant(v):
        if nearest:
            return tuple(int(min(max(rust_round((v[c] - centre[i]) * scale * 32768.0 / step) * step, -32768), 32768 - step))
                         for i, c in enumerate("xyz"))
        return tuple(java_int((v[c] - centre[i]) * scale * 32768.0) & mask for i, c in enumerate("xyz"))

    names, verts, faces = read_ply(mesh)
    expected = Counter(rotated(tuple(quant(verts[k]) for k in f)) for f in faces)
    tris = parse_decoded(decoded)
    kept = [t for t in tris if not degenerate(t)]
    r.check(True, f"{decoded}: {len(tris)} decoded triangles, {len(tris) - len(kept)} degenerate dropped, "
                  f"{len(kept)} left; the PLY has {len(faces)}")
    # Positions in quantized units: x * 32768 is exact for s.15 fixed point.
    got = Counter()
    exact = True
    for t in kept:
        q = []
        for v in t:
            p = tuple(v[i] * 32768.0 for i in range(3))
            exact &= all(c == int(c) for c in p)
            q.append(tuple(int(c) for c in p))
        got[rotated(tuple(q))] += 1
    r.check(exact, "every decoded position is an integer number of 1/32768 units")
    missing = expected - got
    extra = got - expected
    r.check(not missing and not extra,
            f"the non-degenerate triangles are the PLY's, positions quantized to {pos_bits} bits "
            f"({'rounded to nearest' if nearest else 'round toward -inf after (int) truncation'}), winding kept "
            f"({sum(missing.values())} missing, {sum(extra.values())} unexpected)")
    # Normals and colours: how far from the input (matched by quantized position).
    by_pos = {}
    for v in verts:
        by_pos.setdefault(quant(v), []).append(v)
    worst_angle, worst_col = 0.0, 0.0
    for t in kept:
        for v in t:
            key = tuple(int(v[i] * 32768.0) for i in range(3))
            cands = by_pos.get(key)
            if not cands:
                continue
            best_a, best_c = math.pi, 1.0
            for c in cands:
                if "nx" in c:
                    n = (c["nx"], c["ny"], c["nz"])
                    ln = math.sqrt(sum(x * x for x in n)) * math.sqrt(sum(x * x for x in v[3:6]))
                    a = math.acos(max(-1.0, min(1.0, sum(x * y for x, y in zip(n, v[3:6])) / ln))) if ln else math.pi
                else:
                    a = 0.0
                col = max(abs(c.get(k, 1.0) - v[6 + i]) for i, k in enumerate(("red", "green", "blue", "alpha")))
                if (a, col) < (best_a, best_c):
                    best_a, best_c = a, col
            worst_angle = max(worst_angle, best_a)
            worst_col = max(worst_col, best_c)
    print(f"info largest normal error {math.degrees(worst_angle):.3f} degrees, largest colour error "
          f"{worst_col:.5f} (1.0 = full scale)")
    r.finish()


def compare(a, b, keep, ordered):
    r = Report()
    ta, tb = parse_decoded(a), parse_decoded(b)
    if not keep:
        ta = [t for t in ta if not degenerate(t)]
        tb = [t for t in tb if not degenerate(t)]
    what = "triangles" if keep else "non-degenerate triangles"
    r.check(len(ta) == len(tb), f"{len(ta)} vs {len(tb)} {what}")

    def bits(t):
        return tuple(tuple(struct.pack(">10f", *v)) for v in t)

    ca = Counter(rotated(bits(t)) for t in ta)
    cb = Counter(rotated(bits(t)) for t in tb)
    r.check(ca == cb, f"same multiset of {what} (float bits, rotation-normalised, winding kept): "
                      f"{sum((ca - cb).values())} only in {a}, {sum((cb - ca).values())} only in {b}")
    if ordered:
        r.check([bits(t) for t in ta] == [bits(t) for t in tb], f"same order of {what}")
    r.finish()


def main(argv):
    if len(argv) == 4 and argv[0] == "against-ply":
        against_ply(*argv[1:])
    elif len(argv) >= 3 and argv[0] == "compare":
        extra = set(argv[3:])
        if extra - {"--keep-degenerate", "--ordered"}:
            raise SystemExit(__doc__)
        compare(argv[1], argv[2], "--keep-degenerate" in extra, "--ordered" in extra)
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
