#!/usr/bin/env python3
#
# Software License Agreement (BSD License)
#  pcl_spherical_meshless - see LICENSE.
#
# Writes the seed corpus of fuzz_reconstruction into corpus/ (next to this file):
# small clouds the reconstruction handles, and bad inputs (too few points, NaN,
# duplicates, flat and thin clouds), in the byte layout that fuzz_reconstruction.cpp
# documents; and the seeds of fuzz_readers and test_cli_inputs into corpus_readers/:
# one small valid file of each format and encoding the tools read. Deterministic:
# running it again gives the same files. Findings of the fuzzer are added to corpus/
# as they are (named finding-*), not by this script.
import math
import os
import random
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "corpus")
READERS_CORPUS = os.path.join(HERE, "corpus_readers")

# Byte 1 of the header.
UNIFORM, DISTANCE, SHAPE, MEANVALUE = 0, 1, 2, 3
DISC = 4
NO_OPTIMIZE = 8
OCTAHEDRON = 1 << 4
ICOSAHEDRON = 2 << 4
NO_INTERSECTION_CHECK = 64
RADIUS = 128
# Byte 3.
INDICES = 1
BASE_MESH = 2
POLYGONS = 4


def write(name, points, k=12, flags=MEANVALUE, radius_byte=0, extra=0):
    data = bytes([k % 256, flags, radius_byte, extra])
    data += b"".join(struct.pack("<fff", *p) for p in points)
    with open(os.path.join(CORPUS, name), "wb") as f:
        f.write(data)


def fibonacci_sphere(n, scale=(1.0, 1.0, 1.0), offset=(0.0, 0.0, 0.0)):
    golden = math.pi * (3.0 - math.sqrt(5.0))
    points = []
    for i in range(n):
        z = 1.0 - 2.0 * (i + 0.5) / n
        r = math.sqrt(1.0 - z * z)
        p = (r * math.cos(golden * i), r * math.sin(golden * i), z)
        points.append(tuple(offset[j] + scale[j] * p[j] for j in range(3)))
    return points


def main():
    os.makedirs(CORPUS, exist_ok=True)
    rng = random.Random(7)
    nan, inf = float("nan"), float("inf")

    tetrahedron = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
    octahedron = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    write("tetrahedron", tetrahedron)
    write("tetrahedron-k3-polygons", tetrahedron, k=3, extra=POLYGONS)
    write("octahedron-k15", octahedron, k=15)
    write("sphere-50", fibonacci_sphere(50), k=8)
    write("sphere-200-icosahedron", fibonacci_sphere(200), flags=MEANVALUE | ICOSAHEDRON)
    write("sphere-120-octahedron-shape", fibonacci_sphere(120), k=10, flags=SHAPE | OCTAHEDRON)
    write("sphere-100-uniform-no-optimize", fibonacci_sphere(100), k=9,
          flags=UNIFORM | NO_OPTIMIZE | NO_INTERSECTION_CHECK)
    write("sphere-100-radius", fibonacci_sphere(100), flags=DISTANCE | RADIUS, radius_byte=80)
    write("ellipsoid-1-1-20", fibonacci_sphere(150, scale=(1, 1, 20)))
    # Bit 7 of byte 0: setAllowSelfIntersections (true). This cloud is rejected as
    # not sphere-like either way (no small generated cloud here ends with local
    # folds only); the fuzzer's mutations may reach an allowed mesh with pairs.
    write("ellipsoid-1-1-20-pairs-allowed", fibonacci_sphere(150, scale=(1, 1, 20)), k=12 | 128)
    write("sphere-far-from-origin", fibonacci_sphere(80, scale=(100, 100, 100),
                                                     offset=(5e6, 5e6, 0)))
    noisy = [tuple(c + rng.gauss(0.0, 0.02) for c in p) for p in fibonacci_sphere(150)]
    write("sphere-150-noisy", noisy)

    base = fibonacci_sphere(60)
    duplicated = base + base[:20] + [base[3]] * 5
    write("sphere-duplicates", duplicated)
    write("sphere-nan-inf", base[:30] + [(nan, nan, nan), (inf, 0, 0), (0, -inf, nan)] + base[30:])
    write("sphere-indices-repeated", base, extra=INDICES | (7 << 3))
    # The first four points of a Fibonacci sphere are all near the north pole: a
    # poor base mesh, and a tetrahedron that may be inverted, for the validation.
    corners = [(0, 0, 1), (0.94, 0, -0.33), (-0.47, 0.82, -0.33), (-0.47, -0.82, -0.33)]
    write("sphere-user-base-mesh", corners + base, extra=BASE_MESH)

    grid = [(0.1 * i, 0.1 * j, 0.05 * math.sin(i) * math.cos(j))
            for i in range(10) for j in range(10)]
    write("height-field-disc", grid, k=10, flags=MEANVALUE | DISC)
    hemisphere = [p for p in fibonacci_sphere(160) if p[2] > 0.0]
    write("hemisphere-disc", hemisphere, flags=SHAPE | DISC)
    write("plane", [(0.1 * i, 0.1 * j, 2.0) for i in range(8) for j in range(8)])
    write("line", [(0.01 * i, 0.02 * i, -0.005 * i) for i in range(40)])
    two = fibonacci_sphere(40) + fibonacci_sphere(40, offset=(10, 0, 0))
    write("two-spheres", two)
    torus = []
    for i in range(16):
        for j in range(8):
            u, v = 2 * math.pi * i / 16, 2 * math.pi * j / 8
            torus.append(((1 + 0.4 * math.cos(v)) * math.cos(u),
                          (1 + 0.4 * math.cos(v)) * math.sin(u), 0.4 * math.sin(v)))
    write("torus", torus, k=8)
    write("three-points", tetrahedron[:3])
    write("k-zero", fibonacci_sphere(30), k=0)


def lzf_literals(data):
    """LZF as PCL reads it, literal runs only (a control byte of length - 1, at most
    32 bytes): valid binary_compressed data without a compressor."""
    out = b""
    for at in range(0, len(data), 32):
        chunk = data[at:at + 32]
        out += bytes([len(chunk) - 1]) + chunk
    return out


def pcd_header(n, data):
    return ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z\n"
            "SIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH %d\nHEIGHT 1\n"
            "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA %s\n" % (n, n, data)).encode()


def ply_header(fmt, n_vertices, n_faces):
    return ("ply\nformat %s 1.0\ncomment seed of fuzz_readers\nelement vertex %d\n"
            "property float x\nproperty float y\nproperty float z\nelement face %d\n"
            "property list uchar int vertex_indices\nend_header\n"
            % (fmt, n_vertices, n_faces)).encode()


def write_readers_corpus():
    os.makedirs(READERS_CORPUS, exist_ok=True)
    points = fibonacci_sphere(12)
    faces = [(0, 1, 2), (0, 2, 3), (0, 3, 1), (1, 3, 2)]

    def save(name, data):
        with open(os.path.join(READERS_CORPUS, name), "wb") as f:
            f.write(data)

    ascii_rows = "".join("%.6f %.6f %.6f\n" % p for p in points).encode()
    packed = b"".join(struct.pack("<fff", *p) for p in points)
    # binary_compressed stores the fields one after another (all x, then y, then z).
    by_field = b"".join(struct.pack("<f", p[axis]) for axis in range(3) for p in points)
    compressed = lzf_literals(by_field)
    save("sphere-ascii.pcd", pcd_header(len(points), "ascii") + ascii_rows)
    save("sphere-binary.pcd", pcd_header(len(points), "binary") + packed)
    save("sphere-compressed.pcd", pcd_header(len(points), "binary_compressed") +
         struct.pack("<II", len(compressed), len(by_field)) + compressed)
    face_rows = "".join("3 %d %d %d\n" % f for f in faces).encode()
    save("sphere-ascii.ply", ply_header("ascii", len(points), len(faces)) + ascii_rows +
         face_rows)
    save("sphere-binary.ply", ply_header("binary_little_endian", len(points), len(faces)) +
         packed + b"".join(struct.pack("<Biii", 3, *f) for f in faces))
    save("sphere-big-endian.ply", ply_header("binary_big_endian", len(points), 0) +
         b"".join(struct.pack(">fff", *p) for p in points))
    save("sphere.xyz", b"# x y z\n" + ascii_rows + b"nan nan nan\n")


if __name__ == "__main__":
    main()
    write_readers_corpus()
