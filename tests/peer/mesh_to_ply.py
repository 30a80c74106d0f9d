#!/usr/bin/env python3
"""Make the ASCII PLY meshes the Java 3D and Draco peer harnesses read.

    mesh_to_ply.py obj IN.obj OUT.ply [--texture TEX.png]
    mesh_to_ply.py icosphere LEVEL OUT.ply

PLY layout (one vertex per distinct position/normal/colour corner; faces are triangles):
    property float x y z, property float nx ny nz, property uchar red green blue alpha,
    element face: property list uchar int vertex_indices

obj: n-gons are fanned from their first corner. Normals: the OBJ's `vn` when every face
     corner has one, else area-weighted vertex normals per position index (smooth shading).
     Colours: with --texture, the texel nearest to the corner's UV (v up, wrap repeat;
     8-bit RGB/RGBA PNG, non-interlaced); without, derived from the normal:
     rgb = round(255 * (0.5 + 0.5 * n)). Alpha 255.
icosphere: a regular icosahedron subdivided LEVEL times (20 * 4^LEVEL triangles),
     projected to the unit sphere, then stretched to the ellipsoid
     x = 3 + 2.5 u, y = -1 + 2.0 v, z = 2 + 1.5 w (so the bounds are not a cube and the
     Java 3D normalisation is a non-trivial affine map); exact ellipsoid normals; colours
     rgb from the normal as above and alpha = round(255 * (0.25 + 0.75 * (0.5 + 0.5 * u)))
     so that alpha varies. Deterministic (pure Python, fixed order).
Only the Python standard library is used.
"""
import math
import struct
import sys
import zlib


def read_png(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit(f"{path}: not a PNG")
    pos, idat, width = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if kind == b"IHDR":
            width, height, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or ctype not in (2, 6) or interlace:
                raise SystemExit(f"{path}: only 8-bit RGB/RGBA non-interlaced PNG")
            bpp = 3 if ctype == 2 else 4
        elif kind == b"IDAT":
            idat += body
        elif kind == b"IEND":
            break
    raw = zlib.decompress(idat)
    stride = width * bpp
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if f == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 255
        elif f == 2:
            for i in range(stride):
                line[i] = (line[i] + prev[i]) & 255
        elif f == 3:
            for i in range(stride):
                left = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((left + prev[i]) >> 1)) & 255
        elif f == 4:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                b = prev[i]
                c = prev[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pr = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[i] = (line[i] + pr) & 255
        rows.append(line)
        prev = line
    return width, height, bpp, rows


def normalize(v):
    n = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return (v[0] / n, v[1] / n, v[2] / n) if n > 0 else (0.0, 0.0, 1.0)


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normal_colour(n):
    return tuple(max(0, min(255, round(255 * (0.5 + 0.5 * c))))for c in n)


def write_ply(path, vertices, faces, comment):
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\n")
        for line in comment.splitlines():
            f.write(f"comment {line}\n")
        f.write(f"element vertex {len(vertices)}\n")
        for p in ("x", "y", "z", "nx", "ny", "nz"):
            f.write(f"property float {p}\n")
        for p in ("red", "green", "blue", "alpha"):
            f.write(f"property uchar {p}\n")
        f.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for (p, n, c) in vertices:
            f.write("%.7g %.7g %.7g %.6f %.6f %.6f %d %d %d %d\n" % (p + n + c))
        for t in faces:
            f.write("3 %d %d %d\n" % t)
    print(f"{path}: {len(vertices)} vertices, {len(faces)} triangles")


def obj(src, dst, texture=None):
    pos, uv, nrm, corners = [], [], [], []
    for line in open(src):
        w = line.split()
        if not w:
            continue
        if w[0] == "v":
            pos.append(tuple(float(x) for x in w[1:4]))
        elif w[0] == "vt":
            uv.append(tuple(float(x) for x in w[1:3]))
        elif w[0] == "vn":
            nrm.append(tuple(float(x) for x in w[1:4]))
        elif w[0] == "f":
            face = []
            for c in w[1:]:
                parts = c.split("/") + ["", ""]
                idx = []
                for k, arr in ((0, pos), (1, uv), (2, nrm)):
                    if parts[k]:
                        i = int(parts[k])
                        idx.append(i - 1 if i > 0 else len(arr) + i)
                    else:
                        idx.append(None)
                face.append(tuple(idx))
            for k in range(1, len(face) - 1):
                corners.append((face[0], face[k], face[k + 1]))
    use_vn = bool(nrm) and all(c[2] is not None for t in corners for c in t)
    smooth = [(0.0, 0.0, 0.0)] * len(pos)
    if not use_vn:
        acc = [[0.0, 0.0, 0.0] for _ in pos]
        for t in corners:
            a, b, c = (pos[k[0]] for k in t)
            n = cross(sub(b, a), sub(c, a))  # length = 2 * area
            for k in t:
                for i in range(3):
                    acc[k[0]][i] += n[i]
        smooth = [normalize(a) for a in acc]
    tex = read_png(texture) if texture else None
    index, vertices, faces = {}, [], []
    for t in corners:
        tri = []
        for (pi, ti, ni) in t:
            n = normalize(nrm[ni]) if use_vn else smooth[pi]
            if tex and ti is not None:
                w, h, bpp, rows = tex
                u, v = uv[ti]
                x = int(math.floor((u % 1.0) * w)) % w
                y = int(math.floor((1.0 - (v % 1.0)) * h)) % h
                px = rows[y][x * bpp:x * bpp + 3]
                col = (px[0], px[1], px[2], 255)
            else:
                col = normal_colour(n) + (255,)
            key = (pos[pi], n, col)
            if key not in index:
                index[key] = len(vertices)
                vertices.append(key)
            tri.append(index[key])
        faces.append(tuple(tri))
    how = ("colours: nearest texel of " + texture.split("/")[-1]) if tex else "colours: from normals"
    write_ply(dst, vertices, faces,
              f"from {src.split('/')[-1]} by tests/peer/mesh_to_ply.py\n"
              f"normals: {'OBJ vn' if use_vn else 'area-weighted smooth'}; {how}; alpha 255")


def icosphere(level, dst):
    t = (1.0 + math.sqrt(5.0)) / 2.0
    verts = [normalize(v) for v in [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                                    (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
             (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
             (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(level):
        mid, out = {}, []

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                pa, pb = verts[a], verts[b]
                verts.append(normalize(((pa[0] + pb[0]) / 2, (pa[1] + pb[1]) / 2, (pa[2] + pb[2]) / 2)))
                mid[k] = len(verts) - 1
            return mid[k]

        for (a, b, c) in faces:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = out
    radii, centre = (2.5, 2.0, 1.5), (3.0, -1.0, 2.0)
    vertices = []
    for u in verts:
        p = tuple(centre[i] + radii[i] * u[i] for i in range(3))
        n = normalize(tuple(u[i] / radii[i] for i in range(3)))  # gradient of the ellipsoid
        alpha = max(0, min(255, round(255 * (0.25 + 0.75 * (0.5 + 0.5 * u[0])))))
        vertices.append((p, n, normal_colour(n) + (alpha,)))
    write_ply(dst, vertices, faces,
              f"icosphere level {level} by tests/peer/mesh_to_ply.py: ellipsoid centre {centre} radii {radii}\n"
              "normals: exact; rgb from normals; alpha varies with x")


def main(argv):
    if len(argv) >= 3 and argv[0] == "obj":
        texture = None
        if len(argv) == 5 and argv[3] == "--texture":
            texture = argv[4]
        elif len(argv) != 3:
            raise SystemExit(__doc__)
        obj(argv[1], argv[2], texture)
    elif len(argv) == 3 and argv[0] == "icosphere":
        icosphere(int(argv[1]), argv[2])
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
