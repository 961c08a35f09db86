#!/usr/bin/python3
"""Writes a corpus of messy meshes, one per failure class of real assets, into a folder. Usage:
bench/messy_meshes.py OUTDIR [--triangles N] [--seed S] [--class NAME ...] [--parts KIND]

Each mesh is built from parts (spheres, boxes, cylinders, bent panels), placed at random with
the seed, and spoilt the way dataset assets are; --triangles sets about how many triangles
each mesh has (1k to 1M), by the parts' tessellation. The classes:
  open-parts        a car-like model: many disjoint open parts (panels, shells with holes,
                    tubes without caps), a quarter of them inside out, some sharing edges
                    (non-manifold) and some stitched with flipped faces (inconsistent edges)
  inverted          closed parts inside out, alone and nested in correct ones (and correct ones
                    nested in inverted ones)
  duplicates        shells duplicated exactly, copied with faces reversed, and copied with a small
                    shift (overlapping shells)
  thin-panels       double-sided panels: a bent sheet and its reversed copy a hair apart, open
                    along their borders
  interpenetrating  closed and open parts that cross each other
--parts KIND makes open-parts of one kind of part alone (panels, shells, tubes or spheres, with
no shared borders), written as open-parts-KIND.obj: which kind costs what.
No third-party packages: Debian's /usr/bin/python3 alone.
"""
import argparse
import math
import os
import random

CLASSES = ["open-parts", "inverted", "duplicates", "thin-panels", "interpenetrating"]
PART_KINDS = ["panels", "shells", "tubes", "spheres"]  # open-parts' kinds, in its order


class Builder:
    """Vertices and triangles, with parts added under a rigid transform."""

    def __init__(self):
        self.vertices, self.faces = [], []

    def add(self, part, transform, flip=False, drop=None):
        vertices, faces = part
        base = len(self.vertices)
        self.vertices += [transform(v) for v in vertices]
        for i, (a, b, c) in enumerate(faces):
            if drop is not None and drop(i, (vertices[a], vertices[b], vertices[c])):
                continue
            self.faces.append((base + a, base + c, base + b) if flip else (base + a, base + b, base + c))

    def write(self, path):
        with open(path, "w") as f:
            f.writelines("v %.9g %.9g %.9g\n" % v for v in self.vertices)
            f.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in self.faces)


def grid_faces(rows, cols, index, wrap_cols=False):
    faces = []
    for r in range(rows):
        for c in range(cols):
            c1 = (c + 1) % cols if wrap_cols else c + 1
            a, b, d, e = index(r, c), index(r, c1), index(r + 1, c1), index(r + 1, c)
            faces += [(a, b, d), (a, d, e)]
    return faces


def sphere(n):
    """A closed UV sphere of radius 1, outward faces; about 2 n² triangles."""
    rings, segments = max(n, 3), max(2 * n, 4)
    vertices = [(0.0, 0.0, 1.0)]
    for r in range(1, rings):
        t = math.pi * r / rings
        vertices += [(math.sin(t) * math.cos(2 * math.pi * s / segments), math.sin(t) * math.sin(2 * math.pi * s / segments),
                      math.cos(t)) for s in range(segments)]
    vertices.append((0.0, 0.0, -1.0))
    ring = lambda r, s: 1 + (r - 1) * segments + s % segments
    faces = [(0, ring(1, s), ring(1, s + 1)) for s in range(segments)]
    for r in range(1, rings - 1):
        for s in range(segments):
            a, b, c, d = ring(r, s), ring(r + 1, s), ring(r + 1, s + 1), ring(r, s + 1)
            faces += [(a, b, c), (a, c, d)]
    bottom = len(vertices) - 1
    faces += [(bottom, ring(rings - 1, s + 1), ring(rings - 1, s)) for s in range(segments)]
    return vertices, faces


def box(n):
    """A closed cube [-1, 1]³, outward faces, each face an n x n grid (12 n² triangles)."""
    n = max(n, 1)
    vertices, faces = [], []
    for axis in range(3):
        for side in (-1.0, 1.0):
            base = len(vertices)
            u, v = (axis + 1) % 3, (axis + 2) % 3
            for i in range(n + 1):
                for j in range(n + 1):
                    p = [0.0, 0.0, 0.0]
                    p[axis], p[u], p[v] = side, -1 + 2 * i / n, -1 + 2 * j / n
                    vertices.append(tuple(p))
            quad = grid_faces(n, n, lambda r, c: base + r * (n + 1) + c)
            faces += quad if side > 0 else [(a, c, b) for a, b, c in quad]
    return vertices, faces


def tube(n):
    """An open cylinder of radius 1 along z from -1 to 1, no caps (a wheel, a pipe)."""
    segments, rows = max(2 * n, 6), max(n // 2, 1)
    vertices = [(math.cos(2 * math.pi * s / segments), math.sin(2 * math.pi * s / segments), -1 + 2 * r / rows)
                for r in range(rows + 1) for s in range(segments)]
    return vertices, grid_faces(rows, segments, lambda r, c: r * segments + c, wrap_cols=True)


def panel(n, bend, rng):
    """An open bent sheet over [-1, 1]² (a body panel, a leaf), with a wavy height."""
    n = max(n, 2)
    a, b = rng.uniform(1, 3), rng.uniform(1, 3)
    vertices = []
    for i in range(n + 1):
        for j in range(n + 1):
            x, y = -1 + 2 * i / n, -1 + 2 * j / n
            vertices.append((x, y, bend * (x * x + 0.5 * y * y) + 0.05 * math.sin(a * x) * math.cos(b * y)))
    return vertices, grid_faces(n, n, lambda r, c: r * (n + 1) + c)


def rotation(rng):
    """A random rotation (from a random unit quaternion)."""
    q = [rng.gauss(0, 1) for _ in range(4)]
    norm = math.sqrt(sum(x * x for x in q))
    w, x, y, z = (v / norm for v in q)
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def placed(rng, centre, scale, stretch=(1, 1, 1)):
    m = rotation(rng)
    sx, sy, sz = (scale * s for s in stretch)

    def transform(v):
        p = (v[0] * sx, v[1] * sy, v[2] * sz)
        return tuple(centre[k] + m[k][0] * p[0] + m[k][1] * p[1] + m[k][2] * p[2] for k in range(3))
    return transform


def random_holes(rng, fraction):
    return lambda i, tri: rng.random() < fraction


def open_parts(builder, rng, n, only=None):
    """Many disjoint open parts, a quarter inside out, some touching along edges (`only`: parts of
    that kind alone, none touching)."""
    parts = 48
    for k in range(parts):
        centre = (rng.uniform(-4, 4), rng.uniform(-1.5, 1.5), rng.uniform(-1, 1))
        kind = k % 4 if only is None else PART_KINDS.index(only)
        flip = rng.random() < 0.25
        stretch = (rng.uniform(0.6, 1.6), rng.uniform(0.6, 1.6), rng.uniform(0.3, 1.2))
        transform = placed(rng, centre, rng.uniform(0.3, 0.8), stretch)
        if kind == 0:
            builder.add(panel(n, rng.uniform(-0.4, 0.4), rng), transform, flip)
        elif kind == 1:  # a shell with a face or a few cells missing
            missing = rng.randrange(6)
            m = max(n // 3, 1)
            per_face = 2 * m * m
            builder.add(box(m), transform, flip, drop=lambda i, tri: i // per_face == missing or rng.random() < 0.01)
        elif kind == 2:
            builder.add(tube(n), transform, flip)
        else:  # a sphere with a few cells missing
            builder.add(sphere(max(n // 2, 3)), transform, flip, drop=random_holes(rng, 0.02))
    if only is not None:
        return
    # Parts that share a border (non-manifold where three meet) and a stitched pair, one flipped.
    hinge = placed(rng, (0.0, 0.0, 2.5), 0.6)
    for angle in (0.0, 2.1, 4.2):
        c, s = math.cos(angle), math.sin(angle)
        builder.add(panel(n, 0.0, rng), lambda v, c=c, s=s: hinge((0.5 * (v[0] + 1) * c, 0.5 * (v[0] + 1) * s, v[1])),
                    flip=angle > 4)


def inverted(builder, rng, n):
    """Closed parts inside out, alone and nested, in both orders."""
    for k in range(12):
        centre = (rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(-1, 1))
        scale = rng.uniform(0.5, 1.0)
        outer = sphere(n) if k % 2 else box(max(n // 2, 1))
        builder.add(outer, placed(rng, centre, scale), flip=k % 3 == 0)
        if k % 3 != 2:  # a nested part, the other way round or the same way
            inner = box(max(n // 3, 1)) if k % 2 else sphere(max(n // 2, 3))
            builder.add(inner, placed(rng, centre, 0.45 * scale), flip=k % 3 != 0)


def duplicates(builder, rng, n):
    """Exact copies, reversed copies and shifted copies of closed and open shells."""
    for k in range(10):
        centre = (rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(-1, 1))
        part = sphere(n) if k % 2 else tube(n)
        transform = placed(rng, centre, rng.uniform(0.5, 1.0))
        builder.add(part, transform)
        mode = k % 5
        if mode == 0:
            builder.add(part, transform)
        elif mode == 1:
            builder.add(part, transform, flip=True)
        elif mode == 2:
            builder.add(part, lambda v: tuple(x + 0.03 for x in transform(v)))
        elif mode == 3:
            builder.add(part, transform)
            builder.add(part, transform, flip=True)
        else:
            builder.add(part, lambda v: tuple(x - 0.2 for x in transform(v)), flip=True)


def thin_panels(builder, rng, n):
    """Double-sided open panels: a sheet and its reversed copy a hair apart."""
    for k in range(16):
        centre = (rng.uniform(-4, 4), rng.uniform(-4, 4), rng.uniform(-1, 1))
        sheet = panel(n, rng.uniform(-0.3, 0.3), rng)
        transform = placed(rng, centre, rng.uniform(0.5, 1.2))
        thickness = 10 ** rng.uniform(-4, -2)
        builder.add(sheet, transform)
        builder.add(sheet, lambda v: transform((v[0], v[1], v[2] - thickness)), flip=True)


def interpenetrating(builder, rng, n):
    """Closed and open parts crossing each other in a cluster."""
    for k in range(24):
        centre = (rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5), rng.uniform(-1, 1))
        transform = placed(rng, centre, rng.uniform(0.5, 1.1), (1, rng.uniform(0.5, 1.5), rng.uniform(0.5, 1.5)))
        kind = k % 4
        part = sphere(n) if kind == 0 else box(max(n // 2, 1)) if kind == 1 else tube(n) if kind == 2 else panel(n, 0.3, rng)
        builder.add(part, transform, flip=rng.random() < 0.2)


MAKERS = {"open-parts": open_parts, "inverted": inverted, "duplicates": duplicates, "thin-panels": thin_panels,
          "interpenetrating": interpenetrating}


def build(name, triangles, seed, parts=None):
    """The class's mesh with about `triangles` triangles: the tessellation n found by doubling
    (`parts`: open-parts of that kind alone)."""
    def make(n):
        builder = Builder()
        if parts is not None:
            open_parts(builder, random.Random(seed), n, parts)
        else:
            MAKERS[name](builder, random.Random(seed), n)
        return builder
    n = 2
    mesh = make(n)
    while len(mesh.faces) < triangles:
        # the count grows as n², so the next n is known up to rounding
        n = max(n + 1, int(n * math.sqrt(triangles / max(len(mesh.faces), 1))))
        mesh = make(n)
    return mesh


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("outdir")
    parser.add_argument("--triangles", type=int, default=5000, help="about how many triangles each mesh has")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--class", dest="classes", action="append", choices=CLASSES, help="one class (repeatable); all by default")
    parser.add_argument("--parts", choices=PART_KINDS, help="open-parts of this kind of part alone (no other class)")
    args = parser.parse_args()
    if args.parts and args.classes:
        parser.error("--parts makes open-parts alone: leave out --class")
    os.makedirs(args.outdir, exist_ok=True)
    for name in ["open-parts"] if args.parts else args.classes or CLASSES:
        mesh = build(name, args.triangles, args.seed, args.parts)
        path = os.path.join(args.outdir, name + ("-" + args.parts if args.parts else "") + ".obj")
        mesh.write(path)
        print("%s: %d triangles" % (path, len(mesh.faces)))


if __name__ == "__main__":
    main()
