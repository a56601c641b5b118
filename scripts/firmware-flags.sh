# Sourced by scripts/test.sh, scripts/results.sh and scripts/bench-target.sh: builds the
# Cortex-M7 firmware so that its bytes (and with them its flash size and its instruction counts
# under QEMU, which docs/results/ holds and the tests compare exactly) do not depend on where
# the checkout or the cargo registry lies.
#
# Two things would make them depend on it:
# - file paths compiled into the binary: remapped below (`--remap-path-prefix`);
# - cargo's crate hashes (`-C metadata`), which for a path dependency outside the building
#   workspace (qemu/ depends on ../nav-core and ../nav-fsw) include its absolute path. The
#   hashes order the functions LLVM optimises, so another checkout path gives other register
#   allocation and a few instructions more or fewer per frame. `firmware_cargo` therefore
#   builds through a fixed symbolic link to the checkout ($firmware_checkout): cargo takes
#   the manifest's path as given, so every checkout compiles from the same paths.
# The link is one per machine: two checkouts cannot build the firmware at the same moment.
# shellcheck shell=bash
firmware_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
firmware_checkout=/tmp/nav-fw-checkout
export CARGO_TARGET_THUMBV7EM_NONE_EABIHF_RUSTFLAGS="--remap-path-prefix ${firmware_root}=/nav-fw --remap-path-prefix ${firmware_checkout}=/nav-fw --remap-path-prefix ${CARGO_HOME:-$HOME/.cargo}=/cargo"

# `cargo "$@"` for the firmware workspace (qemu/), through the fixed link. Cargo reads its
# configuration from the working directory (the real qemu/), and builds into qemu/target.
firmware_cargo() {
  ln -sfn "$firmware_root" "$firmware_checkout"
  local subcommand="$1"
  shift
  (cd "$firmware_root/qemu" && cargo "$subcommand" --manifest-path "$firmware_checkout/qemu/Cargo.toml" "$@")
}

# Builds the C firmware (qemu/c-firmware) into ELF: nav-c's static library for the Cortex-M7
# (fat LTO and abort on panic, as the Rust firmware's release profile; the FPU's square root;
# the static library alone, since cargo applies no LTO to a build that also makes the rlib),
# built through the same fixed link, then the C code with arm-none-eabi-gcc linked against it.
c_firmware_build() {
  local elf="$1"
  ln -sfn "$firmware_root" "$firmware_checkout"
  (cd "$firmware_checkout" && CARGO_PROFILE_RELEASE_LTO=fat CARGO_PROFILE_RELEASE_PANIC=abort \
    cargo rustc --manifest-path "$firmware_checkout/Cargo.toml" -p nav-c --release \
    --target thumbv7em-none-eabihf --features hardware-sqrt --crate-type staticlib)
  bash "$firmware_root/qemu/c-firmware/build.sh" \
    "${CARGO_TARGET_DIR:-$firmware_root/target}/thumbv7em-none-eabihf/release/libnav_c.a" "$elf"
}
