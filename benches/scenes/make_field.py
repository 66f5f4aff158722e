#!/usr/bin/env python3
"""Writes the instanced-field scenes (and the icosphere mesh the in-repo one uses).

    python3 benches/scenes/make_field.py

benches/scenes/bunny_field.scene: 1,000 Stanford bunnies (read from ../shared/scenes, not
shipped), a 40 x 25 grid. assets/scenes/ball_field.scene: 600 icospheres (assets/meshes/
icosphere.obj, made here), a 30 x 20 grid. Every mesh statement names the same file, so the
renderer stores the mesh once and places it 1,000 (600) times as instances. Seeded: the files
are reproducible.
"""
import math
import random


def field(path, mesh, cols, rows, step, lift, scale, header, camera, light):
    random.seed(1)
    out = header + [
        "ambient 0.4 0.4 0.4",
        light,
        camera,
        "color 0.55 0.55 0.5",
        f"tri -{cols * step / 2 + 1} 0 -5  {cols * step / 2 + 1} 0 -5  {cols * step / 2 + 1} 0 {rows * step + 1}",
        f"tri -{cols * step / 2 + 1} 0 -5  {cols * step / 2 + 1} 0 {rows * step + 1}  -{cols * step / 2 + 1} 0 {rows * step + 1}",
    ]
    for r in range(rows):
        for c in range(cols):
            x = (c - (cols - 1) / 2) * step
            z = r * step
            s = random.uniform(*scale)
            a = random.uniform(-180, 180)
            col = [random.uniform(0.3, 0.95) for _ in range(3)]
            out += [
                "push",
                f"  translate {x:.3f} {lift * s:.5f} {z:.3f}",
                f"  rotate y {a:.1f}",
                f"  scale {s:.3f}",
                f"  color {col[0]:.2f} {col[1]:.2f} {col[2]:.2f}",
                f"  mesh {mesh}",
                "pop",
            ]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def icosphere(path, levels):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        cache, nf = {}, []

        def mid(a, b):
            k = (min(a, b), max(a, b))
            if k not in cache:
                p = [(v[a][i] + v[b][i]) / 2 for i in range(3)]
                n = math.sqrt(sum(x * x for x in p))
                v.append(tuple(x / n for x in p))
                cache[k] = len(v) - 1
            return cache[k]

        for a, b, c in f:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            nf += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = nf
    with open(path, "w") as o:
        o.write(f"# A unit icosphere, {levels} subdivisions ({len(f)} triangles), made by\n")
        o.write("# benches/scenes/make_field.py for raylab's examples.\n")
        for p in v:
            o.write("v %.6f %.6f %.6f\n" % p)
        for a, b, c in f:
            o.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))


field("benches/scenes/bunny_field.scene", "../../../shared/scenes/bunny.obj", 40, 25, 0.2,
      0.0330, (0.8, 1.25),
      ["# 1,000 Stanford bunnies (69,451 triangles each, 69.5M in all), placed by the transform",
       "# stack: a 40 x 25 grid, 0.2 apart, each turned about y and scaled. The bunny is read from",
       "# ../shared/scenes (not shipped); every bunny is one instance of one stored mesh.",
       "# Made by benches/scenes/make_field.py (seed 1)."],
      "camera 0 -1.3 -1.6 pitch -28 fov 60", "light 0 -6 -2 400")
icosphere("assets/meshes/icosphere.obj", 3)
field("assets/scenes/ball_field.scene", "../meshes/icosphere.obj", 30, 20, 0.5,
      -1.0, (0.12, 0.22),
      ["# 600 balls (an icosphere of 1,280 triangles, 768,000 in all) placed by the transform",
       "# stack: a 30 x 20 grid, 0.5 apart, each turned about y and scaled. Every mesh statement",
       "# names the same file, so the mesh is stored once and placed 600 times as instances.",
       "# Made by benches/scenes/make_field.py (seed 1)."],
      "camera 0 -2.2 -3.2 pitch -30 fov 60", "light 0 -12 -4 1600")
