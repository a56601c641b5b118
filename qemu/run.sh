#!/usr/bin/env bash
# The QEMU runner for the firmware (cargo's `runner`, see the root .cargo/config.toml):
# runs ELF on QEMU's MPS2-AN500 (Cortex-M7) with semihosting and deterministic instruction
# counting (-icount shift=0: one instruction = 1 ns of virtual time), and decodes the defmt
# frames the firmware writes to semihosting stdout with `defmt-print -e ELF`. `sleep=off`:
# when the core idles in WFI (the replay waiting for its next frame interrupt), virtual time
# jumps to the next timer event instead of waiting in real time.
# The exit status is the firmware's semihosting exit code (0 = all checks passed).
set -euo pipefail
elf="$1"
shift || true
: "${QEMU_TIMEOUT_S:=600}"
# QEMU_SERIAL: the serial chardevs, UART0 first (default: none); e.g. the UART replay's
# "-serial pipe:DIR/ground -serial pipe:DIR/imu ...".
read -r -a serial_args <<< "${QEMU_SERIAL:--serial none}"
qemu() {
  timeout "$QEMU_TIMEOUT_S" qemu-system-arm \
    -cpu cortex-m7 -machine mps2-an500 -nographic -monitor none "${serial_args[@]}" \
    -semihosting-config enable=on,target=native -icount shift=0,sleep=off \
    -kernel "$elf" "$@"
}
# QEMU_PLAIN_OUTPUT=1: a firmware that prints plain text (the C firmware,
# qemu/c-firmware/run.sh), not defmt frames.
if [ "${QEMU_PLAIN_OUTPUT:-0}" = 1 ]; then
  qemu "$@"
else
  qemu "$@" | defmt-print -e "$elf"
fi
