#!/usr/bin/env bash
# The bare cost of one right-hand-side evaluation, this checkout against an earlier revision
# (not part of CI): studies/rhs_cost.rs built at both (copied into REV's worktree when REV
# predates it), each level's RHS timed at the scene's quasi-static start.
#
#   scripts/compare_rhs.sh REV [rounds] [scene.toml]
#
# The two builds run at the same time, one per core, `rounds` times (default 5), so that the
# shared host's slow spells hit both; each run prints the fastest of 100 batches of about 5 ms.
# Prints per level the minimum and median over the rounds of each build and the ratio of the
# medians (new/old). Scene: default examples/scenes/sec3.5-outer.toml (the cage-less spall
# scene that scripts/compare_builds.sh times).
set -euo pipefail
cd "$(dirname "$0")/.."
rev="${1:?usage: scripts/compare_rhs.sh REV [rounds] [scene.toml]}"
rounds="${2:-5}"
scene="${3:-examples/scenes/sec3.5-outer.toml}"
. scripts/compare_worktree.sh
compare_worktree "$rev"
if [ ! -d "$tree/studies" ]; then
  echo "compare_rhs: $short has no studies/ crate to build rhs_cost in" >&2
  exit 1
fi
cp studies/rhs_cost.rs "$tree/studies/rhs_cost.rs"
if ! grep -q '"rhs_cost"' "$tree/studies/Cargo.toml"; then
  printf '\n[[bin]]\nname = "rhs_cost"\npath = "rhs_cost.rs"\ntest = false\n' >>"$tree/studies/Cargo.toml"
fi
echo "building rhs_cost at $short and in this checkout (release) ..."
(cd "$tree" && CARGO_TARGET_DIR="$root/target/compare/target" cargo build --release --quiet -p raceway-studies --bin rhs_cost)
cargo build --release --quiet -p raceway-studies --bin rhs_cost
old="$root/target/compare/target/release/rhs_cost"
new="$root/target/release/rhs_cost"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
for _ in $(seq "$rounds"); do
  "$old" "$scene" >>"$work/old" &
  "$new" "$scene" >>"$work/new"
  wait
done
stats() { awk -v l="$1" '$1 == l {print $4}' "$2" | sort -g |
  awk '{a[NR] = $1} END {printf "%.4f %.4f\n", a[1], a[int((NR + 1) / 2)]}'; }
echo
echo "== µs per RHS evaluation at the quasi-static start of $scene, $rounds rounds"
printf '%-10s %14s %14s %14s %14s %18s\n' level "$short min" "$short median" "new min" \
  "new median" "new/old (median)"
for level in $(awk '{print $1}' "$work/new" | awk '!seen[$0]++'); do
  read -r omin omed < <(stats "$level" "$work/old")
  read -r nmin nmed < <(stats "$level" "$work/new")
  printf '%-10s %14s %14s %14s %14s %18s\n' "$level" "$omin" "$omed" "$nmin" "$nmed" \
    "$(awk -v a="$nmed" -v b="$omed" 'BEGIN {printf "%.3f", a / b}')"
done
