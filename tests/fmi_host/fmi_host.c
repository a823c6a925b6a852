/*
 * A minimal FMI 2.0 Co-Simulation host, for running an FMU's binary where Python and fmpy are
 * not at hand: inside an older distribution's root file system (scripts/old_distro_check.sh) and
 * under wine (scripts/wine_check.sh). One C file for both platforms: dlopen on Linux,
 * LoadLibrary on Windows.
 *
 *   fmi_host <unzipped FMU folder> <model identifier> <output value reference> [steps]
 *
 * Loads binaries/linux64/<model>.so (binaries/win64/<model>.dll on Windows), reads the GUID and
 * the default experiment (startTime, stopTime, tolerance, stepSize) from modelDescription.xml,
 * instantiates with the file: URI of the folder's resources/, sets up the experiment as fmu-build's
 * reference run does, enters and exits initialization, takes `steps` (default 100) steps of
 * stepSize at the times start + n * stepSize, reads the Real output, prints it and frees the
 * instance. Prints "RESULT <time> <value>" (value with 17 significant digits) on success and
 * exits 0; on any failure prints what failed and exits 1. With FMI_HOST_LOGGING=1 in the
 * environment the instance is created with loggingOn (its log messages go to stderr).
 *
 * Build: zig cc -target x86_64-linux-gnu.2.17 -O2 -o fmi_host fmi_host.c -ldl
 *        x86_64-w64-mingw32-gcc -O2 -static -o fmi_host.exe fmi_host.c
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef _WIN32
#include <windows.h>
#define LIB_DIR "win64"
#define LIB_EXT ".dll"
#else
#include <dlfcn.h>
#include <limits.h>
#define LIB_DIR "linux64"
#define LIB_EXT ".so"
#endif

typedef void *fmi2Component;
typedef unsigned int fmi2ValueReference;
typedef double fmi2Real;
typedef int fmi2Boolean;
typedef int fmi2Status; /* 0 OK, 1 Warning, 2 Discard, 3 Error, 4 Fatal, 5 Pending */

typedef struct {
    void (*logger)(void *, const char *, fmi2Status, const char *, const char *, ...);
    void *(*allocateMemory)(size_t, size_t);
    void (*freeMemory)(void *);
    void (*stepFinished)(void *, fmi2Status);
    void *componentEnvironment;
} fmi2CallbackFunctions;

typedef fmi2Component (*FmiInstantiate)(const char *, int, const char *, const char *,
                                     const fmi2CallbackFunctions *, fmi2Boolean, fmi2Boolean);
typedef fmi2Status (*FmiSetupExperiment)(fmi2Component, fmi2Boolean, fmi2Real, fmi2Real,
                                      fmi2Boolean, fmi2Real);
typedef fmi2Status (*FmiComponentFn)(fmi2Component);
typedef void (*FmiFreeInstance)(fmi2Component);
typedef fmi2Status (*FmiDoStep)(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean);
typedef fmi2Status (*FmiGetReal)(fmi2Component, const fmi2ValueReference *, size_t, fmi2Real *);
typedef const char *(*FmiGetVersion)(void);

static void logger(void *env, const char *instance, fmi2Status status, const char *category,
                   const char *message, ...) {
    va_list ap;
    (void)env;
    fprintf(stderr, "fmi_host: [%s status %d %s] ", instance ? instance : "?", status,
            category ? category : "");
    va_start(ap, message);
    vfprintf(stderr, message, ap);
    va_end(ap);
    fputc('\n', stderr);
}

static void die(const char *what) {
    fprintf(stderr, "fmi_host: error: %s\n", what);
    exit(1);
}

static char *read_file(const char *path) {
    FILE *f = fopen(path, "rb");
    long n;
    char *text;
    if (!f) return NULL;
    fseek(f, 0, SEEK_END);
    n = ftell(f);
    fseek(f, 0, SEEK_SET);
    text = malloc((size_t)n + 1);
    if (!text || fread(text, 1, (size_t)n, f) != (size_t)n) die("cannot read modelDescription.xml");
    text[n] = 0;
    fclose(f);
    return text;
}

/* The value of attribute `name` in the first element that starts with `element`. */
static char *attribute(const char *xml, const char *element, const char *name) {
    const char *e = strstr(xml, element), *a, *end;
    char key[64];
    char *value;
    if (!e) return NULL;
    snprintf(key, sizeof key, " %s=\"", name);
    a = strstr(e, key);
    end = strchr(e, '>');
    if (!a || (end && a > end)) return NULL;
    a += strlen(key);
    end = strchr(a, '"');
    value = malloc((size_t)(end - a) + 1);
    memcpy(value, a, (size_t)(end - a));
    value[end - a] = 0;
    return value;
}

static double number(const char *xml, const char *name, double fallback) {
    char *v = attribute(xml, "<DefaultExperiment", name);
    double x = v ? strtod(v, NULL) : fallback;
    free(v);
    return x;
}

#ifdef _WIN32
typedef HMODULE Library;
static Library open_library(const char *path) { return LoadLibraryA(path); }
static void *symbol(Library h, const char *name) { return (void *)GetProcAddress(h, name); }
static const char *load_error(void) {
    static char msg[64];
    snprintf(msg, sizeof msg, "LoadLibrary error %lu", (unsigned long)GetLastError());
    return msg;
}
static void absolute(const char *dir, char *out, size_t n) {
    char *p;
    if (!GetFullPathNameA(dir, (DWORD)n, out, NULL)) die("GetFullPathName failed");
    for (p = out; *p; p++)
        if (*p == '\\') *p = '/';
}
#else
typedef void *Library;
static Library open_library(const char *path) { return dlopen(path, RTLD_NOW | RTLD_LOCAL); }
static void *symbol(Library h, const char *name) { return dlsym(h, name); }
static const char *load_error(void) { return dlerror(); }
static void absolute(const char *dir, char *out, size_t n) {
    char buf[PATH_MAX];
    if (!realpath(dir, buf)) die("cannot resolve the FMU folder");
    snprintf(out, n, "%s", buf);
}
#endif

/* file: URI of a '/'-separated absolute path, percent-encoding all but unreserved characters. */
static void file_uri(const char *path, char *out, size_t n) {
    static const char *hex = "0123456789ABCDEF";
    size_t k = 0;
    const unsigned char *p = (const unsigned char *)path;
    k += (size_t)snprintf(out, n, path[0] == '/' ? "file://" : "file:///");
    for (; *p && k + 4 < n; p++) {
        if ((*p >= 'A' && *p <= 'Z') || (*p >= 'a' && *p <= 'z') || (*p >= '0' && *p <= '9') ||
            strchr("/-._~:", *p)) {
            out[k++] = (char)*p;
        } else {
            out[k++] = '%';
            out[k++] = hex[*p >> 4];
            out[k++] = hex[*p & 15];
        }
    }
    out[k] = 0;
}

int main(int argc, char **argv) {
    char dir[4096], path[4200], resources[4200], uri[13000];
    char *xml, *guid;
    double start, tolerance, stop, h, t;
    long steps, i;
    int logging;
    fmi2ValueReference vr;
    fmi2Real value;
    Library lib;
    fmi2Component c;
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    FmiInstantiate instantiate;
    FmiSetupExperiment setup;
    FmiComponentFn enter, exit_init, terminate;
    FmiFreeInstance free_instance;
    FmiDoStep do_step;
    FmiGetReal get_real;
    FmiGetVersion get_version;

    if (argc < 4) {
        fprintf(stderr, "usage: %s <unzipped FMU folder> <model identifier> <output vr> [steps]\n",
                argv[0]);
        return 2;
    }
    absolute(argv[1], dir, sizeof dir);
    vr = (fmi2ValueReference)strtoul(argv[3], NULL, 10);
    steps = argc > 4 ? strtol(argv[4], NULL, 10) : 100;

    snprintf(path, sizeof path, "%s/modelDescription.xml", dir);
    xml = read_file(path);
    if (!xml) die("no modelDescription.xml in the FMU folder");
    guid = attribute(xml, "<fmiModelDescription", "guid");
    if (!guid) die("no guid in modelDescription.xml");
    start = number(xml, "startTime", 0.0);
    stop = number(xml, "stopTime", 1.0);
    tolerance = number(xml, "tolerance", 1e-6);
    h = number(xml, "stepSize", 1e-4);

    snprintf(path, sizeof path, "%s/binaries/%s/%s%s", dir, LIB_DIR, argv[2], LIB_EXT);
    lib = open_library(path);
    if (!lib) {
        fprintf(stderr, "fmi_host: cannot load %s: %s\n", path, load_error());
        return 1;
    }
#define RESOLVE(var, type, name)                                                                \
    if (!(var = (type)symbol(lib, name))) die("missing " name);
    RESOLVE(get_version, FmiGetVersion, "fmi2GetVersion")
    RESOLVE(instantiate, FmiInstantiate, "fmi2Instantiate")
    RESOLVE(setup, FmiSetupExperiment, "fmi2SetupExperiment")
    RESOLVE(enter, FmiComponentFn, "fmi2EnterInitializationMode")
    RESOLVE(exit_init, FmiComponentFn, "fmi2ExitInitializationMode")
    RESOLVE(do_step, FmiDoStep, "fmi2DoStep")
    RESOLVE(get_real, FmiGetReal, "fmi2GetReal")
    RESOLVE(terminate, FmiComponentFn, "fmi2Terminate")
    RESOLVE(free_instance, FmiFreeInstance, "fmi2FreeInstance")
    printf("loaded %s (FMI %s)\n", path, get_version());

    snprintf(resources, sizeof resources, "%s/resources", dir);
    file_uri(resources, uri, sizeof uri);
    printf("instantiate %s, GUID %s, resources %s\n", argv[2], guid, uri);
    logging = getenv("FMI_HOST_LOGGING") && strcmp(getenv("FMI_HOST_LOGGING"), "1") == 0;
    c = instantiate(argv[2], 1 /* fmi2CoSimulation */, guid, uri, &cb, 0, logging);
    if (!c) die("fmi2Instantiate failed");
    if (setup(c, 1, tolerance, start, 1, stop) > 1) die("fmi2SetupExperiment failed");
    if (enter(c) > 1) die("fmi2EnterInitializationMode failed");
    if (exit_init(c) > 1) die("fmi2ExitInitializationMode failed");
    t = start;
    for (i = 0; i < steps; i++) {
        double next = start + (double)(i + 1) * h;
        if (do_step(c, t, next - t, 1) > 1) die("fmi2DoStep failed");
        t = next;
    }
    if (get_real(c, &vr, 1, &value) > 1) die("fmi2GetReal failed");
    printf("%ld steps of %g s: t = %g, output vr %u = %.17g\n", steps, h, t, vr, value);
    printf("RESULT %.17g %.17g\n", t, value);
    if (terminate(c) > 1) die("fmi2Terminate failed");
    free_instance(c);
    free(guid);
    free(xml);
    return 0;
}
