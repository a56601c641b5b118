#!/usr/bin/env bash
# Builds an integrator's crate outside the workspace with exactly README's dependency lines
# ("Integrating nav-fsw"), for thumbv7em-none-eabihf and for the host, and runs its host test.
# README's integration snippet must be the crate's src/readme.rs, so it is compiled too.
# The crate's source is examples/integrator; its Cargo.toml must carry the same lines.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
readme_lines="$(awk '/<!-- integrator-dependencies/ {found = 1; next}
  found && /^```toml/ {inside = 1; next}
  inside && /^```/ {exit}
  inside {print}' "$root/README.md")"
if [ -z "$readme_lines" ]; then
  echo "FAIL: README.md has no integrator-dependencies block" >&2
  exit 1
fi
example_lines="$(awk '/^\[dependencies\]/ {inside = 1; print; next}
  inside && /^\[/ {exit}
  inside && NF {print}' "$root/examples/integrator/Cargo.toml")"
if [ "$readme_lines" != "$example_lines" ]; then
  printf 'FAIL: examples/integrator/Cargo.toml [dependencies] differ from README.md:\n%s\n---\n%s\n' \
    "$example_lines" "$readme_lines" >&2
  exit 1
fi
# The README's integration snippet is examples/integrator/src/readme.rs, which the crate compiles
# and its test runs: it cannot drift from the API.
readme_snippet="$(awk '/<!-- integrator-snippet/ {found = 1; next}
  found && /^```rust/ {inside = 1; next}
  inside && /^```/ {exit}
  inside {print}' "$root/README.md")"
if [ "$readme_snippet" != "$(cat "$root/examples/integrator/src/readme.rs")" ]; then
  echo "FAIL: README.md's integrator-snippet block differs from examples/integrator/src/readme.rs" >&2
  diff <(printf '%s\n' "$readme_snippet") "$root/examples/integrator/src/readme.rs" >&2 || true
  exit 1
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cp -r "$root/examples/integrator/src" "$work/src"
{
  printf '[package]\nname = "nav-integrator-example"\nversion = "0.1.0"\nedition = "2021"\npublish = false\n\n'
  printf '%s\n\n' "$readme_lines"
  printf '[patch.crates-io]\nnav-fsw = { path = "%s/nav-fsw" }\n' "$root"
} > "$work/Cargo.toml"
echo "outside the workspace: $work/Cargo.toml"
sed 's/^/    /' "$work/Cargo.toml"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$root/target}/integrator"
(cd "$work" && cargo build --release --target thumbv7em-none-eabihf)
(cd "$work" && cargo test)
