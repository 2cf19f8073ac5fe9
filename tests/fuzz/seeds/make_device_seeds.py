#!/usr/bin/env python3
"""Writes the hand-made seeds of the device fuzz target (tests/fuzz/corpus/device/): command
streams as little-endian 32-bit words (firmware/device.hpp, "Command stream").

    python3 tests/fuzz/seeds/make_device_seeds.py           # write them
    python3 tests/fuzz/seeds/make_device_seeds.py --check   # the test fuzz.device.seeds

Writing removes the corpus files that are no longer seeds (not those added by hand: found_* found
a problem, reach_* reach code the seeds do not). --check writes nothing: it fails unless the
committed corpus holds exactly these seeds besides those, and METHODS names every method of
firmware/types.hpp, so that a method added to the firmware without a seed of its own fails a
test."""
import math
import os
import re
import struct
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
OUT = os.path.join(ROOT, "tests", "fuzz", "corpus", "device")
VIEWPORT, CAPACITY, MODELVIEW, PROJECTION, EYE, MATERIAL, LIGHT, METHOD = range(1, 9)
CULLING, DEPTH, VERTICES, INDICES, CLEAR, DRAW, END, BUDGET = range(9, 17)


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


def setup(width=32, height=24, fmt=0, counts=1, method=3, n=20, ab=(0, 0), capacity=(8, 24)):
    s = cmd(VIEWPORT, width, height, fmt, counts) + cmd(CAPACITY, *capacity)
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


SEEDS = {}  # file name -> bytes


def write(name, words):
    SEEDS[name] = struct.pack("<%dI" % len(words), *words)


# Every method of the firmware's registry (firmware/types.hpp, Method; `tinyphong methods`), so
# that the fuzzer starts from a draw by each: a lit triangle, and a perspective view of two
# triangles, one of them crossing the near plane (its vertex 3 is 0.3 from the eye, the plane
# 0.5), with a point light, a finite eye, depth test and culling off: where the per-pixel vectors
# vary most, and clipping makes new vertices.
METHODS = [(1, "flat"), (2, "gouraud"), (3, "phong"), (4, "duff"), (5, "bishop_weimer"),
           (6, "kb"), (7, "brown"), (8, "quadratic"), (9, "kb_noskip"),
           (11, "kb_decomposition"), (12, "kb_exact"), (13, "kb_adaptive"),
           (14, "kb_adaptive_noskip"), (15, "kb_adaptive_exact"), (16, "bishop_weimer_finite"),
           (17, "brown_noskip"), (18, "gouraud_subdivided"), (19, "quadratic_screen"),
           (21, "envmap"), (22, "blinn_map"), (23, "quadratic_blinn_map")]


def perspective_draw(method):
    return (setup(method=method, n=200) +
            matrix(PROJECTION, perspective(1.0, 32 / 24, 0.5, 10)) +
            matrix(MODELVIEW, translate(0, 0, -0.6)) + cmd(EYE, 0) +
            cmd(LIGHT, 1, 2, q16(0.5), q16(0.5), q16(0.5), 0, 0, 0, q16(1), q16(1), q16(1)) +
            cmd(CULLING, 0) + cmd(DEPTH, 0) +
            vertices(0, TRIANGLE + [((0, 0, 0.3), unit(0, 0, 1))]) +
            cmd(INDICES, 0, 6, 0, 1, 2, 0, 3, 1) + cmd(CLEAR, 0) + cmd(DRAW, 0, 6) + cmd(END))


for method, name in METHODS:
    write("triangle_" + name, setup(method=method) + draw_triangle())
    write("perspective_" + name, perspective_draw(method))
write("triangle_kb_ab", setup(method=6, ab=(0.2, 0.6)) + draw_triangle())
write("triangle_rgb565_no_counts", setup(fmt=1, counts=0) + draw_triangle())
# Viewport flags 2: no depth buffer (bit 1), no write counts (bit 0).
write("triangle_no_depth_buffer", setup(counts=2) + draw_triangle())
# kb-adaptive's perspective draw, then again under an error budget of 4 output levels.
write("perspective_kb_adaptive_budget", perspective_draw(13)[:-1] + cmd(BUDGET, 4) +
      cmd(CLEAR, 0) + cmd(DRAW, 0, 6) + cmd(END))


def sixteen_lights(method):
    """Every light slot lit, directional and point lights in turn, coloured, over a fan of six
    triangles under perspective with a finite eye: the longest seed, so that the fuzzer tries
    streams with many lights and draws from the start (libFuzzer begins with inputs no longer
    than the corpus's longest and lengthens them slowly, up to 4,096 bytes)."""
    s = setup(method=method, n=60, capacity=(16, 24))
    for i in range(16):
        colour = [q16(0.1 + 0.05 * ((i + k) % 4)) for k in range(3)]
        a = 2 * math.pi * i / 16
        if i % 2 == 0:
            s += cmd(LIGHT, i, 1, *colour, *[q30(c) for c in unit(math.cos(a), math.sin(a), 1)],
                     0, 0, 0)
        else:
            s += cmd(LIGHT, i, 2, *colour, 0, 0, 0, q16(0.8 * math.cos(a)), q16(0.8 * math.sin(a)),
                     q16(-1.5))
    fan = [((0, 0, 0.1), unit(0, 0, 1))]
    for k in range(7):
        a = 2 * math.pi * k / 6
        fan.append(((0.7 * math.cos(a), 0.7 * math.sin(a), 0), unit(math.cos(a), math.sin(a), 1.5)))
    indices = [i for k in range(6) for i in (0, k + 1, k + 2)]
    return (s + matrix(PROJECTION, perspective(1.0, 32 / 24, 0.5, 10)) +
            matrix(MODELVIEW, translate(0, 0, -2)) + cmd(EYE, 0) + vertices(0, fan) +
            cmd(INDICES, 0, len(indices), *indices) + cmd(CLEAR, 0x000010) +
            cmd(DRAW, 0, len(indices)) + cmd(END))


write("lights_16_kb", sixteen_lights(6))
write("lights_16_kb_adaptive", sixteen_lights(13))
# Refusals: one for each of the device's errors (firmware/types.hpp, Error), most after a valid
# start.
write("error_bad_opcode", setup() + [0x0000ffff])
write("error_truncated", setup() + cmd(VERTICES, 0, 1, 0, 0)[:3])
write("error_draw_before_viewport", cmd(DRAW, 0, 3))
write("error_index_out_of_range", setup() + vertices(0, TRIANGLE) +
      cmd(INDICES, 0, 3, 0, 1, 7) + cmd(DRAW, 0, 3))
write("error_draw_beyond_indices", setup() + draw_triangle() + cmd(DRAW, 0xfffffffd, 6))
write("error_not_unit", setup() + vertices(0, [((0, 0, 0), (0.5, 0, 0))]))
write("error_out_of_memory", cmd(VIEWPORT, 4096, 4096, 0, 1))
write("error_upload_wraps", setup() + cmd(INDICES, 0xffffffff, 1, 0))
write("error_budget_zero", setup(method=13) + cmd(BUDGET, 0))
write("error_viewport_zero_width", cmd(VIEWPORT, 0, 24, 0, 1))
write("error_exponent_zero", setup(n=0) + draw_triangle())
write("error_light_index_16", setup() + cmd(LIGHT, 16, 1, q16(1), q16(1), q16(1), q30(1), 0, 0,
                                            0, 0, 0))
write("error_unknown_method", setup(method=10) + draw_triangle())

# Inputs added by hand besides the seeds: found_* found a problem, reach_* reach code the seeds
# do not (docs/FUZZING.md).
HAND_ADDED = ("found_", "reach_")


def firmware_method_ids():
    """The ids of firmware/types.hpp's enum class Method; None if an enumerator is not of the
    form `kName = decimal` (then this parse must be taught it)."""
    with open(os.path.join(ROOT, "firmware", "types.hpp")) as f:
        text = f.read()
    body = re.search(r"enum class Method\b[^{]*\{(.*?)\};", text, re.S).group(1)
    body = re.sub(r"//[^\n]*", "", body)
    names = re.findall(r"\bk\w+", body)
    values = re.findall(r"\bk\w+\s*=\s*(\d+)\s*(?:,|$)", body.strip())
    if len(values) != len(names):
        return None
    return sorted(int(v) for v in values)


def check():
    problems = []
    ids = firmware_method_ids()
    seeded = sorted(m for m, _ in METHODS)
    if ids is None:
        problems.append("firmware/types.hpp's Method has an enumerator this script cannot read")
    elif seeded != ids:
        problems.append("METHODS has ids %s, firmware/types.hpp's Method %s" % (seeded, ids))
    committed = {n for n in os.listdir(OUT) if not n.startswith(HAND_ADDED)}
    for name in sorted(committed - SEEDS.keys()):
        problems.append("%s is in the corpus but not written by this script" % name)
    for name, data in sorted(SEEDS.items()):
        path = os.path.join(OUT, name)
        if not os.path.exists(path):
            problems.append("%s is missing from the corpus" % name)
        elif open(path, "rb").read() != data:
            problems.append("%s differs from what this script writes" % name)
    for p in problems:
        print("make_device_seeds.py --check: " + p, file=sys.stderr)
    if problems:
        print("(run python3 tests/fuzz/seeds/make_device_seeds.py to write the seeds)",
              file=sys.stderr)
        return 1
    print("the corpus holds the %d seeds: a triangle and a perspective draw by each of the %d "
          "methods, and %d others" % (len(SEEDS), len(METHODS), len(SEEDS) - 2 * len(METHODS)))
    return 0


if __name__ == "__main__":
    if sys.argv[1:] == ["--check"]:
        sys.exit(check())
    if sys.argv[1:]:
        print("usage: make_device_seeds.py [--check]", file=sys.stderr)
        sys.exit(2)
    os.makedirs(OUT, exist_ok=True)
    for name in sorted(os.listdir(OUT)):
        if not name.startswith(HAND_ADDED) and name not in SEEDS:
            print("removed %s: no longer a seed" % name)
            os.remove(os.path.join(OUT, name))
    for name, data in SEEDS.items():
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(data)
