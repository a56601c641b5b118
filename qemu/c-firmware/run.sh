#!/usr/bin/env bash
# Runs the C firmware on QEMU as qemu/run.sh runs the Rust one, with its plain text output
# (no defmt frames to decode).
set -euo pipefail
QEMU_PLAIN_OUTPUT=1 exec "$(dirname "${BASH_SOURCE[0]}")/../run.sh" "$@"
