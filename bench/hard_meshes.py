#!/usr/bin/python3
"""Writes the generated hard meshes of the benchmark into a folder. Usage:
bench/hard_meshes.py BUNNY.obj OUTDIR
  bunny-holes.obj      the bunny with every 50th triangle removed (one-triangle holes)
  terrain.obj          an open heightfield sheet, 256 x 256 cells, one 1024-edge border
  tetra-copies.obj     100000 copies of a tetrahedron (every edge shared by 200000 triangles)
  bunny-overlap.obj    the bunny, an exact copy of it and a copy moved by 1/100 of its size
"""
import math
import os
import sys


def read_obj(path):
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append(tuple(float(x) for x in parts[1:4]))
            elif parts[0] == "f":
                corners = [int(p.split("/")[0]) for p in parts[1:]]
                corners = [c - 1 if c > 0 else len(vertices) + c for c in corners]
                faces.extend((corners[0], corners[i], corners[i + 1]) for i in range(1, len(corners) - 1))
    return vertices, faces


def write_obj(path, vertices, faces):
    with open(path, "w") as f:
        f.writelines("v %.9g %.9g %.9g\n" % v for v in vertices)
        f.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in faces)


def main():
    bunny, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    vertices, faces = read_obj(bunny)
    write_obj(os.path.join(out, "bunny-holes.obj"), vertices, [f for i, f in enumerate(faces) if i % 50 != 25])

    lo = [min(v[a] for v in vertices) for a in range(3)]
    hi = [max(v[a] for v in vertices) for a in range(3)]
    shift = [(h - l) / 100 for l, h in zip(lo, hi)]
    n = len(vertices)
    write_obj(os.path.join(out, "bunny-overlap.obj"),
              vertices + [tuple(x + s for x, s in zip(v, shift)) for v in vertices],
              faces + faces + [(a + n, b + n, c + n) for a, b, c in faces])

    cells = 256
    terrain = [(x / cells, y / cells, 0.08 * math.sin(9.0 * x / cells) * math.cos(7.0 * y / cells) + 0.03 * math.sin(31.0 * (x + y) / cells))
               for y in range(cells + 1) for x in range(cells + 1)]
    grid = []
    for y in range(cells):
        for x in range(cells):
            a, b, c, d = y * (cells + 1) + x, y * (cells + 1) + x + 1, (y + 1) * (cells + 1) + x + 1, (y + 1) * (cells + 1) + x
            grid += [(a, b, c), (a, c, d)]
    write_obj(os.path.join(out, "terrain.obj"), terrain, grid)

    tetra = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    write_obj(os.path.join(out, "tetra-copies.obj"), tetra, [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)] * 100000)


if __name__ == "__main__":
    main()
