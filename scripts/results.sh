#!/usr/bin/env bash
# Regenerates the measured results under docs/results/ (the tables the docs include) and the
# change indication (tests-host/change_indication/default.csv), then copies the results into
# the pages' results blocks. Run it after a change that moves a figure, and commit the diff.
#   scripts/results.sh          host results and the QEMU results
#   scripts/results.sh host     the nav-sim commands' results and the change indication
#   scripts/results.sh qemu     cost, stack, flash and RAM on the Cortex-M7 under QEMU
#   scripts/results.sh check    (scripts/test.sh) the host commands' results written into
#                               target/results and compared with docs/results/
# QEMU figures are deterministic (-icount) for one firmware binary: any change of the flight
# code or the compiler changes them, and scripts/test.sh then fails until they are regenerated.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
TARGET=thumbv7em-none-eabihf
what="${1:-all}"
# The firmware's flags as scripts/test.sh builds it, so the figures are the ones it compares.
source scripts/firmware-flags.sh

# The host commands whose tables the docs include: `nav-sim ARGS --results DIR`, one per line.
host_commands=(
  "calibrate"
  "calibrate nav-sim/scenarios/upper_stage.toml"
  "calibrate nav-sim/scenarios/paper_strategy_as_printed.toml"
  "monte-carlo --runs 10"
  "monte-carlo nav-sim/scenarios/as_it_is.toml --runs 40"
  "monte-carlo nav-sim/scenarios/upper_stage_as_it_is.toml --runs 40"
  "benefit"
  # The consistency flags' false alarms on the clean flights (the upper stage: about a CPU
  # minute per run).
  "false-alarms --runs 100"
  "false-alarms nav-sim/scenarios/realistic_sensors.toml --runs 100"
  "false-alarms nav-sim/scenarios/upper_stage.toml --runs 100"
)
# The cheap ones scripts/test.sh measures again and compares.
checked_commands=(
  "calibrate"
)

run_host() {
  local binary="$1" directory="$2"
  shift 2
  for command in "$@"; do
    # shellcheck disable=SC2086 # the command's words
    nice "$binary" $command --results "$directory" > /dev/null
  done
}

bless_tests() {
  NAV_RESULTS_BLESS=1 cargo test --workspace "$@"
}

case "$what" in
  all | host | qemu | check) ;;
  *)
    echo "usage: scripts/results.sh [host|qemu|check]" >&2
    exit 2
    ;;
esac

# The test profile's binary (opt-level 2; the bits are a release build's): scripts/test.sh has
# built it with the host tests.
binary="${CARGO_TARGET_DIR:-$root/target}/debug/nav-sim"

if [ "$what" = check ]; then
  directory="$root/target/results"
  rm -rf "$directory"
  run_host "$binary" "$directory" "${checked_commands[@]}"
  for file in "$directory"/*.md; do
    if ! diff -u "docs/results/$(basename "$file")" "$file"; then
      echo "FAIL: docs/results/$(basename "$file") differs from a fresh run (above);" \
        "if the change is intended, run scripts/results.sh host and commit the diff" >&2
      exit 1
    fi
  done
  echo "the host results are the committed ones: ${checked_commands[*]}"
  exit 0
fi

if [ "$what" = all ] || [ "$what" = host ]; then
  cargo build --profile test -p nav-sim --bin nav-sim
  run_host "$binary" docs/results "${host_commands[@]}"
  bless_tests --test change_indication
  bless_tests --test fault_campaign -- --include-ignored
fi

if [ "$what" = all ] || [ "$what" = qemu ]; then
  firmware_cargo build --release --bin checks --bin replay
  elf_dir="${CARGO_TARGET_DIR:-$root/qemu/target}/$TARGET/release"
  mkdir -p target/qemu
  firmware_cargo run --release --bin checks > target/qemu/checks.log
  NAV_QEMU_CHECKS_LOG="$root/target/qemu/checks.log" bless_tests --test target_bit_exact -- --include-ignored
  NAV_QEMU_REPLAY_ELF="$elf_dir/replay" NAV_REPLAY_SECONDS=300 \
    bless_tests --test replay_bit_exact -- --include-ignored
  c_firmware_build "$root/target/qemu/c-replay.elf"
  NAV_QEMU_C_REPLAY_ELF="$root/target/qemu/c-replay.elf" NAV_REPLAY_SECONDS=300 \
    bless_tests --test c_replay_bit_exact -- --include-ignored
fi

NAV_RESULTS_BLESS=1 cargo test --workspace --test doc_figures
git status --short docs/results tests-host/change_indication docs README.md
