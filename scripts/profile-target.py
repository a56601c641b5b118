#!/usr/bin/env python3
"""Instruction profile of one frame of each kind on the Cortex-M7 target.

Reads QEMU's `-d exec,nochain,in_asm` log of the `profile` firmware (scripts/profile-target.sh),
takes the executions between `profile_window_begin` and `profile_window_end`, counts the
instructions of every executed translation block and attributes each instruction to its
source line and (innermost inlined) function with binutils `addr2line -i -f -C`.

usage: profile-target.py ELF LOG [TOP]
"""
import collections
import re
import subprocess
import sys

elf, log = sys.argv[1], sys.argv[2]
top = int(sys.argv[3]) if len(sys.argv) > 3 else 25
# Optional: print the executed instructions (with counts) of the functions matching this
# pattern, disassembled, for the first window.
annotate = sys.argv[4] if len(sys.argv) > 4 else None

trace = re.compile(r"^Trace \d+: \S+ \[[0-9a-f]+/([0-9a-f]+)/")
instruction = re.compile(r"^0x([0-9a-f]+):")
blocks = {}  # TB start pc -> [instruction addresses]
windows = []  # per window: Counter of instruction address -> executions
current = None
pending = None
calls = []  # per window: Counter of (callee symbol, caller address) for library helpers
previous_pc = None
helper = re.compile(r"(memcpy|memset|memclr|memmove|libm)")
# Library helpers (by address range, from the symbol table): their instructions are also
# attributed to the call site that entered them.
helper_ranges = []
for row in subprocess.run(["nm", "-S", "-C", elf], capture_output=True, text=True).stdout.splitlines():
    parts = row.split(maxsplit=3)
    if len(parts) == 4 and helper.search(parts[3]):
        start, size = int(parts[0], 16), int(parts[1], 16)
        helper_ranges.append((start & ~1, (start & ~1) + size, parts[3].split("(")[0][-40:]))

def helper_symbol(pc):
    for start, end, name in helper_ranges:
        if start <= pc < end:
            return name
    return None

with open(log, errors="replace") as stream:
    for line in stream:
        if line.startswith("IN:"):
            pending = []
            continue
        match = instruction.match(line)
        if match and pending is not None:
            pending.append(int(match.group(1), 16))
            continue
        if pending:
            blocks[pending[0]] = pending
            pending = None
        match = trace.match(line)
        if not match:
            continue
        pc = int(match.group(1), 16)
        if line.rstrip().endswith("profile_window_begin"):
            current = collections.Counter()
            current_calls = collections.Counter()
            continue
        if line.rstrip().endswith("profile_window_end"):
            if current is not None:
                windows.append(current)
                calls.append(current_calls)
            current = None
            continue
        if current is not None:
            for address in blocks.get(pc, [pc]):
                current[address] += 1
            symbol = helper_symbol(pc)
            previous_block = blocks.get(previous_pc, [previous_pc])
            if symbol:
                if previous_pc is not None and not helper_symbol(previous_pc):
                    call_site = (symbol, previous_block[-1])
                current_calls[call_site] += len(blocks.get(pc, [pc]))
        previous_pc = pc

addresses = sorted({a for w in windows for a in w} | {a for c in calls for (_, a) in c})
query = "\n".join(hex(a) for a in addresses)
out = subprocess.run(
    ["addr2line", "-e", elf, "-i", "-f", "-C", "-a"],
    input=query, capture_output=True, text=True, check=True,
).stdout.splitlines()
# Output: address line, then (function, file:line) pairs innermost first.
location = {}
i = 0
while i < len(out):
    address = int(out[i], 16)
    i += 1
    frames = []
    while i < len(out) and not out[i].startswith("0x"):
        frames.append((out[i], out[i + 1]))
        i += 2
    location[address] = frames

def short(function):
    function = re.sub(r"<[^<>]*>", "", function)
    function = re.sub(r"<[^<>]*>", "", function)
    return function.split("(")[0][-90:]

def source(path):
    return re.sub(r"^.*/(nav-core|nav-fsw|qemu|nalgebra[^/]*|libm[^/]*|core)/", r"\1/", path)

names = ["IMU-only frame", "star frame", "late-GNSS frame"]
for index, window in enumerate(windows):
    total = sum(window.values())
    print(f"\n=== {names[index] if index < len(names) else index}: {total} instructions ===")
    by_function = collections.Counter()
    by_line = collections.Counter()
    by_nav_function = collections.Counter()
    by_symbol = collections.Counter()
    by_path = collections.Counter()
    by_phase = collections.Counter()
    for address, count in window.items():
        frames = location.get(address) or [("?", "?")]
        by_function[short(frames[0][0])] += count
        by_line[source(frames[0][1].split(" ")[0])] += count
        # The innermost frame that is our own code (nav-core / nav-fsw / qemu).
        own = next((f for f in frames if re.search(r"/(nav-core|nav-fsw|qemu)/", f[1])), frames[0])
        by_nav_function[short(own[0]) + "  " + source(own[1].split(" ")[0])] += count
        by_symbol[short(frames[-1][0])] += count
        # Own-code call path, outermost first, without the closures' own frames.
        path = [short(f[0]).replace("nav_core::", "").replace("nav_fsw::", "")
                for f in reversed(frames) if re.search(r"/(nav-core|nav-fsw)/", f[1])]
        path = [p for p in path if "{{closure}}" not in p]
        by_path[" > ".join(path[-3:]) or short(frames[0][0])] += count
        by_phase[" > ".join(path[1:4]) or short(frames[0][0])] += count
    by_call = collections.Counter()
    for (symbol, address), count in calls[index].items():
        frames = location.get(address) or [("?", "?")]
        own = next((f for f in frames if re.search(r"/(nav-core|nav-fsw)/", f[1])), frames[0])
        by_call[f"{symbol} <- {short(own[0])} {source(own[1].split(' ')[0])}"] += count
    for title, counter in [("library helper (memcpy, memset, libm) instructions by call site", by_call),
                           ("symbol (outermost, not inlined)", by_symbol),
                           ("own-code call path (last three)", by_path),
                           ("phase (own-code call path, levels 2-4)", by_phase),
                           ("innermost function", by_function),
                           ("own code line (innermost nav-core/nav-fsw frame)", by_nav_function),
                           ("source line", by_line)]:
        print(f"-- by {title}")
        for key, count in counter.most_common(top):
            print(f"{count:8d} {100.0 * count / total:5.1f}%  {key}")

if annotate and windows:
    window = windows[0]
    chosen = sorted(a for a in window
                    if any(re.search(annotate, f[0]) for f in location.get(a, [])))
    disassembly = {}
    for line in subprocess.run(["llvm-objdump", "-d", "--mcpu=cortex-m7", elf],
                               capture_output=True, text=True).stdout.splitlines():
        match = re.match(r"^\s*([0-9a-f]+):\s+(.*)$", line)
        if match:
            disassembly[int(match.group(1), 16)] = match.group(2)
    print(f"\n=== annotated ({annotate}), first window ===")
    for address in chosen:
        frames = location.get(address) or [("?", "?")]
        print(f"{window[address]:6d}  {address:08x}  {disassembly.get(address, '?'):60s} {source(frames[0][1])}")
