#!/usr/bin/env bash
# Cost of one communication step, this checkout against an earlier revision (not part of CI):
#
#   scripts/step_overhead.sh REV [rounds]
#
# Exports REV and HEAD with `git archive` (no worktree) into target/step_overhead/, builds the
# small program scripts/step_overhead/main.rs against each (release), and runs them interleaved
# `rounds` times (default 8), 3 repeats per run: 1 s of the default scene at the kinematic and
# lumped levels in 1e-4 s steps, through the library (Simulation::advance + every output read)
# and through the FMU shell in-process (fmi2DoStep + fmi2GetReal of every Real output). Prints the
# minimum and median wall seconds per 1 s and per step of each build, and the ratio. The host is
# shared: compare the two builds of one run, not numbers from different runs. Committed changes
# only (HEAD), uncommitted edits are not measured.
set -euo pipefail
cd "$(dirname "$0")/.."
rev="${1:?usage: scripts/step_overhead.sh REV [rounds]}"
rounds="${2:-8}"
root="$PWD/target/step_overhead"
mkdir -p "$root"
for v in base new; do
  commit=$([ "$v" = base ] && git rev-parse --verify "$rev^{commit}" || git rev-parse HEAD)
  src="$root/raceway-$v"
  rm -rf "$src" && mkdir -p "$src"
  git archive "$commit" | tar -x -C "$src"
  bench="$root/bench-$v"
  mkdir -p "$bench/src"
  cp scripts/step_overhead/main.rs "$bench/src/main.rs"
  cp "$src/Cargo.lock" "$bench/Cargo.lock"
  # The workspace split (issue 18) moved the FMI shell into the fmi2 and ballbearing-fmu crates.
  if [ -d "$src/fmu" ]; then
    deps="raceway = { path = \"$src\" }
fmi2 = { path = \"$src/fmi2\" }
ballbearing-fmu = { path = \"$src/fmu\" }"
    features='[features]
default = ["split"]
split = []'
  else
    deps="raceway = { path = \"$src\" }"
    features='[features]
split = []'
  fi
  cat >"$bench/Cargo.toml" <<TOML
[package]
name = "step_overhead"
version = "0.1.0"
edition = "2021"

[dependencies]
$deps

$features

[profile.release]
panic = "unwind"
debug = 1

# Not a member of the checkout's workspace (it lives under its target/).
[workspace]
TOML
  echo "building $v ($commit) ..."
  (cd "$bench" && cargo build --release --quiet)
done
out="$root/results.txt"
: >"$out"
for _ in $(seq "$rounds"); do
  for level in kinematic lumped; do
    for v in base new; do
      "$root/bench-$v/target/release/step_overhead" "$level" 3 | sed "s/^/$v /" >>"$out"
    done
  done
done
python3 - "$out" <<'PY'
import collections, statistics, sys
d = collections.defaultdict(list)
for line in open(sys.argv[1]):
    v, mode, level, w = line.split()
    d[(mode, level, v)].append(float(w))
print(f"{'path':8} {'level':10} {'build':5} {'n':>3} {'min s':>9} {'median s':>9} {'µs/step':>8}")
for mode in ["library", "fmu"]:
    for level in ["kinematic", "lumped"]:
        for v in ["base", "new"]:
            x = d[(mode, level, v)]
            med = statistics.median(x)
            print(f"{mode:8} {level:10} {v:5} {len(x):3d} {min(x):9.5f} {med:9.5f} {med / 1e4 * 1e6:8.3f}")
        b, n = d[(mode, level, "base")], d[(mode, level, "new")]
        print(f"{'':8} {level:10} new/base: median {statistics.median(n) / statistics.median(b):.3f}, "
              f"min {min(n) / min(b):.3f}")
PY
