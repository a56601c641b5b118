#!/usr/bin/env python3
"""Truncate an ICGEM gravity-field file (.gfc) to a maximum degree.

Usage: truncate_gfc.py SOURCE.gfc MAX_DEGREE OUTPUT.gfc

The header is copied verbatim except the value of its `max_degree` line, which becomes
MAX_DEGREE; after `end_of_head`, every `gfc L M ...` line with L <= MAX_DEGREE is copied
verbatim, in its original order, and every other line is dropped. No coefficient is
changed. Prints the SHA-256 of SOURCE and of OUTPUT (nav-sim/data/README.md records both).
"""

import hashlib
import sys


def sha256(path):
    with open(path, "rb") as handle:
        return hashlib.sha256(handle.read()).hexdigest()


def truncate(source, max_degree, output):
    in_header = True
    kept = 0
    with open(source, encoding="ascii") as inp, open(output, "w", encoding="ascii") as out:
        for line in inp:
            if in_header:
                words = line.split()
                if words and words[0] == "max_degree":
                    value_at = line.index(words[1])
                    line = line[:value_at] + str(max_degree) + "\n"
                if words and words[0] == "end_of_head":
                    in_header = False
                out.write(line)
                continue
            words = line.split()
            if words and words[0] == "gfc" and int(words[1]) <= max_degree:
                out.write(line)
                kept += 1
    if in_header:
        sys.exit(f"{source}: no end_of_head line")
    return kept


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    source, max_degree, output = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    kept = truncate(source, max_degree, output)
    print(f"{kept} coefficient lines up to degree {max_degree}")
    print(f"sha256 {sha256(source)}  {source}")
    print(f"sha256 {sha256(output)}  {output}")


if __name__ == "__main__":
    main()
