/*
 * Fingerprints of the libm functions the FMU libraries import (objdump -T: hypot, sin, cos,
 * sincos, tan, pow, exp, log, log10, atan2, atan, asin): for each, a hash of the bits of its
 * results on 2,000,000 pseudo-random arguments (the same on every run). Two systems printing the
 * same hash for a function return the same bits for it; scripts/old_distro_check.sh prints them
 * for this machine and for the older distribution, where a different glibc can round differently.
 *
 * Build: zig cc -target x86_64-linux-gnu.2.17 -O1 -fno-builtin -o libm_probe libm_probe.c -lm
 */
#define _GNU_SOURCE
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

static uint64_t state;
static double rnd(double lo, double hi) {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return lo + (hi - lo) * (double)(state >> 11) / 9007199254740992.0;
}

#define PROBE(name, expr, lo, hi)                                                               \
    {                                                                                           \
        uint64_t h = 1469598103934665603ull, b;                                                 \
        state = 88172645463325252ull;                                                           \
        for (int i = 0; i < 2000000; i++) {                                                     \
            double x = rnd(lo, hi), y = rnd(lo, hi), r = (expr);                                \
            memcpy(&b, &r, 8);                                                                  \
            h = (h ^ b) * 1099511628211ull;                                                     \
        }                                                                                       \
        printf("%-6s %016llx\n", name, (unsigned long long)h);                                  \
    }

static double sincos_sum(double x) {
    double s, c;
    sincos(x, &s, &c);
    return s + 3.0 * c;
}

int main(void) {
    PROBE("hypot", hypot(x, y), -10, 10)
    PROBE("sin", sin(x), -10, 10)
    PROBE("cos", cos(x), -10, 10)
    PROBE("sincos", sincos_sum(x), -10, 10)
    PROBE("tan", tan(x), -1.5, 1.5)
    PROBE("pow", pow(fabs(x), y), -10, 10)
    PROBE("exp", exp(x), -10, 10)
    PROBE("log", log(fabs(x)), -10, 10)
    PROBE("log10", log10(fabs(x)), -10, 10)
    PROBE("atan2", atan2(x, y), -10, 10)
    PROBE("atan", atan(x), -10, 10)
    PROBE("asin", asin(x), -1, 1)
    return 0;
}
