#!/usr/bin/env python3
"""How much of the Cortex-M3 -Os image's firmware code only the methods' per-triangle set-up
needs (docs/TARGET.md, "Nor by set-up on the host"): the bound on a design that would leave each
triangle's set-up to the host's driver and send its result down the stream, so that the part keeps
only the code of the commands, the draw pipeline and the span loops.

A static call graph of the image (`m3-Os-replay`, every method linked, no stream built in): its
functions are the firmware's input sections in the link map (one per function,
-ffunction-sections); an edge is a branch from one function into another (`bl`, and the `b` of a
tail call), or a function's address in its literal pool. The methods' virtual functions are
reached through their vtables, and the registry's constructors through its rows, so every
function address in the image's read-only data is a root. The set-up side's roots are the
`::setup(` functions among them, the methods' per-triangle set-up; the device's roots are the
other addresses (`shade_span`, `linear_span`, the registry's `construct_at`) and the vector
table's reset handler, from which the commands and the draw pipeline are reached. Code reached
from the device's roots stays on the part; code reached only from the set-up's could go to the
host.

Prints the firmware's code in the two parts and what neither reaches (code the graph misses: an
indirect call through an address computed at run time), and with --top the N largest functions
that only the set-up reaches. Stops (exit 1) if it finds no `setup` function or no reset handler
among the roots.

Usage: python3 scripts/target-setup-split.py [--build DIR] [--top N] [--list]
  DIR: a built tree (default build/release); --list: also every firmware function, one per line:
  `device`, `setup` (reached only from set-up) or `neither`, its bytes and its name."""
import argparse, bisect, os, re, subprocess, sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
from map_sizes import demangled, input_sections, origin_of  # noqa: E402

IMAGE = "m3-Os-replay"
TARGET = 48 * 1024  # issue 12's firmware code at -Os
OBJDUMP = "arm-none-eabi-objdump"

# "  8a4:	f7ff fffc 	bl	40 <name>": a branch to an address, conditional or not, with or
# without a register operand (cbz, cbnz). The call and tail-call edges of the graph.
BRANCH = re.compile(r"^\s*([0-9a-f]+):\s+[0-9a-f ]+\s+(?:b[a-z.]*|cbn?z)\s+(?:r\d+,\s*)?([0-9a-f]+)\s+<")
# "  8b0:	00001235 	.word	0x00001235": a literal pool word, a function's address if it is one
# (with the Thumb bit).
WORD = re.compile(r"^\s*([0-9a-f]+):\s+[0-9a-f]{8}\s+\.word\s+0x([0-9a-f]+)")
# " 2d40 35120000 d1130000 ...": a line of `objdump -s`, an address and up to four words.
DATA = re.compile(r"^\s*([0-9a-f]{4,8})\s+((?:[0-9a-f]{8}\s?){1,4})")


class Functions:
    """The image's code, one function per input section, found by any address inside it."""

    def __init__(self, map_path):
        self.by_start = {}
        for section, name, address, size, obj in input_sections(map_path):
            if section == ".text" and size > 0:
                self.by_start[address] = (size, name, origin_of(obj))
        self.starts = sorted(self.by_start)

    def holding(self, address):
        """The start of the function whose code holds address, or None."""
        i = bisect.bisect_right(self.starts, address) - 1
        if i < 0:
            return None
        start = self.starts[i]
        return start if address < start + self.by_start[start][0] else None

    def size(self, start):
        return self.by_start[start][0]

    def origin(self, start):
        return self.by_start[start][2]


def run(*command):
    return subprocess.run(command, capture_output=True, text=True, check=True).stdout


def call_edges(image, functions):
    """{caller: {callee}} from the disassembly: branches between functions and function addresses
    in literal pools."""
    edges = {}
    for line in run(OBJDUMP, "-d", image).split("\n"):
        m = BRANCH.match(line)
        target = None
        if m:
            target = int(m.group(2), 16)
        else:
            m = WORD.match(line)
            if m and int(m.group(2), 16) & 1:
                target = int(m.group(2), 16) & ~1
        if target is None:
            continue
        caller, callee = functions.holding(int(m.group(1), 16)), functions.holding(target)
        if caller is not None and callee == target and callee != caller:
            edges.setdefault(caller, set()).add(callee)
    return edges


def data_roots(image, functions):
    """Every function whose address (with the Thumb bit) is a word of the image's read-only or
    initialised data: vtables, the registry's rows, the vector table."""
    roots = set()
    dump = run(OBJDUMP, "-s", "-j", ".vectors", "-j", ".rodata", "-j", ".data", image)
    for line in dump.split("\n"):
        m = DATA.match(line)
        if not m:
            continue
        for word in m.group(2).split():
            value = int.from_bytes(bytes.fromhex(word), "little")
            if value & 1 and (value & ~1) in functions.by_start:
                roots.add(value & ~1)
    return roots


def reached(roots, edges):
    seen, stack = set(roots), list(roots)
    while stack:
        for callee in edges.get(stack.pop(), ()):
            if callee not in seen:
                seen.add(callee)
                stack.append(callee)
    return seen


def main():
    parser = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    parser.add_argument("--build", default=os.path.join(ROOT, "build", "release"))
    parser.add_argument("--top", type=int, default=0)
    parser.add_argument("--list", action="store_true")
    args = parser.parse_args()
    image = os.path.join(args.build, "target", IMAGE + ".elf")
    functions = Functions(image[:-len(".elf")] + ".map")
    edges = call_edges(image, functions)
    roots = data_roots(image, functions)
    names = dict(zip(functions.starts,
                     demangled([functions.by_start[s][1] for s in functions.starts])))
    setup_roots = {r for r in roots if "::setup(" in names[r]}
    device_roots = roots - setup_roots  # the vector table's reset handler among them
    if not setup_roots or not any(names[s] == "reset_handler" for s in device_roots):
        sys.exit("target-setup-split: no set-up functions or no reset handler found in " + image)
    device = reached(device_roots, edges)
    setup_only = reached(setup_roots, edges) - device

    firmware = [s for s in functions.starts if functions.origin(s) == "firmware"]
    total = sum(functions.size(s) for s in firmware)
    stays = sum(functions.size(s) for s in firmware if s in device)
    goes = sum(functions.size(s) for s in firmware if s in setup_only)
    missed = [s for s in firmware if s not in device and s not in setup_only]
    unreached = sum(functions.size(s) for s in missed)
    print("firmware code of %s: %d bytes in %d functions" % (IMAGE, total, len(firmware)))
    print("  reached from the device's own work (commands, draw, spans, constructors): %d bytes "
          "(%+d against 48 KiB)" % (stays, stays - TARGET))
    print("  reached only from the methods' per-triangle set-up (%d setup functions): %d bytes"
          % (len(setup_roots), goes))
    print("  reached from neither: %d bytes%s" % (unreached, "".join(
        "\n    %6d %s" % (functions.size(s), names[s]) for s in missed)))
    for s in sorted((s for s in firmware if s in setup_only), key=functions.size, reverse=True)[:args.top]:
        print("%8d  %s" % (functions.size(s), names[s]))
    if args.list:
        for s in firmware:
            side = "device" if s in device else "setup" if s in setup_only else "neither"
            print("%s %d %s" % (side, functions.size(s), names[s]))


if __name__ == "__main__":
    main()
