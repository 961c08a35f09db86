#!/usr/bin/python3
"""Midpoint-subdivide an OBJ mesh (each triangle into four, shape unchanged) to make a larger test
mesh for the scaling benchmark. Usage: bench/subdivide.py IN.obj OUT.obj [LEVELS]"""
import sys


def main():
    source, target = sys.argv[1], sys.argv[2]
    levels = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    vertices, faces = [], []
    with open(source) as f:
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
    for _ in range(levels):
        midpoints = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in midpoints:
                vertices.append(tuple((x + y) / 2 for x, y in zip(vertices[a], vertices[b])))
                midpoints[key] = len(vertices) - 1
            return midpoints[key]

        faces = [t for a, b, c in faces
                 for ab, bc, ca in [(midpoint(a, b), midpoint(b, c), midpoint(c, a))]
                 for t in ((a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca))]
    with open(target, "w") as f:
        f.write(f"# {source} midpoint-subdivided {levels} time(s) by bench/subdivide.py\n")
        f.writelines(f"v {x:.9g} {y:.9g} {z:.9g}\n" for x, y, z in vertices)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in faces)


if __name__ == "__main__":
    main()
