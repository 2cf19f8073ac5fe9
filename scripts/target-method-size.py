#!/usr/bin/env python3
"""What each shading method costs in firmware code on the Cortex-M3 at -Os: the "Code by method"
table of docs/TARGET.md. A port links only the methods it ships (TP_FIRMWARE_METHODS, a mask of
Method ids; firmware/device.cpp), so for each method this links an image of a base (gouraud,
which every device needs since it starts with it, and flat, the smallest) plus that method
alone, and reports its firmware code (.text) and read-only data from the link map
(scripts/map_sizes.py). "Over the base" is what the method adds; methods share code
(PointShader, the Kuijk-Blake arcs, the fixed-point functions), so the additions of several
methods overlap and do not sum.

Only device.cpp reads the mask: it is compiled once per image with the release build's own
command for the m3-Os configuration, and linked with that build's other objects by its own
link command (both from `ninja -t commands`), in a temporary folder; the build is not touched.
Usage: python3 scripts/target-method-size.py [--build DIR] [--methods kb,kb-adaptive] [--keep DIR]
                                             [--fill BYTES]
(default build/release, built; --methods: one row, the base with those methods together).
--fill BYTES: which methods a part with BYTES of firmware code can link, chosen greedily: from the
base (and the --methods, if given) it adds, one at a time, the method whose image is then the
smallest, while the code stays within BYTES; a row per step (docs/TARGET.md, "What fits a part").
It links every remaining method at every step: up to some 180 links, a few minutes."""
import argparse, os, re, shlex, shutil, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
from map_sizes import sizes  # noqa: E402

CONFIG = "m3-Os"
BASE = ("flat", "gouraud")


def method_ids():
    """[(name, id)] in the registry's order: names from firmware/registry.hpp's rows, ids from
    the Method enum of firmware/types.hpp."""
    types = open(os.path.join(ROOT, "firmware/types.hpp")).read()
    enum = types[types.index("enum class Method"):]
    enum = enum[:enum.index("};")]
    ids = {k: int(v) for k, v in re.findall(r"\b(k\w+) = (\d+)", enum)}
    registry = open(os.path.join(ROOT, "firmware/registry.hpp")).read()
    rows = re.findall(r"\{Method::(k\w+),\s*\"([\w-]+)\"", registry)
    if not rows:
        sys.exit("target-method-size.py: no method rows found in firmware/registry.hpp")
    return [(name, ids[enumerator]) for enumerator, name in rows]


def ninja_command(target_dir, output):
    """The last command ninja runs to build `output` (relative to the target build), as argv."""
    out = subprocess.run(["ninja", "-C", target_dir, "-t", "commands", output], check=True,
                         capture_output=True, text=True).stdout.strip().split("\n")
    return shlex.split(out[-1].removeprefix(": && ").removesuffix(" && :"))


def without_depfile(argv):
    """argv without gcc's dependency-file options (-MD, -MT X, -MF X)."""
    out, skip = [], False
    for a in argv:
        if skip:
            skip = False
        elif a in ("-MT", "-MF"):
            skip = True
        elif a != "-MD":
            out.append(a)
    return out


def replaced(argv, old, new):
    if old not in argv:
        sys.exit("target-method-size.py: %s not in the command %s" % (old, " ".join(argv)))
    return [new if a == old else a for a in argv]


def fill(budget, start, footprint, row, base_text, names, tmp):
    """The greedy choice of --fill: a row for the start, then one per method added ("+ name"),
    and a last line naming the cheapest method left out and its image's code."""
    chosen = list(BASE) + [m for m in start if m not in BASE]
    if start:
        text, rodata = footprint("start", chosen, tmp)
        row(" + ".join(start), text, rodata, base_text)
        if text > budget:
            print("the start alone is over %s bytes" % format(budget, ","))
            return
    while True:
        best = None
        for name in names:
            if name not in chosen:
                text, rodata = footprint("try", chosen + [name], tmp)
                if best is None or text < best[1]:
                    best = (name, text, rodata)
        if best is None:
            print("every method fits within %s bytes" % format(budget, ","))
            return
        if best[1] > budget:
            print("left out: %d of %d methods; the cheapest next, %s, would make %s bytes (over %s)"
                  % (len(names) - len(chosen), len(names), best[0], format(best[1], ","),
                     format(budget, ",")))
            return
        chosen.append(best[0])
        row("+ " + best[0], best[1], best[2], base_text)


def main():
    parser = argparse.ArgumentParser(description="Firmware code by method, Cortex-M3 -Os "
                                     "(docs/TARGET.md, \"Code by method\").")
    parser.add_argument("--build", default="build/release",
                        help="the build folder, already built (default build/release)")
    parser.add_argument("--methods", help="comma-separated: one row, the base with these "
                        "methods together (what a port that ships them links)")
    parser.add_argument("--keep", metavar="DIR",
                        help="copy the images linked (NAME.elf, NAME.map) into DIR")
    parser.add_argument("--fill", metavar="BYTES", type=int,
                        help="add methods greedily while the code stays within BYTES")
    args = parser.parse_args()
    if args.fill is not None and args.fill <= 0:
        sys.exit("target-method-size.py: --fill: a number of bytes above 0")
    target_dir = os.path.join(ROOT, args.build, "target")
    image = "%s-kb.elf" % CONFIG
    if not os.path.exists(os.path.join(target_dir, image)):
        sys.exit("target-method-size.py: %s/%s missing (build the release preset first)"
                 % (target_dir, image))
    ids = method_ids()
    by_name = dict(ids)
    chosen = None
    if args.methods is not None:
        chosen = [m for m in args.methods.split(",") if m]
        unknown = [m for m in chosen if m not in by_name]
        if unknown or not chosen:
            sys.exit("target-method-size.py: --methods: unknown method(s) %s (known: %s)"
                     % (", ".join(unknown) or "(none given)", ", ".join(by_name)))
    device_obj = "CMakeFiles/port_%s.dir%s/firmware/device.cpp.obj" % (CONFIG, ROOT)
    compile_cmd = without_depfile(ninja_command(target_dir, device_obj))
    link_cmd = ninja_command(target_dir, image)
    map_flag = [a for a in link_cmd if a.startswith("-Wl,-Map=")]
    if len(map_flag) != 1:
        sys.exit("target-method-size.py: no single -Wl,-Map= in the link command")

    def footprint(tag, names, tmp):
        mask = "|".join("(1ull<<%d)" % by_name[n] for n in names)
        # In a folder named firmware: map_sizes.py tells firmware objects by their path.
        obj = os.path.join(tmp, "firmware", tag + ".device.o")
        elf = os.path.join(tmp, tag + ".elf")
        mapfile = os.path.join(tmp, tag + ".map")
        cc = replaced(compile_cmd, device_obj, obj) + ["-DTP_FIRMWARE_METHODS=(%s)" % mask]
        subprocess.run(cc, cwd=target_dir, check=True)
        ld = replaced(replaced(link_cmd, device_obj, obj), image, elf)
        ld = replaced(ld, map_flag[0], "-Wl,-Map=" + mapfile)
        subprocess.run(ld, cwd=target_dir, check=True)
        s = sizes(mapfile)
        if args.keep:
            os.makedirs(args.keep, exist_ok=True)
            for f in (elf, mapfile):
                shutil.copy(f, args.keep)
        return s.get((".text", "firmware"), 0), s.get((".rodata", "firmware"), 0)

    def row(label, text, rodata, base_text):
        print("| %s | %s | %s | %s |" % (label, format(text, ","),
                                         format(text - base_text, "+,"), format(rodata, ",")))

    with tempfile.TemporaryDirectory() as tmp:
        os.mkdir(os.path.join(tmp, "firmware"))
        base_text, base_rodata = footprint("base", list(BASE), tmp)
        print("| method | code | over the base | read-only data |")
        print("|---|---:|---:|---:|")
        print("| base: %s | %s | | %s |" % (" + ".join(BASE), format(base_text, ","),
                                             format(base_rodata, ",")))
        if args.fill is not None:
            fill(args.fill, chosen or [], footprint, row, base_text, [n for n, _ in ids], tmp)
            return
        if chosen is not None:
            names = list(BASE) + [m for m in chosen if m not in BASE]
            row(" + ".join(chosen), *footprint("chosen", names, tmp), base_text)
            return
        for name, _ in ids:
            if name not in BASE:
                row(name, *footprint(name, list(BASE) + [name], tmp), base_text)
        row("every method", *footprint("every", [n for n, _ in ids], tmp), base_text)


if __name__ == "__main__":
    main()
