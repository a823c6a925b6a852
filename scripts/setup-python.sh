#!/usr/bin/env bash
# Creates (or updates) the Python environment used by the FMU tests in tests/python/:
#   .venv/ at the repository root with fmpy, numpy, scipy, matplotlib, pytest and libcosimpy.
# Idempotent: an existing .venv is reused, and pip only installs what is missing.
# Needs only python3 (>= 3.9, with the venv module) and network access to PyPI.
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="${RACEWAY_VENV:-$ROOT/.venv}"
PY="${PYTHON:-python3}"
PACKAGES=(fmpy numpy scipy matplotlib pytest libcosimpy "dask[distributed]")

say() { printf 'setup-python: %s\n' "$*"; }

if ! command -v "$PY" >/dev/null 2>&1; then
    say "error: $PY not found (install Python 3.11 or set PYTHON=...)" >&2
    exit 1
fi

if [ -x "$VENV/bin/python" ]; then
    say "reusing existing virtual environment $VENV ($("$VENV/bin/python" --version 2>&1))"
else
    say "creating virtual environment $VENV with $("$PY" --version 2>&1)"
    if ! "$PY" -m venv "$VENV"; then
        say "error: '$PY -m venv' failed; on Debian/Ubuntu install python3-venv" >&2
        exit 1
    fi
fi

# pip itself first (old pips cannot resolve manylinux_2_28 wheels such as libcosimpy's).
say "upgrading pip"
"$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --upgrade pip

missing=()
for p in "${PACKAGES[@]}"; do
    if "$VENV/bin/python" -m pip show --quiet "$p" >/dev/null 2>&1; then
        say "already installed: $p $("$VENV/bin/python" -m pip show "$p" 2>/dev/null | sed -n 's/^Version: //p')"
    else
        missing+=("$p")
    fi
done

if [ "${#missing[@]}" -gt 0 ]; then
    say "installing: ${missing[*]}"
    "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check "${missing[@]}"
fi

for p in "${PACKAGES[@]}"; do
    say "  $p $("$VENV/bin/python" -m pip show "$p" 2>/dev/null | sed -n 's/^Version: //p')"
done
say "done: activate with 'source $VENV/bin/activate', run the FMU tests with '$VENV/bin/python -m pytest tests/python'"
