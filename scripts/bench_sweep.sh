#!/usr/bin/env bash
# Throughput benchmark of `raceway sweep` (not a test): the 40-run lumped study
# examples/sweeps/bench40.toml with --jobs 1 and --jobs 2, wall times, speed-up, and a check that
# both result tables are identical run for run (results.sorted.csv without the wall_s column).
# Usage: scripts/bench_sweep.sh [SWEEP_FILE]   (env: CARGO_TARGET_DIR, REPS=1)
set -euo pipefail
cd "$(dirname "$0")/.."
SWEEP="${1:-examples/sweeps/bench40.toml}"
REPS="${REPS:-1}"
TARGET="${CARGO_TARGET_DIR:-target}"
cargo build --quiet --release --bin raceway
BIN="$TARGET/release/raceway"
OUT="$(mktemp -d "${TMPDIR:-/tmp}/bench_sweep.XXXXXX")"
trap 'rm -rf "$OUT"' EXIT

best() { printf '%s\n' "$@" | sort -g | head -1; }
declare -a T1 T2
for r in $(seq 1 "$REPS"); do
  for jobs in 1 2; do
    rm -rf "$OUT/j$jobs"
    TIMEFORMAT='%R %U %S'
    { time "$BIN" sweep "$SWEEP" --out "$OUT/j$jobs" --jobs "$jobs" --quiet ; } 2> "$OUT/time"
    read -r dt user sys < "$OUT/time"
    if [ "$jobs" = 1 ]; then T1+=("$dt"); else T2+=("$dt"); fi
    # CPU use = (user + sys) / wall: 2.0 means both cores were ours for the whole sweep.
    printf 'rep %d --jobs %d: %.2f s wall, %.2f s CPU, CPU use %.2f cores\n' "$r" "$jobs" "$dt" \
      "$(echo "$user + $sys" | bc -l)" "$(echo "($user + $sys) / $dt" | bc -l)"
  done
done
strip() { cut -d, -f1-4,6- "$1"; }   # drop wall_s (column 5)
runs=$(($(wc -l < "$OUT/j1/results.sorted.csv") - 1))
if diff <(strip "$OUT/j1/results.sorted.csv") <(strip "$OUT/j2/results.sorted.csv") >/dev/null; then
  same="identical"
else
  same="DIFFERENT"
fi
b1=$(best "${T1[@]}"); b2=$(best "${T2[@]}")
printf 'runs: %d, failed: %d\n' "$runs" "$(grep -c ',failed,' "$OUT/j1/results.csv" || true)"
printf 'best of %d: --jobs 1 %.2f s, --jobs 2 %.2f s, speed-up %.2fx; rows %s\n' \
  "$REPS" "$b1" "$b2" "$(echo "$b1 / $b2" | bc -l)" "$same"
printf 'conditions: %s, %s cores, load average %s\n' "$(uname -m)" "$(nproc)" "$(cut -d' ' -f1-3 /proc/loadavg)"
# CPU pressure: the share of time runnable tasks waited for a core (others' work included).
[ -r /proc/pressure/cpu ] && printf 'cpu pressure: %s\n' "$(head -1 /proc/pressure/cpu)"
[ "$same" = identical ]
