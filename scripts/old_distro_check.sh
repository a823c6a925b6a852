#!/usr/bin/env bash
# Runs the FMUs' linux64 binaries inside an older distribution's root file system: a Debian
# minbase root made with debootstrap (default bullseye, glibc 2.31), entered with chroot. The host
# is tests/fmi_host/fmi_host.c, compiled for glibc 2.17 with zig cc (so it runs there too): it
# loads the .so, instantiates with the resources/ URI, initializes, takes 100 steps of 1e-4 s and
# prints one output. The BallBearing's value is compared with the FMU's own reference results
# (documentation/BallBearing_ref.csv at t = 0.01 s) and each value with the same run on this machine.
# Results: docs/platforms.md.
#
#   scripts/old_distro_check.sh [suite]      # suite: a Debian release on deb.debian.org (bullseye)
#
# Needs root (debootstrap, chroot), debootstrap (apt-get installs it when missing), the FMUs
# (cargo run --release -p fmu-build) and zig (scripts/setup-cross.sh). The root is kept in
# target/old-distro/debian-<suite> (about 220 MB) and reused.
set -euo pipefail
cd "$(dirname "$0")/.."

SUITE="${1:-bullseye}"
MIRROR="${DEBIAN_MIRROR:-http://deb.debian.org/debian}"
TARGET="${CARGO_TARGET_DIR:-target}"
ROOTFS="$TARGET/old-distro/debian-$SUITE"
FMUS="$TARGET/fmu"
say() { printf 'old_distro_check: %s\n' "$*"; }
die() { say "error: $*" >&2; exit 1; }

[ "$(id -u)" -eq 0 ] || die "needs root (debootstrap and chroot)"
for m in BallBearing JeffcottRotor; do
    [ -f "$FMUS/$m.fmu" ] || die "$FMUS/$m.fmu missing: run cargo run --release -p fmu-build"
done
.venv/bin/python -m ziglang version >/dev/null 2>&1 || die "zig missing: run scripts/setup-cross.sh"

if [ ! -x "$ROOTFS/bin/sh" ]; then
    if ! command -v debootstrap >/dev/null 2>&1; then
        say "installing debootstrap (apt-get)"
        DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends debootstrap >/dev/null
    fi
    say "debootstrap --variant=minbase $SUITE $ROOTFS $MIRROR"
    rm -rf "$ROOTFS"
    mkdir -p "$(dirname "$ROOTFS")"
    debootstrap --variant=minbase "$SUITE" "$ROOTFS" "$MIRROR" >"$ROOTFS.log" 2>&1 \
        || { tail -n 20 "$ROOTFS.log" >&2; die "debootstrap failed (log: $ROOTFS.log)"; }
fi

work="$ROOTFS/fmu-check"
rm -rf "$work"
mkdir -p "$work"
say "compiling tests/fmi_host/fmi_host.c for glibc 2.17 (zig cc)"
.venv/bin/python -m ziglang cc -target x86_64-linux-gnu.2.17 -O2 -o "$work/fmi_host" \
    tests/fmi_host/fmi_host.c -ldl
for m in BallBearing JeffcottRotor; do
    mkdir -p "$work/$m"
    (cd "$work/$m" && unzip -q "$OLDPWD/$FMUS/$m.fmu")
done

echo
echo "Host: $(. /etc/os-release && echo "$PRETTY_NAME"), $(ldd --version | head -n1)"
echo "Root: Debian $(cat "$ROOTFS/etc/debian_version") ($SUITE), $(chroot "$ROOTFS" /usr/bin/ldd --version | head -n1)"
for m in BallBearing JeffcottRotor; do
    so="$work/$m/binaries/linux64/$m.so"
    echo "$m.so: newest glibc symbol version needed: $(objdump -T "$so" | grep -o 'GLIBC_[0-9.]*' | sort -uV | tail -n1)"
done
status=0
declare -A VR=([BallBearing]=1001 [JeffcottRotor]=1002)     # pedestal.a.z, journal.z
declare -A HERE INSIDE
for m in BallBearing JeffcottRotor; do
    echo
    echo "\$ chroot $ROOTFS /fmu-check/fmi_host /fmu-check/$m $m ${VR[$m]}"
    if ! out="$(chroot "$ROOTFS" /fmu-check/fmi_host "/fmu-check/$m" "$m" "${VR[$m]}" 2>&1)"; then
        echo "$out"
        say "FAILED: $m inside $SUITE"
        status=1
        continue
    fi
    echo "$out"
    INSIDE[$m]="$(echo "$out" | awk '/^RESULT/ { print $3 }')"
    HERE[$m]="$("$work/fmi_host" "$work/$m" "$m" "${VR[$m]}" 2>/dev/null | awk '/^RESULT/ { print $3 }')"
done
[ "$status" -eq 0 ] || exit "$status"

# The values against this machine's run of the same binaries and against the reference results
# fmu-build computed (on the build machine, through the same .so).
ref="$work/BallBearing/documentation/BallBearing_ref.csv"
want="$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "\"pedestal.a.z\"") c = i }
                 $1 == "0.01" { print $c; exit }' "$ref")"
echo
compare() { # label, value inside, value elsewhere
    python3 - "$@" <<'PY'
import sys
label, a, b = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
same = "identical" if a == b else f"relative difference {abs(a - b) / abs(b):.2e}"
print(f"{label}: {same} ({sys.argv[2]} vs {sys.argv[3]})")
PY
}
compare "BallBearing pedestal.a.z at t = 0.01 s, $SUITE vs this machine" "${INSIDE[BallBearing]}" "${HERE[BallBearing]}"
compare "BallBearing pedestal.a.z at t = 0.01 s, $SUITE vs the FMU reference results" "${INSIDE[BallBearing]}" "$want"
compare "JeffcottRotor journal.z at t = 0.01 s, $SUITE vs this machine" "${INSIDE[JeffcottRotor]}" "${HERE[JeffcottRotor]}"

# Which libm functions round differently there (the FMU libraries import glibc's libm).
.venv/bin/python -m ziglang cc -target x86_64-linux-gnu.2.17 -O1 -fno-builtin -o "$work/libm_probe" \
    tests/fmi_host/libm_probe.c -lm
echo
echo "libm fingerprints (tests/fmi_host/libm_probe.c), this machine vs $SUITE:"
paste <("$work/libm_probe") <(chroot "$ROOTFS" /fmu-check/libm_probe) |
    awk '{ printf "  %-6s %s\n", $1, ($2 == $4 ? "same bits" : "different bits") }'
rm -rf "$work"
