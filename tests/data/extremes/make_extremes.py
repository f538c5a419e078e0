"""Fields of thin discs and long needles (issue 37): 4x4x4 points, unit spacing, each tensor
R diag(l) R^T with R a random rotation (seeded), written as legacy VTK ASCII with 17
significant digits. Drawn with --scale 0.8 --min-radius 0 the glyphs (largest radius 0.8)
pass through their neighbours.

  discs.vtk    eigenvalues (1, 1, 1e-5): discs, k = 1e5
  needles.vtk  eigenvalues (1, 1e-4, 1e-4): needles, k = 1e4
  mixed.vtk    discs and needles, k drawn from 1e3, 1e4, 1e5, 1e6
  needle_field.vtk  1000 needles (10x10x10), k = 1e4: enough pixels at 1024x768 (200 to 1300)
                    for a normal p99 that is not one pixel's
  needle_field_1e5.vtk, needle_field_1e6.vtk  the same at k = 1e5 and 1e6 (seeds 41, 42): each
                    needle is thinner than a pixel (5 to 260 pixel centres meet them at 1024x768)

Run: python3 make_extremes.py (standard library only).
"""
import math
import random


def rotation(rng):
    # A uniform random unit quaternion (Shoemake), as a row-major matrix.
    u1, u2, u3 = rng.random(), rng.random(), rng.random()
    a, b = math.sqrt(1 - u1), math.sqrt(u1)
    w, x = a * math.sin(2 * math.pi * u2), a * math.cos(2 * math.pi * u2)
    y, z = b * math.sin(2 * math.pi * u3), b * math.cos(2 * math.pi * u3)
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]


def tensor(r, lam):
    return [
        [sum(r[i][k] * lam[k] * r[j][k] for k in range(3)) for j in range(3)] for i in range(3)
    ]


def write(path, eigen, seed, n=4):
    rng = random.Random(seed)
    lines = [
        "# vtk DataFile Version 3.0",
        f"{path}: issue 37's thin glyphs, seed {seed}",
        "ASCII",
        "DATASET STRUCTURED_POINTS",
        f"DIMENSIONS {n} {n} {n}",
        "ORIGIN 0 0 0",
        "SPACING 1 1 1",
        f"POINT_DATA {n ** 3}",
        "TENSORS tensors double",
    ]
    for _ in range(n ** 3):
        t = tensor(rotation(rng), eigen(rng))
        for row in t:
            lines.append(" ".join(repr(v) for v in row))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def mixed(rng):
    k = rng.choice([1e3, 1e4, 1e5, 1e6])
    return (1.0, 1.0, 1.0 / k) if rng.random() < 0.5 else (1.0, 1.0 / k, 1.0 / k)


write("discs.vtk", lambda rng: (1.0, 1.0, 1e-5), 37)
write("needles.vtk", lambda rng: (1.0, 1e-4, 1e-4), 38)
write("mixed.vtk", mixed, 39)
write("needle_field.vtk", lambda rng: (1.0, 1e-4, 1e-4), 40, n=10)
write("needle_field_1e5.vtk", lambda rng: (1.0, 1e-5, 1e-5), 41, n=10)
write("needle_field_1e6.vtk", lambda rng: (1.0, 1e-6, 1e-6), 42, n=10)
