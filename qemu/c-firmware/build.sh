#!/usr/bin/env bash
# Builds the C firmware (qemu/c-firmware/*.c) with Debian's arm-none-eabi-gcc against nav-c's
# static library for thumbv7em-none-eabihf: `build.sh LIBRARY OUTPUT-ELF`. The library is
# built by scripts/test.sh (cargo build -p nav-c --release --target thumbv7em-none-eabihf).
# C99 with every warning an error; `-ffp-contract=off` keeps the C code's arithmetic as
# written (it does none on the navigation path: the library's is Rust's, never contracted).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
library="$1"
elf="$2"
arm-none-eabi-gcc -mcpu=cortex-m7 -mthumb -mfpu=fpv5-d16 -mfloat-abi=hard \
  -std=c99 -O2 -g -Wall -Wextra -Werror -ffp-contract=off -ffunction-sections -fdata-sections \
  -I "$here/../../nav-c/include" -I "$here" \
  -nostartfiles -T "$here/link.ld" -L "$here/../.." \
  "$here/startup.c" "$here/semihosting.c" "$here/main.c" "$library" \
  -Wl,--gc-sections -Wl,-z,noexecstack -lc -lgcc -o "$elf"
