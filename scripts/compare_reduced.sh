#!/usr/bin/env bash
# Level-against-level comparison on the S2 scene (paper Sec. 3.5: outer spall 1.0 x 0.2 mm,
# Fa 4000 N, Fr 1000 N, 9900 rpm; examples/scenes/sec3.5-outer.toml), not part of CI:
# L3 reduced against L4 full (inner-ring tilt held, as L3 has none, and free) and L2 lumped.
# Envelope peaks at BPFO x 1..5 (band 1-20 kHz, Hann, after the 20 ms transient), BPFO from
# impact spacing, cage speed, friction torque, impact forces, cost. Writes docs/research/levels-reduced.md.
# Also tabulates docs/research/bench-reduced/bench.csv, written by (about 3 minutes):
#   raceway bench --quick --scenes S2 --levels reduced --out docs/research/bench-reduced
# Usage: scripts/compare_reduced.sh [simulated seconds, default 0.14]
set -euo pipefail
cd "$(dirname "$0")/.."
duration="${1:-0.14}"
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-target}"
cargo build --release --bin raceway
bin="$CARGO_TARGET_DIR/release/raceway"
py="${PYTHON:-.venv/bin/python}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
scene=examples/scenes/sec3.5-outer.toml
fs=204800  # 4 x 51.2 kHz: impact times to 5 us; the same spectral resolution
sim() { "$bin" simulate "$@" --duration "$duration" --sample-rate "$fs" --quiet; }
sim "$scene" --fidelity reduced --out "$work/reduced.csv"
sim examples/scenes/sec3.5-outer-full.toml --out "$work/full_lock_tilt.csv"
sim "$scene" --fidelity full --out "$work/full.csv"
sim "$scene" --fidelity lumped --out "$work/lumped.csv"
"$py" studies/compare_levels.py "$bin" docs/research/levels-reduced.md \
  "full_lock_tilt=$work/full_lock_tilt.csv" "full=$work/full.csv" \
  "reduced=$work/reduced.csv" "lumped=$work/lumped.csv" \
  "bench=docs/research/bench-reduced/bench.csv"
