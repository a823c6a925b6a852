#!/usr/bin/env bash
# Long validation runs of the L4 full model (not part of CI). Writes the measured table of
# paper Sec. 3.5 (outer-race spall) to docs/validation-full-sec3.5.md; docs/validation.md quotes it.
# Usage: scripts/validate_full.sh [simulated seconds, default 0.14]
set -euo pipefail
cd "$(dirname "$0")/.."
duration="${1:-0.14}"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-target}"
cargo build --release --example validate_full
mkdir -p docs
"$CARGO_TARGET_DIR/release/examples/validate_full" "$duration" docs/validation-full-sec3.5.md
