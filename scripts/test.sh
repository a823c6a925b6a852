#!/usr/bin/env bash
# Runs every test: formatting and lint gates, the Rust test suite, the FMU build and the Python
# (fmpy / libcosimpy) tests of the FMU. Works on a fresh machine with only Rust and Python 3 (plus
# apt-get, or an installed MinGW-w64, for scripts/setup-cross.sh).
set -euo pipefail
cd "$(dirname "$0")/.."

step() { printf '\n== %s\n' "$*"; }

step "cargo fmt --check"
cargo fmt --all -- --check

step "cargo clippy (all targets, warnings are errors, every unsafe block with a SAFETY comment)"
cargo clippy --workspace --all-targets --quiet -- -D warnings -D clippy::undocumented_unsafe_blocks

step "cargo doc (the crate's documentation builds without warnings)"
RUSTDOCFLAGS="-D warnings" cargo doc --workspace --no-deps --quiet
RUSTDOCFLAGS="-D warnings -D missing_docs" cargo doc -p fmi2 --no-deps --quiet
RUSTDOCFLAGS="-D warnings -D missing_docs" cargo doc -p raceway --no-deps --quiet

step "Rust tests"
if cargo nextest --version >/dev/null 2>&1; then
  cargo nextest run --workspace --cargo-profile ci --no-fail-fast
else
  cargo test --workspace --profile ci --no-fail-fast
fi

step "Cross-compilation tools (zig, cargo-zigbuild, MinGW-w64) for the FMUs' linux64 and win64 binaries"
scripts/setup-cross.sh

step "Build the FMUs (linux64 for glibc >= 2.17, win64)"
cargo run --quiet --release -p fmu-build

step "Python environment"
scripts/setup-python.sh

step "Python tests of the FMU"
.venv/bin/python -m pytest tests/python -q -rs
