#!/usr/bin/env bash
# Target benchmark: builds the replay firmware and runs `nav-sim target-bench`,
# which replays the first SECONDS (default 60) of the scenario (default: the built-in one) on
# QEMU and on the host, checks bit-for-bit agreement and prints the per-frame cost by frame
# type, the stack high-water mark and the image's flash and static RAM.
#   scripts/bench-target.sh [SECONDS] [SCENARIO.toml]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
# The firmware as scripts/test.sh builds it (paths remapped), so its figures compare.
source scripts/firmware-flags.sh
seconds="${1:-60}"
firmware_cargo build --release --bin replay
elf="${CARGO_TARGET_DIR:-qemu/target}/thumbv7em-none-eabihf/release/replay"
cargo run --release -p nav-sim -- target-bench ${2:+"$2"} --elf "$elf" --seconds "$seconds"
