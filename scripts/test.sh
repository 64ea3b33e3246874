#!/usr/bin/env bash
# Runs everything that must pass: formatting, lints, and every test of the workspace.
# On a fresh machine it installs what the tests need from Debian's packages: Verilator (with
# g++ and make, to build its simulations; gcc and g++ also build the C ABI's C and C++
# examples), Icarus Verilog, yosys (the gate-level run and the
# synthesis analysis), tclsh (the ISE script's check) and ccache (Verilator's builds compile
# its runtime once through it instead of once a build). A missing tool is installed or the
# script fails: no test is skipped for want of one.
set -euo pipefail
cd "$(dirname "$0")/.."

# The machine's Rust toolchain ships cargo, rustfmt and clippy; nothing else can be fetched.
for tool in "cargo --version" "cargo fmt --version" "cargo clippy --version"; do
  $tool >/dev/null 2>&1 || { echo "error: '$tool' failed: the Rust toolchain is incomplete" >&2; exit 1; }
done

need=()
command -v verilator >/dev/null 2>&1 || need+=(verilator)
command -v iverilog >/dev/null 2>&1 || need+=(iverilog)
command -v g++ >/dev/null 2>&1 || need+=(g++)
command -v cc >/dev/null 2>&1 || need+=(gcc)
command -v c++ >/dev/null 2>&1 || need+=(g++)
command -v make >/dev/null 2>&1 || need+=(make)
command -v tclsh >/dev/null 2>&1 || need+=(tcl)
command -v yosys >/dev/null 2>&1 || need+=(yosys)
command -v ccache >/dev/null 2>&1 || need+=(ccache)
if [ ${#need[@]} -gt 0 ]; then
  if [ "$(id -u)" != 0 ]; then
    echo "error: missing ${need[*]}; run as root (or install them) so that the HDL tests can run" >&2
    exit 1
  fi
  echo "installing ${need[*]}"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi
verilator --version
yosys -V

cargo fmt --all -- --check
cargo clippy --workspace --all-targets --locked -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --document-private-items --locked
cargo test --workspace --locked
