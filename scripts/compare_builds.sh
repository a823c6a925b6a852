#!/usr/bin/env bash
# Side-by-side check of a change against an earlier revision (not part of CI): are the outputs
# the same, and how much faster or slower is it?
#
#   scripts/compare_builds.sh REV [runs]
#
# Builds REV (a commit, tag or branch) in a git worktree under target/compare/ and this checkout
# (release, `raceway` only), then
#  1. writes the CSV of every dynamic level (kinematic, lumped, reduced, full) on the outer- and
#     inner-spall scenes of paper Sec. 3.5 (examples/scenes/sec3.5-*.toml; 0.1 s for the cheap
#     levels, 0.03 s for the per-ball ones) with both builds and compares them byte for byte;
#     each build reads the scene files of its own revision (a newer scene may name keys an
#     older build does not know, e.g. `[full] cage = false`, which keeps the paper's cage-less
#     bearing);
#  2. times `raceway simulate` of the Sec. 3.5 outer scene (the default scene's bearing, loads
#     and spall, without a cage; DOP853, rtol 1e-6, only pedestal.a.z
#     written) at each level, the two builds interleaved `runs` times (default 5), and prints
#     the minimum and median wall seconds per simulated second of each (the figure `simulate`
#     prints, CSV writing included) and the ratio of the medians. The host is
#     shared: compare the two columns of one run, not numbers from different runs.
#
# An output that differs is named with the relative RMS difference of its pedestal.a.z column.
# Exit status 1 when an output differs (the timings are printed either way).
#
# Environment: LEVELS="full reduced" times those levels only; CONCURRENT=1 runs the two builds'
# timed runs at the same time, one per core (on a 2-core shared host the slow spells then hit
# both builds alike; the runs compete only for memory bandwidth). EDGE=abrupt or EDGE=blend
# times both builds with the same spall edge (each build's own bearing preset with its
# `blend_length` set to 0 or "b"): the default changed from the blend to the abrupt edge
# (decision D2, 3cdaf7a), so without EDGE a build from before that times another edge.

set -euo pipefail
cd "$(dirname "$0")/.."
rev="${1:?usage: scripts/compare_builds.sh REV [runs]}"
runs="${2:-5}"
. scripts/compare_worktree.sh
compare_worktree "$rev"
echo "building $short and this checkout (release) ..."
(cd "$tree" && CARGO_TARGET_DIR="$root/target/compare/target" cargo build --release --quiet --bin raceway)
cargo build --release --quiet --bin raceway
old="$root/target/compare/target/release/raceway"
new="$root/target/release/raceway"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# How far apart two CSVs' pedestal.a.z columns are: the RMS of the difference over the RMS of
# the old column, on the rows both have (the row count too, when it differs).
rms_diff() {
  paste -d, "$1" "$2" | awk -F, '
    NR == 1 { h = NF / 2; for (i = 1; i <= h; i++) if ($i == "pedestal.a.z") c = i; next }
    NF == 2 * h { d = $c - $(c + h); s += d * d; r += $c * $c; n++ }
    END { printf "pedestal.a.z relative RMS difference %.2e over %d rows", sqrt(s / r), n }'
  local a b
  a=$(wc -l <"$1")
  b=$(wc -l <"$2")
  [ "$a" = "$b" ] || printf '; %s against %s lines' "$a" "$b"
}

echo
echo "== outputs of $short and this checkout"
status=0
for scene in sec3.5-outer sec3.5-inner; do
  for level in kinematic lumped reduced full; do
    case "$level" in reduced | full) d=0.03 ;; *) d=0.1 ;; esac
    args=(--fidelity "$level" --duration "$d" --quiet)
    "$old" simulate "$tree/examples/scenes/$scene.toml" "${args[@]}" --out "$work/old.csv"
    "$new" simulate "examples/scenes/$scene.toml" "${args[@]}" --out "$work/new.csv"
    if cmp -s "$work/old.csv" "$work/new.csv"; then
      echo "$scene $level ($d s): byte-equal ($(wc -l <"$work/new.csv") lines)"
    else
      echo "$scene $level ($d s): DIFFERENT ($(rms_diff "$work/old.csv" "$work/new.csv"))"
      status=1
    fi
  done
done

# The timed scene of each build: its own Sec. 3.5 outer scene, or with EDGE a copy of it whose
# bearing is its own preset with the edge set.
timed_scene() {
  local src="$1/examples/scenes/sec3.5-outer.toml"
  case "${EDGE:-}" in
    "") echo "$src"; return ;;
    abrupt) blend="0.0" ;;
    blend) blend='"b"' ;;
    *) echo "EDGE must be abrupt or blend, not $EDGE" >&2; exit 2 ;;
  esac
  mkdir -p "$work/$2"
  sed "s/^blend_length = .*/blend_length = $blend/" "$1/presets/niu2014-table1.toml" >"$work/$2/bearing.toml"
  grep -q "^blend_length = $blend\$" "$work/$2/bearing.toml" || { echo "no blend_length in $1's preset" >&2; exit 2; }
  sed 's|^bearing = .*|bearing = "bearing.toml"|' "$src" >"$work/$2/scene.toml"
  echo "$work/$2/scene.toml"
}
old_scene="$(timed_scene "$tree" old)"
new_scene="$(timed_scene "$root" new)"

echo
echo "== wall seconds per simulated second of raceway simulate, Sec. 3.5 outer scene${EDGE:+ with the $EDGE edge on both}, $runs $([ "${CONCURRENT:-0}" = 1 ] && echo "concurrent" || echo "interleaved") runs each"
wall() { "$1" simulate "$4" --fidelity "$2" --duration "$3" \
  --columns pedestal.a.z --out "$work/t-$5.csv" 2>&1 | sed -n 's/.* s wall (\([0-9.e+-]*\) s per simulated s).*/\1/p'; }
stats() { sort -g | awk '{a[NR] = $1} END {printf "%.4g %.4g\n", a[1], a[int((NR + 1) / 2)]}'; }
printf '%-10s %10s %14s %14s %14s %14s %18s\n' level simulated_s "$short min" "$short median" \
  "new min" "new median" "new/old (median)"
for level in ${LEVELS:-kinematic lumped reduced full}; do
  case "$level" in reduced | full) d=0.04 ;; *) d=1 ;; esac
  : >"$work/old.t"
  : >"$work/new.t"
  for _ in $(seq "$runs"); do
    if [ "${CONCURRENT:-0}" = 1 ]; then
      wall "$old" "$level" "$d" "$old_scene" old >>"$work/old.t" &
      wall "$new" "$level" "$d" "$new_scene" new >>"$work/new.t"
      wait
    else
      wall "$old" "$level" "$d" "$old_scene" old >>"$work/old.t"
      wall "$new" "$level" "$d" "$new_scene" new >>"$work/new.t"
    fi
  done
  read -r omin omed < <(stats <"$work/old.t")
  read -r nmin nmed < <(stats <"$work/new.t")
  printf '%-10s %10s %14s %14s %14s %14s %18s\n' "$level" "$d" "$omin" "$omed" "$nmin" "$nmed" \
    "$(awk -v a="$nmed" -v b="$omed" 'BEGIN {printf "%.3f", a / b}')"
done
exit "$status"
