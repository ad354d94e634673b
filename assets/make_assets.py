#!/usr/bin/env python3
"""Authors Taut's sample cages. Run from assets/: python3 make_assets.py

Every cage is written counter-clockwise seen from outside, with vertices shared between faces.
The cages are modelled Z up, as Taut models; OBJ files are written Y up, as Blender and most
tools write and read them (Taut's own (x, y, z) is the file's (x, z, -y)).
"""
import json
import math


def write_obj(path, title, vertices, faces):
    with open(path, "w") as f:
        f.write(f"# {title}\n# Taut sample cage: {len(vertices)} vertices, {len(faces)} faces\n")
        for x, y, z in vertices:
            f.write("v " + " ".join(f"{c + 0.0:.6g}" for c in (x, z, -y)) + "\n")
        for face in faces:
            f.write("f " + " ".join(str(i + 1) for i in face) + "\n")


def cube():
    v = [[x, y, z] for z in (-50, 50) for y in (-50, 50) for x in (-50, 50)]
    f = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    return v, f


def prism(n=5, r=300.0, h=300.0):
    v = [[r * math.cos(2 * math.pi * k / n), r * math.sin(2 * math.pi * k / n), z] for z in (0.0, h) for k in range(n)]
    f = [list(reversed(range(n))), list(range(n, 2 * n))]
    f += [[k, (k + 1) % n, n + (k + 1) % n, n + k] for k in range(n)]
    return v, f


def patch(nx=4, ny=3, h=25.0):
    v = []
    for j in range(ny + 1):
        for i in range(nx + 1):
            x, y = i * h, j * h
            z = 18.0 * math.sin(math.pi * i / nx) * math.sin(math.pi * j / ny) + 4.0 * (i - nx / 2)
            v.append([x, y, z])
    f = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            f.append([a, a + 1, a + nx + 2, a + nx + 1])
    return v, f


def torus(n_major=8, n_minor=4, big=60.0, small=22.0):
    v = []
    for i in range(n_major):
        a = 2 * math.pi * i / n_major
        for j in range(n_minor):
            b = 2 * math.pi * j / n_minor + math.pi / 4
            rr = big + small * math.cos(b) * math.sqrt(2)
            v.append([rr * math.cos(a), rr * math.sin(a), small * math.sin(b) * math.sqrt(2)])
    f = []
    for i in range(n_major):
        for j in range(n_minor):
            i1, j1 = (i + 1) % n_major, (j + 1) % n_minor
            f.append([i * n_minor + j, i1 * n_minor + j, i1 * n_minor + j1, i * n_minor + j1])
    return v, f


def knob():
    """A hand-held product form: a chamfered octagonal body (long sides and short chamfers),
    a waist, a domed top closed by a fan of triangles, and a flat octagonal base (an n-gon)."""
    def ring(half, chamfer, z, squash=1.0):
        # Octagon with alternating long sides (2·(half − chamfer)) and short chamfer sides.
        pts = [(half, -half + chamfer), (half, half - chamfer), (half - chamfer, half), (-half + chamfer, half),
               (-half, half - chamfer), (-half, -half + chamfer), (-half + chamfer, -half), (half - chamfer, -half)]
        return [[x, y * squash, z] for x, y in pts]

    rings = [ring(40, 6, 0), ring(44, 7, 22), ring(36, 6, 38), ring(40, 9, 58), ring(24, 8, 76)]
    v = [p for r in rings for p in r]
    n = 8
    f = [list(reversed(range(n)))]  # the base: one octagon
    for k in range(len(rings) - 1):
        for i in range(n):
            a, b = k * n + i, k * n + (i + 1) % n
            f.append([a, b, b + n, a + n])
    apex = len(v)
    v.append([0.0, 0.0, 86.0])
    top = (len(rings) - 1) * n
    for i in range(n):
        f.append([top + i, top + (i + 1) % n, apex])
    return v, f


def main():
    for name, title, (v, f) in [
        ("cube.obj", "A cube of side 100", cube()),
        ("prism.obj", "A pentagonal prism, circumradius 300, height 300", prism()),
        ("prism30.obj", "A pentagonal prism, circumradius 30, height 30 (the size the curve-mesh paper's figures fit)",
         prism(r=30.0, h=30.0)),
        ("patch.obj", "An open 4 x 3 quad patch", patch()),
        ("torus.obj", "A genus-1 cage: 8 x 4 quads", torus()),
    ]:
        write_obj(name, title, v, f)
    v, f = knob()
    doc = {
        "format": "taut-cage",
        "version": 1,
        "positions": v,
        "faces": f,
        "fixed": [True] * len(v),
        "vertex_tension": [0.0] * len(v),
        "edge_tension": [],
        "settings": {"levels": 4, "lambda": 0.6, "tol": 0.001, "max_iterations": 5000, "spacing": "chord"},
    }
    with open("default.taut", "w") as out:
        json.dump(doc, out, indent=1)
        out.write("\n")
    write_obj("knob.obj", "The default scene's cage (see default.taut)", v, f)


if __name__ == "__main__":
    main()
