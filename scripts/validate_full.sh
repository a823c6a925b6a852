#!/usr/bin/env bash
# Long validation runs of the L4 full model (not part of CI): paper Sec. 3.5 with the outer- and
# the inner-race spall, the inner-ring tilt held (D1) and free. Writes the measured tables to
# docs/research/validation-full-*.md; docs/validation.md quotes them.
# Usage: scripts/validate_full.sh [simulated seconds, default 0.14]
set -euo pipefail
cd "$(dirname "$0")/.."
duration="${1:-0.14}"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-target}"
cargo build --release -p raceway-studies --bin validate_full
mkdir -p docs/research
bin="$CARGO_TARGET_DIR/release/validate_full"
"$bin" "$duration" docs/research/validation-full-sec3.5.md 20 outer
"$bin" "$duration" docs/research/validation-full-sec3.5-inner.md 20 inner
# The same with the inner ring free to tilt (shaft tilt inertia and stiffness, docs/model.md#d1).
"$bin" "$duration" docs/research/validation-full-sec3.5-free-tilt.md 20 outer free_tilt
"$bin" "$duration" docs/research/validation-full-sec3.5-inner-free-tilt.md 20 inner free_tilt
# Table-2 impact test (docs/model.md#c14), tilt held and free: fel, feh per Fa.
rm -f docs/research/validation-full-table2.md
for fa in 3000 4000 5000; do
  for tilt in held free_tilt; do
    "$bin" 0.1 docs/research/validation-full-table2.md 20 "impact$fa" "$tilt"
  done
done
