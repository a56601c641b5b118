# Sourced by scripts/test.sh and scripts/results.sh: path remapping for the Cortex-M7 build,
# so the firmware's bytes (and with them its flash size and its instruction counts under
# QEMU, which docs/results/ holds) do not depend on where the checkout or the cargo registry
# lies. Cargo adds these to the target's `rustflags` of .cargo/config.toml.
# shellcheck shell=bash
firmware_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export CARGO_TARGET_THUMBV7EM_NONE_EABIHF_RUSTFLAGS="--remap-path-prefix ${firmware_root}=/nav-fw --remap-path-prefix ${CARGO_HOME:-$HOME/.cargo}=/cargo"
