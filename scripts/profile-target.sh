#!/usr/bin/env bash
# Instruction profile of one IMU-only, one star and one late-GNSS frame on the Cortex-M7
# target: builds the `profile` firmware, runs it on QEMU with the execution trace
# on (-d exec,nochain,in_asm) and attributes every instruction of the bracketed frames to
# its function and source line (scripts/profile-target.py; needs python3 and binutils'
# addr2line). Usage: scripts/profile-target.sh [TOP-N] > profile.txt
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
top="${1:-30}"
(cd "$root/qemu" && cargo build --release --bin profile >&2)
elf="${CARGO_TARGET_DIR:-$root/qemu/target}/thumbv7em-none-eabihf/release/profile"
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
qemu-system-arm -cpu cortex-m7 -machine mps2-an500 -nographic -monitor none -serial none \
  -semihosting-config enable=on,target=native -icount shift=0,sleep=off \
  -kernel "$elf" -d exec,nochain,in_asm -D "$log" > /dev/null
python3 "$root/scripts/profile-target.py" "$elf" "$log" "$top"
