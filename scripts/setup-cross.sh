#!/usr/bin/env bash
# Installs the cross-compilation tools `cargo run --release -p fmu-build` needs to build the FMUs'
# binaries for the platforms they ship (docs/platforms.md):
#   binaries/linux64 (glibc >= 2.17): cargo-zigbuild and zig (PyPI packages cargo-zigbuild and
#                                      ziglang, in the project's .venv, where fmu-build looks for them)
#   binaries/win64:                    the Rust target x86_64-pc-windows-gnu (rustup) and MinGW-w64
#                                      (Debian/Ubuntu package gcc-mingw-w64-x86-64, via apt-get)
# Idempotent: installs only what is missing. The apt-get step needs root (or sudo).
set -euo pipefail

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
VENV="$ROOT/.venv"
PY="${PYTHON:-python3}"
# Versions known to work together (zig's command line changes between releases).
ZIGBUILD_VERSION="0.24.1"
ZIGLANG_VERSION="0.17.1"
WIN_TARGET="x86_64-pc-windows-gnu"

say() { printf 'setup-cross: %s\n' "$*"; }
die() { say "error: $*" >&2; exit 1; }

# zig and cargo-zigbuild, as the PyPI packages ziglang and cargo-zigbuild (a prebuilt binary:
# seconds, where `cargo install cargo-zigbuild` compiles for minutes) in .venv, the environment
# scripts/setup-python.sh fills too; fmu-build looks for them there.
if [ ! -x "$VENV/bin/python" ]; then
    command -v "$PY" >/dev/null 2>&1 || die "$PY not found (install Python 3 or set PYTHON=...)"
    say "creating virtual environment $VENV"
    "$PY" -m venv "$VENV" || die "'$PY -m venv' failed; on Debian/Ubuntu install python3-venv"
fi
if zig_version="$("$VENV/bin/python" -m ziglang version 2>/dev/null)"; then
    say "already installed: zig $zig_version (ziglang in $VENV)"
else
    say "installing zig (ziglang==$ZIGLANG_VERSION) into $VENV"
    "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check "ziglang==$ZIGLANG_VERSION"
fi
if zigbuild_version="$("$VENV/bin/cargo-zigbuild" --version 2>/dev/null)"; then
    say "already installed: $zigbuild_version (in $VENV)"
else
    say "installing cargo-zigbuild==$ZIGBUILD_VERSION into $VENV"
    "$VENV/bin/python" -m pip install --quiet --disable-pip-version-check --no-deps \
        "cargo-zigbuild==$ZIGBUILD_VERSION"
fi

# The Rust standard library for win64
if rustup target list --installed 2>/dev/null | grep -qx "$WIN_TARGET"; then
    say "already installed: Rust target $WIN_TARGET"
else
    command -v rustup >/dev/null 2>&1 || die "rustup not found: install the Rust target $WIN_TARGET by other means"
    say "installing Rust target $WIN_TARGET"
    rustup target add "$WIN_TARGET"
fi

# MinGW-w64: the win64 linker, its strip and objdump
if command -v x86_64-w64-mingw32-gcc >/dev/null 2>&1 && command -v x86_64-w64-mingw32-strip >/dev/null 2>&1; then
    say "already installed: $(x86_64-w64-mingw32-gcc --version | head -n1)"
else
    command -v apt-get >/dev/null 2>&1 \
        || die "x86_64-w64-mingw32-gcc not found and no apt-get: install MinGW-w64 (x86_64) with your package manager"
    SUDO=""
    if [ "$(id -u)" -ne 0 ]; then
        command -v sudo >/dev/null 2>&1 || die "installing gcc-mingw-w64-x86-64 needs root (or sudo)"
        SUDO="sudo"
    fi
    say "installing gcc-mingw-w64-x86-64 (apt-get)"
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends \
        gcc-mingw-w64-x86-64 binutils-mingw-w64-x86-64 >/dev/null
fi
say "done"
