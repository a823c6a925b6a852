#!/usr/bin/env bash
# Runs the FMUs' win64 binaries under wine: tests/fmi_host/fmi_host.c built for Windows with
# MinGW-w64 (LoadLibrary/GetProcAddress) loads each DLL, instantiates with the file:///Z:/...
# URI of the unzipped FMU's resources, initializes, takes 100 steps of 1e-4 s and prints one
# output, compared with the same run of the linux64 binary on this machine. Then fmi2's toy-model
# tests, panic_becomes_fatal among them (a Rust panic caught at the C boundary), built for
# x86_64-pc-windows-gnu in release and run under wine, and the libm fingerprints of both platforms.
# Results: docs/platforms.md.
#
# Needs wine64 (Debian package wine64; apt-get installs it when missing and this runs as root),
# the FMUs (cargo run --release -p fmu-build) and the tools of scripts/setup-cross.sh.
#
# Debian 12's wine 8.0 has no bcryptprimitives.dll, which Rust's standard library imports
# (ProcessPrng, Windows 10 and later): tests/fmi_host/bcryptprimitives_shim.c stands in for it,
# next to fmi_host.exe, for this run only.
set -euo pipefail
cd "$(dirname "$0")/.."

TARGET="${CARGO_TARGET_DIR:-target}"
FMUS="$TARGET/fmu"
work="$(cd "$TARGET" && pwd)/wine-check"
say() { printf 'wine_check: %s\n' "$*"; }
die() { say "error: $*" >&2; exit 1; }

WINE="$(command -v wine64 || command -v wine || true)"
[ -n "$WINE" ] || { [ -x /usr/lib/wine/wine64 ] && WINE=/usr/lib/wine/wine64; } || true
if [ -z "$WINE" ]; then
    [ "$(id -u)" -eq 0 ] && command -v apt-get >/dev/null 2>&1 || die "wine64 is not installed"
    say "installing wine64 (apt-get)"
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends wine64 >/dev/null
    WINE=/usr/lib/wine/wine64
fi
command -v x86_64-w64-mingw32-gcc >/dev/null 2>&1 || die "MinGW-w64 missing: run scripts/setup-cross.sh"
.venv/bin/python -m ziglang version >/dev/null 2>&1 || die "zig missing: run scripts/setup-cross.sh"
for m in BallBearing JeffcottRotor; do
    [ -f "$FMUS/$m.fmu" ] || die "$FMUS/$m.fmu missing: run cargo run --release -p fmu-build"
done

rm -rf "$work/bin" "$work/fmus"
mkdir -p "$work/bin" "$work/fmus"
x86_64-w64-mingw32-gcc -O2 -static -o "$work/bin/fmi_host.exe" tests/fmi_host/fmi_host.c
x86_64-w64-mingw32-gcc -O2 -shared -o "$work/bin/bcryptprimitives.dll" \
    tests/fmi_host/bcryptprimitives_shim.c -ladvapi32
.venv/bin/python -m ziglang cc -target x86_64-linux-gnu.2.17 -O2 -o "$work/bin/fmi_host" \
    tests/fmi_host/fmi_host.c -ldl
for m in BallBearing JeffcottRotor; do
    mkdir -p "$work/fmus/$m"
    (cd "$work/fmus/$m" && unzip -q "$OLDPWD/$FMUS/$m.fmu")
done
export WINEPREFIX="$work/prefix" WINEDEBUG=-all
export WINEPATH="Z:${work//\//\\}\\bin"

echo
echo "wine: $("$WINE" --version), $WINE"
for m in BallBearing JeffcottRotor; do
    echo "$m.dll imports: $(objdump -p "$work/fmus/$m/binaries/win64/$m.dll" | sed -n 's/.*DLL Name: //p' | tr '\n' ' ')"
done
declare -A VR=([BallBearing]=1001 [JeffcottRotor]=1002)     # pedestal.a.z, journal.z
status=0
for m in BallBearing JeffcottRotor; do
    echo
    echo "\$ FMI_HOST_LOGGING=1 wine fmi_host.exe $m $m ${VR[$m]}"
    if ! out="$(cd "$work/fmus" && FMI_HOST_LOGGING=1 "$WINE" "$work/bin/fmi_host.exe" "$m" "$m" "${VR[$m]}" 2>&1)"; then
        echo "$out" | tail -n 20
        say "FAILED: $m under wine"
        status=1
        continue
    fi
    # The host's own lines and the FMU's line saying where the bearing came from.
    echo "$out" | grep -E "^(loaded|instantiate|[0-9]+ steps|RESULT)|bearing '" | cut -c1-200
    win="$(echo "$out" | tr -d '\r' | awk '/^RESULT/ { print $3 }')"
    lin="$("$work/bin/fmi_host" "$work/fmus/$m" "$m" "${VR[$m]}" 2>/dev/null | awk '/^RESULT/ { print $3 }')"
    python3 - "$m" "$win" "$lin" <<'PY'
import sys
m, a, b = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
same = "identical" if a == b else f"relative difference {abs(a - b) / abs(b):.2e}"
print(f"{m} at t = 0.01 s, win64 under wine vs linux64 here: {same} ({sys.argv[2]} vs {sys.argv[3]})")
PY
done

echo
echo "\$ cargo test --release -p fmi2 --target x86_64-pc-windows-gnu --test toy   (runner: wine)"
CARGO_TARGET_X86_64_PC_WINDOWS_GNU_RUNNER="$WINE" RUST_BACKTRACE=0 \
    cargo test --quiet --release -p fmi2 --target x86_64-pc-windows-gnu --test toy 2>&1 \
    | grep -E "^(running|test result)|panicked" || status=1

x86_64-w64-mingw32-gcc -O1 -fno-builtin -o "$work/bin/libm_probe.exe" tests/fmi_host/libm_probe.c
.venv/bin/python -m ziglang cc -target x86_64-linux-gnu.2.17 -O1 -fno-builtin -o "$work/bin/libm_probe" \
    tests/fmi_host/libm_probe.c -lm
echo
echo "libm fingerprints (tests/fmi_host/libm_probe.c), glibc here vs MinGW-w64 under wine:"
paste <("$work/bin/libm_probe") <("$WINE" "$work/bin/libm_probe.exe" | tr -d '\r') |
    awk '{ printf "  %-6s %s\n", $1, ($2 == $4 ? "same bits" : "different bits") }'
exit $status
