#!/usr/bin/env bash
# Mutation testing of the core's emitted Verilog (not part of scripts/test.sh: each mutant takes
# a Verilator build of the whole core, about 26 s on 2 cores). Draws a sample of the default
# core's single mutants, runs each through the co-simulation frames of tests/mutants.rs against
# the bit-exact model (a mutant of the SAT that passes them also through the comparison of every
# axis' sides in the standalone SAT), and prints each verdict, a tally by kind and the
# survivors; the log is kept in target/mutants.log. Needs Verilator (scripts/test.sh installs
# it).
#
#   scripts/mutants.sh [COUNT [SEED [MATCH]]]
#
# COUNT mutants (default 40) drawn with SEED (default 1) from those whose module name contains
# MATCH, or whose kind is MATCH (compare, arithmetic, logic, shift, invert, constant, condition,
# swap, bypass); default: all. With MUTANTS_ONLY set (e.g. MUTANTS_ONLY=7,12, numbers as a run
# prints them), only those of the sample run: how a survivor is judged again after a new test.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v verilator >/dev/null 2>&1 || { echo "error: verilator is missing (scripts/test.sh installs it)" >&2; exit 1; }
mkdir -p target
MUTANTS="${1:-40}" MUTANTS_SEED="${2:-1}" MUTANTS_MATCH="${3:-}" \
  cargo test --locked -p obb-rtl --test rtl -- --ignored --nocapture mutants::mutants_of_the_default_core \
  2>&1 | tee target/mutants.log
