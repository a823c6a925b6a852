#!/usr/bin/env bash
# The main job: build BallBearing.fmu, create the Python environment, and run the default scene
# (Table-1 bearing, 9900 rpm, Fa 4000 N, Fr 1000 N, outer-race spall 1.0 x 0.2 mm) through fmpy.
# Prints the kinematic fault frequencies and the envelope-spectrum peak, saves out/default_scene.png.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup-cross.sh >/dev/null
cargo run --quiet --release -p fmu-build
scripts/setup-python.sh >/dev/null
mkdir -p out
.venv/bin/python examples/default_scene.py --fmu target/fmu/BallBearing.fmu --out out/default_scene.png "$@"
