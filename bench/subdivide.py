#!/usr/bin/python3
"""Midpoint-subdivide an OBJ mesh (each triangle into four, shape unchanged) to make a larger test
mesh for the scaling benchmark. Usage: bench/subdivide.py IN.obj OUT.obj [LEVELS]"""
import sys

from hard_meshes import read_obj  # the benchmark meshes' OBJ reader, beside this script


def main():
    source, target = sys.argv[1], sys.argv[2]
    levels = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    vertices, faces = read_obj(source)
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
