#!/usr/bin/env python3
"""Where a raylab frame's time goes: a sampling profile at full speed, by inlined function.

The kernels are inlined into a few large functions (one per SIMD level), so a profile by
symbol says nothing. This samples the CPU clock with `perf` (no hardware counters needed:
the VMs this project is measured on have none), maps each sample to its chain of inlined
functions with `llvm-symbolizer --inlining` (the release profile keeps line tables), and
files it under the first function of the chain, innermost first, that `CATEGORIES` names.
Unlike callgrind it times the AVX-512 kernels too, and counts stalls where they happen: a
load that misses the caches is charged to the instruction that waits for it.

Usage (from the repository's root, after `cargo build --release`):

    python3 benches/time_profile.py [--binary target/release/raylab] [--freq 2000] -- \
        bench --scene benches/scenes/bunny_field.scene --step flat --width 1280 \
        --height 720 --threads 1 --frames 20

Needs `perf` (Debian: linux-perf), `llvm-symbolizer` (Debian: llvm) and `nm` (binutils).
Prints a markdown table. The samples include the scene's load and build (the bench reports
their time): a small share against 20 frames.
"""

import argparse
import collections
import os
import re
import subprocess
import sys
import tempfile

STACK = "walk stack: children sorted in, popped"
PACKET_TESTS = "node and instance-box tests: packets"
REST = "walks' control, ray generation, the tile loop (the rest of raylab)"

# Each category and the inlined functions filed under it.
CATEGORIES = {
    "instanced leaves: object triangles loaded and carried into the world (f64)": ["world_lanes"],
    "leaves: f32 preparation for the eye": [
        "new8_from_lanes", "new8_from", "prepare_leaf", "prepare_block", "prepare_corners",
    ],
    "leaves: f64 preparation (lanes f32 left undecided)": ["precise", "take_precise"],
    "leaves: tests of the prepared triangles": [
        "offer_block_to_lane", "offer_leaf_to_lanes", "take_decided", "offer_decided",
        "offer_as", "offer_each", "lane_decision",
    ],
    "node tests: one lane, 8 boxes": ["push_lane"],
    STACK: ["insert", "pop_above", "top_above"],
    "prefetches": ["prefetch"],
    PACKET_TESTS: ["enter", "lanes"],
    "instances: rays carried into the mesh's frame": ["carry_origin", "carry_directions", "new_in"],
    "pixels: colours": ["color_run"],
}
# Function name -> its category, looked up innermost first along a sample's chain.
RULES = {name: cat for cat, names in CATEGORIES.items() for name in names}


def symbols(binary):
    """Function name (mangled) -> file address."""
    out = subprocess.run(["nm", binary], capture_output=True, text=True, check=True).stdout
    table = {}
    for line in out.splitlines():
        parts = line.split(" ", 2)
        if len(parts) == 3 and parts[0] and parts[1] in "tTwW":
            table.setdefault(parts[2], int(parts[0], 16))
    return table


def samples(data, binary):
    """Counts per file address of `binary`, and the count of samples elsewhere."""
    table = symbols(binary)
    out = subprocess.run(
        ["perf", "script", "-i", data, "-F", "ip,sym,symoff,dso", "--no-demangle"],
        capture_output=True, text=True, check=True,
    ).stdout
    counts, elsewhere = collections.Counter(), 0
    for line in out.splitlines():
        m = re.match(r"\s*[0-9a-f]+ (.*)\+0x([0-9a-f]+) \((.*)\)", line)
        if m and m.group(1) in table and os.path.basename(m.group(3)) == os.path.basename(binary):
            counts[table[m.group(1)] + int(m.group(2), 16)] += 1
        elif line.strip():
            elsewhere += 1
    return counts, elsewhere


def short(name):
    """A function's name without its generic arguments, its path or its hash."""
    name = re.sub(r"::h[0-9a-f]{16}$", "", name)
    while True:
        stripped = re.sub(r"<[^<>]*>", "", name)
        if stripped == name:
            return name.split("::")[-1]
        name = stripped


def chains(binary, addresses):
    """Address -> its inlined functions' short names, innermost first. (llvm-symbolizer:
    binutils' addr2line names the innermost frame of the first address it looks up in a
    unit by its outermost symbol, and elfutils' takes minutes.)"""
    out = subprocess.run(
        ["llvm-symbolizer", f"--obj={binary}", "--inlining", "--demangle", "--print-address"],
        input="\n".join(hex(a) for a in addresses), capture_output=True, text=True, check=True,
    ).stdout
    result, current, expect_function = {}, None, True
    for line in out.splitlines():
        if re.fullmatch(r"0x[0-9a-f]+", line):
            current, expect_function = int(line, 16), True
            result[current] = []
        elif current is not None and line:
            if expect_function:
                result[current].append(short(line))
            expect_function = not expect_function
    return result


def category(chain):
    """The category of the first function of `chain` (innermost first) that `RULES` names."""
    for at, name in enumerate(chain):
        if name == "push":
            # The stack's own push (one-lane walks, per-ray walks) or a packet's child test.
            outer = chain[at + 1] if at + 1 < len(chain) else ""
            return STACK if outer in ("push_lane", "traverse") else PACKET_TESTS
        if name in RULES:
            return RULES[name]
    return REST


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--binary", default="target/release/raylab")
    parser.add_argument("--freq", type=int, default=2000, help="samples a second")
    parser.add_argument("--data", help="read this perf.data (of --binary) instead of recording")
    parser.add_argument("args", nargs=argparse.REMAINDER, help="-- then raylab's arguments")
    opts = parser.parse_args()
    args = opts.args[1:] if opts.args[:1] == ["--"] else opts.args
    if opts.data:
        counts, elsewhere = samples(opts.data, opts.binary)
    else:
        counts, elsewhere = record(opts.binary, opts.freq, args)
    report(opts.binary, opts.freq, counts, elsewhere)


def record(binary, freq, args):
    """Runs raylab under perf; the samples by address."""
    with tempfile.NamedTemporaryFile(suffix=".data") as data:
        run = subprocess.run(
            ["perf", "record", "-q", "-e", "cpu-clock", "-F", str(freq), "-o", data.name,
             "--", binary, *args],
            capture_output=True, text=True,
        )
        if run.returncode != 0:
            sys.exit(f"perf record failed:\n{run.stderr}")
        for line in run.stdout.splitlines():
            if line.startswith("median frame"):
                print(f"raylab: {line}")
        return samples(data.name, binary)


def report(binary, freq, counts, elsewhere):
    """The samples' shares by category, as a markdown table."""
    names = chains(binary, sorted(counts))
    shares = collections.Counter()
    for address, n in counts.items():
        shares[category(names.get(address, []))] += n
    shares["outside raylab (kernel, libc)"] += elsewhere
    total = sum(shares.values())
    print(f"{total} samples at {freq}/s\n")
    print("| where | share of samples |")
    print("|---|---|")
    for cat, n in shares.most_common():
        print(f"| {cat} | {100 * n / total:.1f}% |")


if __name__ == "__main__":
    main()
