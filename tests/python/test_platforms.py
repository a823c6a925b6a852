"""The FMUs' binaries for the platforms they ship (docs/platforms.md), checked with binutils'
objdump on the files inside the built FMUs:

- binaries/linux64/*.so needs no glibc symbol version newer than 2.17 (`objdump -T`), so it
  loads on RHEL 7, Debian 9, Ubuntu 18.04 and later, not only on the build machine's glibc;
- binaries/win64/*.dll is there and exports the same fmi2* functions as the linux64 library, all
  of FMI 2.0 (`objdump -p`, export table);
- the DLL imports only Windows system DLLs, no MinGW runtime (libgcc_s_seh-1.dll,
  libwinpthread-1.dll, libstdc++-6.dll) that an importer's machine would not have.

A test whose tool is missing is skipped, with the reason (pytest -rs lists it).
"""

import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import pytest

from conftest import REPO, fmu_path

MODELS = ["BallBearing", "JeffcottRotor"]
MAX_GLIBC = (2, 17)

# The DLLs a win64 FMU may import: Windows' own (what Rust's std links on x86_64-pc-windows-gnu).
SYSTEM_DLLS = {
    "kernel32.dll",
    "ntdll.dll",
    "bcrypt.dll",
    "bcryptprimitives.dll",
    "advapi32.dll",
    "userenv.dll",
    "ws2_32.dll",
    "msvcrt.dll",
    "ucrtbase.dll",
    "synchronization.dll",
}
MINGW_RUNTIME = {"libgcc_s_seh-1.dll", "libwinpthread-1.dll", "libstdc++-6.dll"}


def fmi2_functions():
    """The FMI 2.0 function names the shell exports (fmi2/src/exports.rs)."""
    text = (REPO / "fmi2" / "src" / "exports.rs").read_text()
    block = re.search(r"EXPORTED_FUNCTIONS: \[&str; (\d+)\] = \[(.*?)\];", text, re.S)
    names = set(re.findall(r'"(fmi2\w+)"', block.group(2)))
    assert len(names) == int(block.group(1))
    return names


def system_dll(name):
    n = name.lower()
    return n in SYSTEM_DLLS or (n.startswith("api-ms-win-") and n.endswith(".dll"))


def objdump(*args):
    return subprocess.run(["objdump", *args], capture_output=True, text=True, check=True).stdout


def pe_objdump(*args):
    """objdump for PE images: MinGW-w64's, else binutils' own if it reads pei-x86-64."""
    tool = shutil.which("x86_64-w64-mingw32-objdump") or shutil.which("objdump")
    if tool is None:
        pytest.skip("no objdump (binutils) to read the DLL")
    proc = subprocess.run([tool, *args], capture_output=True, text=True)
    if proc.returncode != 0:
        pytest.skip(f"{tool} cannot read a PE image: {proc.stderr.strip()}")
    return proc.stdout


@pytest.fixture(scope="module", params=MODELS)
def binaries(request, tmp_path_factory):
    """(model, linux64 library, win64 library or None), unpacked from the FMU."""
    model = request.param
    fmu = fmu_path().with_name(f"{model}.fmu") if model != "BallBearing" else fmu_path()
    if not fmu.is_file():
        pytest.fail(f"{fmu} does not exist: build it with `cargo run --release -p fmu-build`")
    d = tmp_path_factory.mktemp(f"{model}-binaries")
    with zipfile.ZipFile(fmu) as z:
        names = set(z.namelist())
        so = f"binaries/linux64/{model}.so"
        dll = f"binaries/win64/{model}.dll"
        assert so in names, f"{fmu.name} has no {so}"
        z.extract(so, d)
        if dll in names:
            z.extract(dll, d)
    win = d / dll
    return model, d / so, (win if win.is_file() else None)


@pytest.fixture(scope="module")
def need_objdump():
    if shutil.which("objdump") is None:
        pytest.skip("objdump (binutils) is not installed")


def test_win64_binary_present(binaries):
    model, _, dll = binaries
    assert dll is not None, (
        f"{model}.fmu has no binaries/win64/{model}.dll (built with --host-only?)"
    )


def test_linux64_needs_glibc_2_17_at_most(binaries, need_objdump):
    model, so, _ = binaries
    out = objdump("-T", str(so))
    assert "GLIBC_PRIVATE" not in out, f"{so.name} uses glibc's private symbols"
    needs = {}
    for line in out.splitlines():
        m = re.search(r"GLIBC_(\d+(?:\.\d+)+)", line)
        if m:
            version = tuple(int(x) for x in m.group(1).split("."))
            needs.setdefault(version, []).append(line.split()[-1])
    assert needs, f"objdump -T {so.name} lists no GLIBC_ versions"
    newest = max(needs)
    too_new = {".".join(map(str, v)): sorted(s) for v, s in needs.items() if v > MAX_GLIBC}
    assert not too_new, (
        f"{model}'s linux64 library needs glibc {'.'.join(map(str, newest))} "
        f"(> 2.17): {too_new}"
    )
    print(f"{model}.so: newest glibc symbol version GLIBC_{'.'.join(map(str, newest))}")


def linux_exports(so):
    # Defined (not *UND*) dynamic symbols named fmi2*
    return {
        f[-1]
        for f in (line.split() for line in objdump("-T", str(so)).splitlines())
        if len(f) >= 6 and f[-1].startswith("fmi2") and "*UND*" not in f
    }


def dll_table(dll):
    """(exported names, imported DLL names) from `objdump -p`."""
    out = pe_objdump("-p", str(dll))
    imports = re.findall(r"DLL Name: (\S+)", out)
    table = out.split("[Ordinal/Name Pointer] Table", 1)
    exports = set()
    if len(table) == 2:
        for line in table[1].splitlines()[1:]:
            m = re.match(r"\s*\[\s*\d+\]\s+(\S+)", line)
            if not m:
                break
            exports.add(m.group(1))
    return exports, imports


def test_same_fmi2_exports_on_both_platforms(binaries, need_objdump):
    model, so, dll = binaries
    if dll is None:
        pytest.fail(f"{model}.fmu has no win64 library")
    expected = fmi2_functions()
    linux = linux_exports(so)
    win = {n for n in dll_table(dll)[0] if n.startswith("fmi2")}
    assert linux == expected, f"linux64: missing {expected - linux}, extra {linux - expected}"
    assert win == linux, f"win64 vs linux64: missing {linux - win}, extra {win - linux}"
    print(f"{model}: {len(linux)} fmi2 functions exported by the .so and the .dll")


def test_dll_imports_only_windows_system_dlls(binaries):
    model, _, dll = binaries
    if dll is None:
        pytest.fail(f"{model}.fmu has no win64 library")
    _, imports = dll_table(dll)
    assert imports, f"objdump -p {dll.name} lists no imported DLL"
    runtime = [n for n in imports if n.lower() in MINGW_RUNTIME]
    assert not runtime, f"{dll.name} needs MinGW runtime DLLs: {runtime}"
    foreign = [n for n in imports if not system_dll(n)]
    assert not foreign, f"{dll.name} imports DLLs that are not part of Windows: {foreign}"
    print(f"{model}.dll imports {', '.join(sorted(imports, key=str.lower))}")


def test_allow_list_rejects_mingw_runtime():
    for n in MINGW_RUNTIME | {"zlib1.dll", "python3.dll"}:
        assert not system_dll(n), n
    for n in ["KERNEL32.dll", "api-ms-win-core-synch-l1-2-0.dll", "WS2_32.dll"]:
        assert system_dll(n), n
