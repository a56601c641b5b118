#!/usr/bin/env bash
# The project's one test command (README "Tests"; .ci/run calls exactly this).
#
# 1. installs what is missing (idempotent): the thumbv7em-none-eabihf target, llvm-tools,
#    qemu-system-arm (apt-get when root), defmt-print;
# 2. formatting, clippy (host workspace and firmware workspace) and the workspace's API docs
#    with warnings as errors;
# 3. host tests (with the docs' figure check and the default flight's change indication), then
#    the fault-injection campaign with its table and the host commands' results compared with
#    docs/results/, then the docs' Slurm recipe on a single-node Slurm (munge, slurmctld,
#    slurmd: apt-get when root);
# 4. the firmware build for the Cortex-M7, with a disassembly check that f64 arithmetic is
#    hardware double precision (vmul.f64/vadd.f64, no __aeabi_d* soft-float calls);
# 5. the panic-free flight build, and proof that it rejects a deliberately added panic path;
# 6. the target checks on QEMU (decoded defmt log shown), then the host tests that compare
#    the target's results with the host's bit for bit, and its measured cost, stack, flash and
#    RAM with docs/results/ (a difference fails: regenerate with scripts/results.sh qemu);
#    the C firmware (qemu/c-firmware, arm-none-eabi-gcc against nav-c) replays the same
#    scenarios bit for bit, its interface's cost compared with the Rust firmware's.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
export PATH="$HOME/.cargo/bin:$PATH"
TARGET=thumbv7em-none-eabihf
step() { printf "\n==== %s  [t=%d s]\n" "$*" "$SECONDS"; }
# The firmware's flags, with its paths remapped (its measured figures are compared exactly).
source scripts/firmware-flags.sh

step "prerequisites"
if ! rustup target list --installed | grep -qx "$TARGET"; then rustup target add "$TARGET"; fi
for component in llvm-tools rustfmt clippy; do
  if ! rustup component list --installed | grep -q "^$component"; then rustup component add "$component"; fi
done
if ! command -v qemu-system-arm >/dev/null; then
  if [ "$(id -u)" = 0 ]; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq qemu-system-arm >/dev/null
  else
    echo "qemu-system-arm is missing: install it (Debian/Ubuntu: sudo apt-get install qemu-system-arm)" >&2
    exit 1
  fi
fi
# The C firmware's toolchain (qemu/c-firmware): Debian's arm-none-eabi-gcc and newlib.
if ! command -v arm-none-eabi-gcc >/dev/null; then
  if [ "$(id -u)" = 0 ]; then
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
      gcc-arm-none-eabi libnewlib-arm-none-eabi >/dev/null
  else
    echo "arm-none-eabi-gcc is missing: install it (Debian/Ubuntu: sudo apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi)" >&2
    exit 1
  fi
fi
if ! command -v defmt-print >/dev/null; then cargo install --locked defmt-print; fi
if ! command -v cargo-fuzz >/dev/null; then cargo install --locked cargo-fuzz; fi
qemu-system-arm --version | head -1
arm-none-eabi-gcc --version | head -1
defmt-print --version
llvm_bin="$(rustc --print sysroot)/lib/rustlib/$(rustc -vV | sed -n 's/^host: //p')/bin"

step "format"
cargo fmt --all --check
(cd qemu && cargo fmt --check)

step "clippy (host workspace, all targets)"
cargo clippy --workspace --all-targets -- -D warnings
step "clippy (firmware workspace, $TARGET)"
(cd qemu && cargo clippy --release --bins --features panic-never -- -D warnings)

step "API docs of the workspace (warnings are errors)"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps

step "an integrator's crate outside the workspace, with README's dependency lines ($TARGET and host)"
(cd examples/integrator && cargo fmt --check)
bash scripts/integrator-check.sh
step "the flight crates package for a registry (cargo package, verified)"
# In a fresh target directory: cargo extracts the packaged crates into a cache keyed by the
# target directory's path and never re-extracts the same name and version, so a reused path
# would verify nav-fsw against an older packaged nav-core.
package_dir="$(mktemp -d)"
cargo package -p nav-core -p nav-fsw --allow-dirty --target-dir "$package_dir"
rm -rf "$package_dir"

step "host tests"
cargo test --workspace

step "fault-injection campaign (nav_sim::studies::faults): the table, every row met"
# --workspace: the same feature set as the host tests above, so nothing is compiled again.
cargo test --workspace --test fault_campaign -- --include-ignored --nocapture

step "the host commands' measured tables written again and compared with docs/results/"
bash scripts/results.sh check

step "the Slurm recipe of docs/guide/monte-carlo.md on a single-node Slurm: sharded campaign merged = one-process campaign"
bash scripts/slurm-check.sh

step "fuzzing the firmware's input decoders (cargo-fuzz on stable, --sanitizer none, 30 s)"
# New inputs go to a scratch corpus; the kept corpus (fuzz/corpus/log_decoder) is only read.
mkdir -p target/fuzz-corpus
if ! cargo fuzz run log_decoder --sanitizer none target/fuzz-corpus fuzz/corpus/log_decoder -- \
  -max_total_time=30 > target/fuzz.log 2>&1; then
  tail -40 target/fuzz.log
  echo "FAIL: the fuzzer found a crash (input saved under fuzz/artifacts/log_decoder/)" >&2
  exit 1
fi
grep -E "^Done [0-9]+ runs" target/fuzz.log

step "firmware build ($TARGET, cortex-m7)"
firmware_cargo build --release --bin checks
# Honour CARGO_TARGET_DIR (absolute) for the firmware too; the logs stay under ./target.
checks_elf="${CARGO_TARGET_DIR:-qemu/target}/$TARGET/release/checks"
mkdir -p target
"$llvm_bin/llvm-objdump" -d --mcpu=cortex-m7 "$checks_elf" > target/checks.dis
hardware_mul=$(grep -c 'vmul\.f64' target/checks.dis || true)
hardware_add=$(grep -c 'vadd\.f64' target/checks.dis || true)
soft_float=$(grep -cE '__aeabi_d(add|sub|mul|div)' target/checks.dis || true)
echo "disassembly: ${hardware_mul} vmul.f64, ${hardware_add} vadd.f64, ${soft_float} soft-float calls"
if [ "$hardware_mul" -eq 0 ] || [ "$soft_float" -ne 0 ]; then
  echo "FAIL: f64 arithmetic is not hardware double precision" >&2
  exit 1
fi
"$llvm_bin/llvm-size" "$checks_elf"

step "panic-free flight build"
firmware_cargo build --release --bin flight --no-default-features --features panic-never,state-blocks
echo "flight build links with no panic path"
step "the flight binary holds no dense reference, ground analysis or self-test code"
flight_elf="$(cd "$(dirname "${CARGO_TARGET_DIR:-qemu/target}/$TARGET/release/flight")" && pwd)/flight"
"$llvm_bin/llvm-nm" --demangle "$flight_elf" > target/flight.nm
# The modules and functions each feature adds (nav-core `dense-reference`, `ground-analysis`,
# `selftest`; nav-fsw `dense-reference`, `ground-analysis`).
if grep -E 'nav_core::(selftest|observability|discretise::discretise|arithmetic::dense)|reset_dense|update_with_frozen_blocks|update_bordered_dense|measurement::refer_to_later_time::|MotionObservabilityTable::compute|ErrorStateFilter::predict::' target/flight.nm; then
  echo "FAIL: the flight build compiles reference or ground-analysis code (symbols above)" >&2
  exit 1
fi
echo "none of their symbols in the flight ELF ($(wc -l < target/flight.nm) symbols)"
step "no recursion and no indirect call in the flight binary's call graph"
"$llvm_bin/llvm-objdump" -d --no-show-raw-insn --mcpu=cortex-m7 "$flight_elf" > target/flight.dis
NAV_FLIGHT_ELF="$flight_elf" NAV_FLIGHT_DISASSEMBLY="$root/target/flight.dis" \
  cargo test --workspace --test call_graph -- --include-ignored --nocapture
step "panic-free build rejects a deliberately added panic path"
if firmware_cargo build --release --bin flight --no-default-features --features panic-never,demo-panic-path > target/demo-panic.log 2>&1; then
  echo "FAIL: the panic-never build accepted a slice index that can panic" >&2
  exit 1
fi
grep -o 'undefined symbol: panic_path_reachable_in_flight_build' target/demo-panic.log | head -1
echo "as expected, the link failed on the injected panic path"

step "target checks on QEMU (mps2-an500, -icount shift=0), decoded defmt log"
mkdir -p target/qemu
firmware_cargo run --release --bin checks | tee target/qemu/checks.log
step "stack overflow faults on the MPU guard (must fail with a HardFault)"
firmware_cargo build --release --bin stack_guard_demo
guard_elf="${CARGO_TARGET_DIR:-qemu/target}/$TARGET/release/stack_guard_demo"
if QEMU_TIMEOUT_S=60 qemu/run.sh "$guard_elf" > target/qemu/stack-guard.log 2>&1; then
  cat target/qemu/stack-guard.log
  echo "FAIL: the stack overflow was not caught" >&2
  exit 1
fi
cat target/qemu/stack-guard.log
grep -q "HardFault" target/qemu/stack-guard.log
grep -q "STACK depth 3072 KiB" target/qemu/stack-guard.log
echo "as expected, the overflow faulted at the guard after using the whole stack region"
step "flight build on QEMU"
firmware_cargo run --release --bin flight --no-default-features --features panic-never,state-blocks
step "flight build without the optional features (state blocks, gravity field beyond J2; panic-free, on QEMU): the computer's size"
firmware_cargo run --release --bin flight --no-default-features --features panic-never | tee target/qemu/flight-no-blocks.log
grep -E "^NavigationComputer: [0-9]+ bytes" target/qemu/flight-no-blocks.log
# The bound a mission without the optional features is held to (bytes of static RAM).
no_features_bound=26000
no_features_size=$(awk '/^NavigationComputer: [0-9]+ bytes/ { print $2; exit }' target/qemu/flight-no-blocks.log)
if [ -z "$no_features_size" ] || [ "$no_features_size" -gt "$no_features_bound" ]; then
  echo "FAIL: NavigationComputer without the optional features is ${no_features_size:-unknown} bytes, above $no_features_bound" >&2
  exit 1
fi
echo "NavigationComputer without the optional features: within $no_features_bound bytes"

step "bit-for-bit: host build vs Cortex-M7 build"
NAV_QEMU_CHECKS_LOG="$root/target/qemu/checks.log" \
  cargo test --workspace --test target_bit_exact -- --include-ignored --nocapture

step "whole-scenario replay: host vs Cortex-M7 on QEMU, 500 Hz SysTick frames, bit for bit"
firmware_cargo build --release --bin replay
NAV_QEMU_REPLAY_ELF="${CARGO_TARGET_DIR:-$root/qemu/target}/$TARGET/release/replay" NAV_REPLAY_SECONDS="${NAV_REPLAY_SECONDS:-300}" \
  cargo test --workspace --test replay_bit_exact -- --include-ignored --nocapture

step "whole-scenario replay from C: C firmware (arm-none-eabi-gcc, nav-c's static library) on QEMU, bit for bit with the host, the interface's cost"
mkdir -p target/qemu
c_firmware_build "$root/target/qemu/c-replay.elf"
# The library behind the C interface has no panic path: with fat LTO nothing reaches
# core::panicking or the panic handler, so neither is in the library or the C firmware.
if "$llvm_bin/llvm-nm" --demangle "${CARGO_TARGET_DIR:-$root/target}/$TARGET/release/libnav_c.a" \
  "$root/target/qemu/c-replay.elf" 2>/dev/null | grep -E 'core::panicking|rust_begin_unwind'; then
  echo "FAIL: nav-c's static library has a panic path (symbols above)" >&2
  exit 1
fi
echo "nav-c's static library and the C firmware: no panic path"
NAV_QEMU_C_REPLAY_ELF="$root/target/qemu/c-replay.elf" NAV_REPLAY_SECONDS="${NAV_REPLAY_SECONDS:-300}" \
  cargo test --workspace --test c_replay_bit_exact -- --include-ignored --nocapture

step "replay over serial lines: one CMSDK UART per sensor on QEMU, clean and corrupted, bit for bit with the host; its telemetry packets from UART4 decoded, word for word with the host"
firmware_cargo build --release --bin uart_replay
NAV_QEMU_UART_REPLAY_ELF="${CARGO_TARGET_DIR:-$root/qemu/target}/$TARGET/release/uart_replay" \
  cargo test --workspace --test uart_replay -- --include-ignored --nocapture --test-threads 1
printf "\n==== done  [t=%d s]\n" "$SECONDS"
