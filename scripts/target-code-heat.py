#!/usr/bin/env python3
"""How often the Cortex-M3 -Os image's firmware code runs: for every function (one input section
each, -ffunction-sections), the largest share it takes of any run's guest instructions, over
every method on a few paper scenes at 160x120 (docs/TARGET.md, "Nor by a slower form for the code
that rarely runs"). A benchmark, not a test: it bounds any design that would keep the rarely run
code in a slower but denser form (a bytecode and its interpreter) to fit 48 KiB.

Each run is one recorded stream (`tinyphong record`) fed to the m3-Os replay image
(target/replay.cpp) under `qemu-system-arm -d in_asm,exec,nochain`: QEMU logs the instructions
of every block it translates, then every execution of a block with the host address of its
translation, so each execution counts its own translation's instructions, charged to the function
whose address range (from the link map, scripts/map_sizes.py) holds the block's start. A block
that starts in no input section of the image's code stops the script, and so does a run whose
frame hash is not the host's (`tinyphong replay --hash`). The whole run, counted from reset,
includes the upload of the stream's vertices and the image's own start, so the shares are of the
run, not of the draw alone.

Prints the firmware's code by the largest share its functions take of any run (and the functions
never run), and the bytes that a greedy choice (functions by share per byte, least first) can
take while all the chosen functions together stay within a share of every run.

Usage: python3 scripts/target-code-heat.py [--build DIR] [--methods m1,m2] [--scenes s1,s2]
       [--jobs N] [--top N] [--qemu PATH]
  DIR: a built tree (default build/release); --methods: default every method `tinyphong methods`
  lists; --scenes: paper scenes (default teapot-l4,sphere-40-l2,dodecahedron-30-l8,triangle);
  --top: also list the N largest functions. Last, for the firmware's bytes over 48 KiB, the share
  of a run that the code a slower form would have to replace takes: the greedy choice's, and a
  lower bound of any choice's (least_share). The defaults' 84 runs took
  26 minutes on two cores (2026-12-06), most of it the teapot's with the per-pixel methods."""
import argparse, bisect, concurrent.futures, functools, math, os, subprocess, sys, tempfile, threading

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
from map_sizes import demangled, input_sections, origin_of  # noqa: E402

IMAGE = "m3-Os-replay"
SCENES = "teapot-l4,sphere-40-l2,dodecahedron-30-l8,triangle"
SHARES = (1e-4, 1e-3, 3e-3, 1e-2, 3e-2)
BUDGETS = (0.005, 0.01, 0.02, 0.05, 0.10)
TARGET = 48 * 1024  # issue 12's firmware code at -Os
DENSITIES = (0.0, 0.25, 0.5)  # a slower form's bytes per byte of Thumb-2 it replaces


def code_sections(map_path, origin=None):
    """[(address, bytes, section name)] of the image's code (of one origin: "firmware"), by
    address."""
    return sorted((address, size, name) for section, name, address, size, obj in input_sections(map_path)
                  if section == ".text" and size > 0 and origin in (None, origin_of(obj)))


def firmware_functions(map_path):
    """[(address, bytes, section name)] of the firmware's code, one function each, by address."""
    return code_sections(map_path, "firmware")


def trace(qemu, image, code, stream, host_hash, workdir):
    """{block address: executed instructions} of one run of the stream, its frame checked."""
    fifo = os.path.join(workdir, os.path.basename(stream) + ".fifo")
    os.mkfifo(fifo)
    run = subprocess.Popen(
        ["timeout", "3600", qemu, "-M", "mps2-an385", "-nographic", "-monitor", "none",
         "-semihosting-config", "enable=on,target=native", "-kernel", image,
         "-append", os.path.basename(stream), "-d", "in_asm,exec,nochain", "-D", fifo],
        cwd=os.path.dirname(stream), stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE, text=True)
    console = []

    def release():  # a QEMU that ends without opening the log must not leave the reader waiting
        console.append(run.communicate()[1])
        try:
            os.close(os.open(fifo, os.O_WRONLY | os.O_NONBLOCK))
        except OSError:
            pass  # the reader has closed the log already

    watcher = threading.Thread(target=release)
    watcher.start()
    length = {}  # host address of a translation -> its instructions
    instructions = {}
    translated = None  # (first address, instructions) of the block just translated
    with open(fifo, buffering=1 << 20) as log:
        for line in log:
            if line.startswith("Trace"):  # "Trace 0: HOST [FLAGS/PC/...] ..."
                host = line.split()[2]
                pc = int(line.split("[", 1)[1].split("/", 2)[1], 16)
                if translated is not None:  # a translation's first execution follows it
                    if translated[0] != pc:
                        sys.exit("target-code-heat.py: block 0x%x translated, 0x%x run" % (translated[0], pc))
                    length[host] = translated[1]
                    translated = None
                instructions[pc] = instructions.get(pc, 0) + length[host]
            elif line.startswith("IN:"):
                translated = None
            elif line.startswith("0x"):  # "0xADDR:  encoding  instruction" of a translated block
                if translated is None:
                    translated = (int(line.split(":", 1)[0], 16), 0)
                translated = (translated[0], translated[1] + 1)
    watcher.join()
    os.remove(fifo)
    if run.returncode != 0:
        sys.exit("target-code-heat.py: %s failed on %s:\n%s" % (image, stream, console[0]))
    if "stream %s %s" % (os.path.basename(stream), host_hash) not in console[0].splitlines():
        sys.exit("target-code-heat.py: the core's frame of %s is not the host's %s:\n%s"
                 % (stream, host_hash, console[0]))
    starts = [c[0] for c in code]
    for pc in instructions:
        i = bisect.bisect_right(starts, pc) - 1
        if i < 0 or pc >= code[i][0] + code[i][1]:
            sys.exit("target-code-heat.py: block 0x%x of %s is in no section of the image's code" % (pc, stream))
    return instructions


def per_function(functions, instructions):
    """[executed instructions of each function], and the run's instructions in all."""
    starts = [f[0] for f in functions]
    counts = [0] * len(functions)
    for pc, n in instructions.items():
        i = bisect.bisect_right(starts, pc) - 1
        if i >= 0 and pc < functions[i][0] + functions[i][1]:
            counts[i] += n
    return counts, sum(instructions.values())


def least_weighted_share(functions, weighted, need):
    """The least share that holds `need` bytes when a part of a function may be taken, each
    function's share `weighted[i]`: (that share, the part taken of each function)."""
    held, share, taken = 0, 0.0, [0.0] * len(functions)
    for i in sorted(range(len(functions)), key=lambda i: weighted[i] / functions[i][1]):
        taken[i] = min(functions[i][1], need - held) / functions[i][1]
        held += functions[i][1] * taken[i]
        share += weighted[i] * taken[i]
        if held >= need:
            break
    return share, taken


def least_share(functions, shares, need, rounds=300, rate=50.0):
    """A lower bound of the largest share of a run that any choice of functions holding `need`
    bytes takes. For any weights over the runs, that largest share is at least the weighted mean
    share, which is at least the least weighted share holding the bytes with parts of functions
    allowed; the best bound over weights updated multiplicatively, towards the runs that the
    last round's choice loads most."""
    runs = len(shares)
    weights = [1.0 / runs] * runs
    best = 0.0
    for _ in range(rounds):
        weighted = [sum(weights[r] * shares[r][i] for r in range(runs)) for i in range(len(functions))]
        bound, taken = least_weighted_share(functions, weighted, need)
        best = max(best, bound)
        load = [sum(s[i] * taken[i] for i in range(len(functions))) for s in shares]
        top = max(load)
        weights = [max(w * math.exp(rate * (l - top)), 1e-300) for w, l in zip(weights, load)]
        weights = [w / sum(weights) for w in weights]
    return best


def without_parameters(name):
    """A demangled function name without its parameter list (and trailing qualifiers)."""
    end = name.rfind(")")
    depth = 0
    for i in range(end, -1, -1):
        depth += {")": 1, "(": -1}.get(name[i], 0)
        if depth == 0:
            return name[:i]
    return name


def greedy(functions, shares, budget):
    """Bytes of the functions a greedy choice takes, least share per byte first, while the chosen
    together stay within `budget` of every run's instructions."""
    order = sorted(range(len(functions)), key=lambda i: max(s[i] for s in shares) / functions[i][1])
    sums = [0.0] * len(shares)
    chosen = 0
    for i in order:
        if all(sums[r] + shares[r][i] <= budget for r in range(len(shares))):
            chosen += functions[i][1]
            for r in range(len(shares)):
                sums[r] += shares[r][i]
    return chosen


def positive(text):
    """A whole number >= 1 (argparse's type: --jobs 0 ran the recording first, then failed)."""
    if not text.isdigit() or int(text) < 1:
        raise argparse.ArgumentTypeError("a whole number >= 1, got '%s'" % text)
    return int(text)


def main():
    ap = argparse.ArgumentParser(description=" ".join(__doc__.split("\n\n")[0].split()))
    ap.add_argument("--build", default=os.path.join(ROOT, "build/release"))
    ap.add_argument("--methods")
    ap.add_argument("--scenes", default=SCENES)
    ap.add_argument("--jobs", type=positive, default=2)
    ap.add_argument("--top", type=int, default=0)
    ap.add_argument("--qemu", default="qemu-system-arm")
    args = ap.parse_args()
    build = os.path.abspath(args.build)  # QEMU runs in the streams' folder
    cli = os.path.join(build, "host/tinyphong")
    image = os.path.join(build, "target", IMAGE + ".elf")
    for path in (cli, image):
        if not os.path.exists(path):
            sys.exit("target-code-heat.py: %s missing (cmake --build --preset release)" % path)
    methods = (args.methods.split(",") if args.methods else
               [line.split("\t")[0] for line in subprocess.run([cli, "methods"], check=True, capture_output=True,
                                                               text=True).stdout.splitlines()])
    functions = firmware_functions(os.path.join(build, "target", IMAGE + ".map"))
    image_code = code_sections(os.path.join(build, "target", IMAGE + ".map"))
    with tempfile.TemporaryDirectory() as tmp:
        streams = []
        for method in methods:
            for scene in args.scenes.split(","):
                path = os.path.join(tmp, "%s.%s.tpcmd" % (method, scene))
                if subprocess.run([cli, "record", os.path.join(ROOT, "scenes", scene + ".json"), "--method",
                                   method, "--size", "160x120", "-o", path], stdout=subprocess.DEVNULL).returncode:
                    sys.exit("target-code-heat.py: tinyphong record refused scene %s, method %s (above)"
                             % (scene, method))
                streams.append(path)
        hashes = [subprocess.run([cli, "replay", "--hash", stream], check=True, capture_output=True,
                                 text=True).stdout.split()[0] for stream in streams]
        with concurrent.futures.ProcessPoolExecutor(args.jobs) as pool:  # the log's parse holds a core
            traced = list(pool.map(functools.partial(trace, args.qemu, image, image_code, workdir=tmp), streams,
                                   hashes))
        shares = []
        for instructions in traced:
            counts, total = per_function(functions, instructions)
            shares.append([c / total for c in counts])
    largest = [max(s[i] for s in shares) for i in range(len(functions))]
    code = sum(f[1] for f in functions)
    print("%d runs (%d methods x %s at 160x120), %s; firmware code %d bytes in %d functions" %
          (len(shares), len(methods), args.scenes, IMAGE, code, len(functions)))
    print("\n| functions that take less than this share of every run | functions | bytes | "
          "those functions together, at most, of a run |")
    print("|---|---:|---:|---:|")
    never = [i for i in range(len(functions)) if largest[i] == 0]
    print("| never run | %d | %d | 0 |" % (len(never), sum(functions[i][1] for i in never)))
    never_names = demangled([functions[i][2] for i in never])
    for limit in SHARES:
        cold = [i for i in range(len(functions)) if largest[i] < limit]
        together = max(sum(s[i] for i in cold) for s in shares)
        print("| %s | %d | %d | %s |" % (format(limit, ".2%"), len(cold), sum(functions[i][1] for i in cold),
                                         format(together, ".2%")))
    never_run = sorted(zip(never, never_names), key=lambda p: -functions[p[0]][1])
    print("\nNever run: " + "; ".join("%s %d" % (without_parameters(name), functions[i][1]) for i, name in never_run))
    print("\n| the chosen functions together at most, of every run | bytes (greedy) |")
    print("|---|---:|")
    for budget in BUDGETS:
        print("| %s | %d |" % (format(budget, ".1%"), greedy(functions, shares, budget)))
    gap = code - TARGET
    if gap > 0:
        print("\n%d bytes over 48 KiB: what a slower form taking d bytes per byte of the code it replaces "
              "would have to hold (the interpreter not counted)\n" % gap)
        print("| d | bytes to replace | the chosen functions together, of some run (greedy) | "
              "any choice's, at least |")
        print("|---:|---:|---:|---:|")
        for d in DENSITIES:
            need = math.ceil(gap / (1 - d))
            lo, hi = 0.0, 1.0
            for _ in range(24):  # the least budget whose greedy choice holds `need` bytes
                mid = (lo + hi) / 2
                lo, hi = (lo, mid) if greedy(functions, shares, mid) >= need else (mid, hi)
            print("| %.2f | %d | %s | %s |" % (d, need, format(hi, ".2%"),
                                              format(least_share(functions, shares, need), ".2%")))
    if args.top:
        print("\n| bytes | largest share of a run | function |")
        print("|---:|---:|---|")
        top = sorted(range(len(functions)), key=lambda i: -functions[i][1])[:args.top]
        for i, name in zip(top, demangled([functions[i][2] for i in top])):
            print("| %d | %s | `%s` |" % (functions[i][1], format(largest[i], ".3%"), without_parameters(name)))


if __name__ == "__main__":
    main()
