#!/usr/bin/env bash
# Runs everything that must pass: formatting, lints, and every test of the workspace.
# Installs what the tests need on a fresh machine (today: only the Rust toolchain, already there).
set -euo pipefail
cd "$(dirname "$0")/.."

# The machine's Rust toolchain ships cargo, rustfmt and clippy; nothing else can be fetched.
for tool in "cargo --version" "cargo fmt --version" "cargo clippy --version"; do
  $tool >/dev/null 2>&1 || { echo "error: '$tool' failed: the Rust toolchain is incomplete" >&2; exit 1; }
done

cargo fmt --all -- --check
cargo clippy --workspace --all-targets --locked -- -D warnings
cargo test --workspace --locked
