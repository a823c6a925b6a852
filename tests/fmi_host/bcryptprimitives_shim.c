/*
 * bcryptprimitives.dll for wine 8 (Debian 12's), which lacks it: only ProcessPrng, the one
 * function Rust's standard library imports from it (its random source since Rust 1.78, Windows
 * 10 and later, where the real DLL is part of the system). scripts/wine_check.sh places this
 * next to fmi_host.exe for the wine run only; the FMU does not ship it.
 *
 * Build: x86_64-w64-mingw32-gcc -O2 -shared -o bcryptprimitives.dll bcryptprimitives_shim.c -ladvapi32
 */
#include <windows.h>
#include <ntsecapi.h>

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T len) {
    while (len > 0) {
        ULONG n = len > 0x10000000 ? 0x10000000 : (ULONG)len;
        if (!RtlGenRandom(data, n)) return FALSE;
        data += n;
        len -= n;
    }
    return TRUE;
}
