#!/usr/bin/env python3
"""Code and read-only data of a Cortex-M image by origin (firmware, port, libgcc, newlib), and its
vector table, summed from the input sections of its GNU ld link map; the streams (section
.streams) are not counted.
Prints one line per (section, origin): section, origin, bytes; then what a part's flash holds in
all (the stream table left out). Used by scripts/target-size.sh
(docs/TARGET.md, "Footprint"), scripts/target-method-size.py (which imports sizes()),
scripts/target-code-heat.py and scripts/target-setup-split.py (input_sections(), origin_of()
and demangled()), tests/target/check_budget.sh, check_code_heat.sh and check_setup_split.sh.
Usage: python3 scripts/map_sizes.py IMAGE.map"""
import re, subprocess, sys


def input_sections(map_path):
    """[(output section, input section, address, bytes, object)] of the image's .vectors, .text
    and .rodata, in the order of its GNU ld link map at map_path."""
    found = []
    section = None
    lines = open(map_path).read().split("\n")
    started = False
    for i, line in enumerate(lines):
        if line.startswith("Linker script and memory map"):
            started = True
        if not started:
            continue
        m = re.match(r"^(\.[\w.]+)\s+0x", line)  # an output section
        if m:
            section = m.group(1)
            continue
        # An input section: " .text.name  0xADDR  0xSIZE  object", or its name alone on a line
        # with the address, size and object on the next.
        m = re.match(r"^ (\.[\w.\-$]+)\s+(0x[0-9a-f]+)\s+(0x[0-9a-f]+)\s+(\S+)", line)
        if m:
            name, address, size, obj = m.group(1), int(m.group(2), 16), int(m.group(3), 16), m.group(4)
        elif re.match(r"^ (\.[\w.\-$]+)\s*$", line) and i + 1 < len(lines):
            nxt = lines[i + 1].split()
            if len(nxt) < 3 or not nxt[0].startswith("0x") or not nxt[1].startswith("0x"):
                continue
            name, address, size, obj = line.strip(), int(nxt[0], 16), int(nxt[1], 16), nxt[2]
        else:
            continue
        if section in (".vectors", ".text", ".rodata"):
            found.append((section, name, address, size, obj))
    return found


def origin_of(obj):
    """Where an input section's object comes from: firmware, the port, the stream table, libgcc,
    newlib, or other."""
    if "/firmware/" in obj:
        return "firmware"
    if "port_" in obj or "main_" in obj or "cost_" in obj or "part_" in obj:
        return "port (startup, semihosting, main)"
    if "streams" in obj:
        return "stream table"
    if "libgcc" in obj:
        return "libgcc"
    if "libc" in obj or "libg" in obj or "libstdc++" in obj:
        return "newlib"
    return "other"


def demangled(sections):
    """The C++ names of .text.MANGLED input sections (c++filt, the names on its input)."""
    names = [name[len(".text."):] if name.startswith(".text.") else name for name in sections]
    return subprocess.run(["c++filt"], input="\n".join(names), capture_output=True, text=True,
                          check=True).stdout.splitlines()


def sizes(map_path):
    """{(section, origin): bytes} of the image whose GNU ld link map is at map_path."""
    totals = {}
    for section, _, _, size, obj in input_sections(map_path):
        key = section, origin_of(obj)
        totals[key] = totals.get(key, 0) + size
    return totals


def flash_bytes(totals):
    """What a part's flash holds of the image: every counted section and origin but the table of
    the embedded streams (test data, as the streams themselves)."""
    return sum(size for (_, origin), size in totals.items() if origin != "stream table")


if __name__ == "__main__":
    if len(sys.argv) != 2 or sys.argv[1].startswith("-"):
        sys.exit("usage: python3 scripts/map_sizes.py IMAGE.map (a GNU ld link map)")
    try:
        totals = sizes(sys.argv[1])
    except (OSError, UnicodeDecodeError) as e:  # a missing, unreadable or binary file
        sys.exit("map_sizes.py: %s: %s" % (sys.argv[1], e.strerror if isinstance(e, OSError) else e))
    if not any(totals.values()):
        sys.exit("map_sizes.py: %s: no input sections of .vectors, .text or .rodata (not a link map?)"
                 % sys.argv[1])
    for (section, origin), size in sorted(totals.items()):
        if size:
            print("%-8s %-36s %8d" % (section, origin, size))
    print("%-45s %8d" % ("flash in all (vectors, code, read-only data)", flash_bytes(totals)))
