#!/usr/bin/env python3
"""Writes the hand-made seeds of the device fuzz target (tests/fuzz/corpus/device/): command
streams as little-endian 32-bit words (firmware/device.hpp, "Command stream"). Run from the
repository root: python3 tests/fuzz/seeds/make_device_seeds.py"""
import math
import os
import struct

OUT = "tests/fuzz/corpus/device"
VIEWPORT, CAPACITY, MODELVIEW, PROJECTION, EYE, MATERIAL, LIGHT, METHOD = range(1, 9)
CULLING, DEPTH, VERTICES, INDICES, CLEAR, DRAW, END = range(9, 16)


def q16(v): return round(v * 65536) & 0xffffffff
def q30(v): return round(v * (1 << 30)) & 0xffffffff
def q29(v): return round(v * (1 << 29)) & 0xffffffff


def cmd(op, *payload): return [op | (len(payload) << 16), *payload]


def matrix(op, m):  # m[col][row]
    return cmd(op, *[q16(m[c][r]) for c in range(4) for r in range(4)])


IDENTITY = [[1 if c == r else 0 for r in range(4)] for c in range(4)]


def perspective(fovy, aspect, near, far):
    f = 1 / math.tan(fovy / 2)
    m = [[0] * 4 for _ in range(4)]
    m[0][0], m[1][1] = f / aspect, f
    m[2][2], m[2][3] = (far + near) / (near - far), -1
    m[3][2] = 2 * far * near / (near - far)
    return m


def translate(x, y, z):
    m = [row[:] for row in IDENTITY]
    m[3][0], m[3][1], m[3][2] = x, y, z
    return m


def unit(x, y, z):
    n = math.sqrt(x * x + y * y + z * z)
    return x / n, y / n, z / n


def vertices(first, verts):
    words = [first, len(verts)]
    for (p, n) in verts:
        words += [q16(c) for c in p] + [q30(c) for c in n]
    return cmd(VERTICES, *words)


def setup(width=32, height=24, fmt=0, counts=1, method=3, n=20, ab=(0, 0)):
    s = cmd(VIEWPORT, width, height, fmt, counts) + cmd(CAPACITY, 8, 24)
    s += cmd(MATERIAL, q30(1), q30(0.8), q30(0.6), q30(0.1), q30(0.6), q30(0.4), n,
             q29(ab[0]), q29(ab[1]))
    s += cmd(LIGHT, 0, 1, q16(1), q16(1), q16(1), *[q30(c) for c in unit(0.3, 0.4, 1)],
             0, 0, 0)
    s += cmd(METHOD, method)
    return s


TRIANGLE = [((-0.8, -0.7, 0), unit(-0.5, -0.4, 1)), ((0.8, -0.7, 0), unit(0.5, -0.4, 1)),
            ((0, 0.9, 0), unit(0, 0.6, 1))]


def draw_triangle():
    return (vertices(0, TRIANGLE) + cmd(INDICES, 0, 3, 0, 1, 2) + cmd(CLEAR, 0x102030) +
            cmd(DRAW, 0, 3) + cmd(END))


def write(name, words):
    with open(os.path.join(OUT, name), "wb") as f:
        f.write(struct.pack("<%dI" % len(words), *words))


os.makedirs(OUT, exist_ok=True)
for method, name in [(1, "flat"), (2, "gouraud"), (3, "phong"), (6, "kb"),
                     (11, "kb_decomposition"), (12, "kb_exact"), (13, "kb_adaptive")]:
    write("triangle_" + name, setup(method=method) + draw_triangle())
write("triangle_kb_ab", setup(method=6, ab=(0.2, 0.6)) + draw_triangle())
write("triangle_rgb565_no_counts", setup(fmt=1, counts=0) + draw_triangle())
# Perspective, a point light, a finite eye, depth test off, culling off: the near plane clips.
persp = (setup(method=13, n=200) + matrix(PROJECTION, perspective(1.0, 32 / 24, 0.5, 10)) +
         matrix(MODELVIEW, translate(0, 0, -0.6)) + cmd(EYE, 0) +
         cmd(LIGHT, 1, 2, q16(0.5), q16(0.5), q16(0.5), 0, 0, 0, q16(1), q16(1), q16(1)) +
         cmd(CULLING, 0) + cmd(DEPTH, 0) +
         vertices(0, TRIANGLE + [((0, 0, -2), unit(0, 0, 1))]) +
         cmd(INDICES, 0, 6, 0, 1, 2, 0, 3, 1) + cmd(CLEAR, 0) + cmd(DRAW, 0, 6) + cmd(END))
write("perspective_clipped", persp)
# Refusals: each a different error path, after a valid start.
write("error_bad_opcode", setup() + [0x0000ffff])
write("error_truncated", setup() + cmd(VERTICES, 0, 1, 0, 0)[:3])
write("error_draw_before_viewport", cmd(DRAW, 0, 3))
write("error_index_out_of_range", setup() + vertices(0, TRIANGLE) +
      cmd(INDICES, 0, 3, 0, 1, 7) + cmd(DRAW, 0, 3))
write("error_draw_beyond_indices", setup() + draw_triangle() + cmd(DRAW, 0xfffffffd, 6))
write("error_not_unit", setup() + vertices(0, [((0, 0, 0), (0.5, 0, 0))]))
write("error_out_of_memory", cmd(VIEWPORT, 4096, 4096, 0, 1))
write("error_upload_wraps", setup() + cmd(INDICES, 0xffffffff, 1, 0))
