#!/usr/bin/env bash
# The fidelity ladder's costs, measured in one run (not part of CI): wall seconds per simulated
# second of `raceway simulate` at each dynamic level on one scene, the levels interleaved `runs`
# times (default 5) so that the host's drift hits them alike, and each level's median as a
# ratio to the next level up (issue 24: a rung should cost at most a fifth of the one above).
# A deprecated level (the reduced one; `raceway levels` says which) is measured too but is no
# rung: the lumped level's next level up is the full one, and the reduced level is shown against
# the full level.
#
#   scripts/ladder.sh [runs] [scene]      (default scene: examples/scenes/default.toml)
#
# Only pedestal.a.z is written (`--columns`), at the scene's sample rate; the simulated time is
# 2 s (kinematic), 1 s (lumped) and 0.1 s (reduced, full), the figure `simulate` prints (the
# advance alone, CSV writing included, the model's build not). Writes the table to stdout and
# to docs/research/ladder.md.
set -euo pipefail
cd "$(dirname "$0")/.."
runs="${1:-5}"
scene="${2:-examples/scenes/default.toml}"
cargo build --release --quiet --bin raceway
bin=target/release/raceway
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
levels=(kinematic lumped reduced full)
duration() { case "$1" in kinematic) echo 2 ;; lumped) echo 1 ;; *) echo 0.1 ;; esac; }
# The deprecated levels, from the library's registry (`raceway levels --json`): measured, but
# no rung.
deprecated=" $("$bin" levels --json | python3 -c 'import json, sys
print(" ".join(l["name"] for l in json.load(sys.stdin) if l["deprecated"]))') "
is_deprecated() { [[ "$deprecated" == *" $1 "* ]]; }
# The next rung up: the next level of the list above this one that is not deprecated.
up_of() {
  local seen=""
  for l in "${levels[@]}"; do
    if [ -n "$seen" ] && ! is_deprecated "$l"; then
      echo "$l"
      return
    fi
    [ "$l" = "$1" ] && seen=1
  done
  echo
}
label() { if is_deprecated "$1"; then echo "$1 (deprecated, no rung)"; else echo "$1"; fi; }
for _ in $(seq "$runs"); do
  for level in "${levels[@]}"; do
    "$bin" simulate "$scene" --fidelity "$level" --duration "$(duration "$level")" \
      --columns pedestal.a.z --out "$work/t.csv" 2>&1 |
      sed -n 's/.* s wall (\([0-9.e+-]*\) s per simulated s).*/\1/p' >>"$work/$level.t"
  done
done
median() { sort -g "$1" | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
minimum() { sort -g "$1" | head -1; }
rev="$(git rev-parse --short=12 HEAD)$(git diff --quiet HEAD -- src solver cli || echo '+changes')"
{
  echo "# The fidelity ladder's costs"
  echo
  echo "*Made by \`scripts/ladder.sh $runs $scene\` at revision $rev, $(date -u +%Y-%m-%d); do"
  echo "not edit by hand.* Wall seconds per simulated second of \`raceway simulate\` (only"
  echo "\`pedestal.a.z\` written), the levels interleaved $runs times in one run; the ratio is each"
  echo "level's median against the next rung up's (the deprecated reduced level is no rung: the"
  echo "lumped level's next rung is the full level). The host is shared: compare the columns of one"
  echo "run, not numbers from different runs."
  echo
  echo "| level | simulated [s] | min [s/s] | median [s/s] | median against the next rung up |"
  echo "|---|---|---|---|---|"
  for level in "${levels[@]}"; do
    med="$(median "$work/$level.t")"
    next="$(up_of "$level")"
    if [ -n "$next" ]; then
      up="$(median "$work/$next.t")"
      ratio="$(awk -v a="$med" -v b="$up" 'BEGIN {printf "%.3g (%s)", a / b, "'"$next"'"}')"
    else
      ratio="—"
    fi
    echo "| $(label "$level") | $(duration "$level") | $(minimum "$work/$level.t") | $med | $ratio |"
  done
} | tee docs/research/ladder.md
