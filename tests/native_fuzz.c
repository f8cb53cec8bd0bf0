/*
 * Fuzz host of the native FMU (tests/test_fmu_native_fuzz.py): adversarial inputs (NaN, inf,
 * huge, negative, denormal), odd communication steps, random rollbacks through get/set and
 * serialize/deserialize, corrupt state blobs and misuse, on two instances.
 *
 * argv: binary, resources URI, GUID, steps, seed[, cpu]. Exit 0 and a summary line when every
 * output stayed finite and every status was the expected one; otherwise a message and exit 1.
 * With cpu = 1 a doStep whose CPU time exceeds 50 ms + 5 ms per 0.187 ms of step (the bound of
 * tests/test_fmu_fuzz.py: the core's work budget per outer step, docs/tire-core.md) fails too.
 */
#define _POSIX_C_SOURCE 200809L
#include <dlfcn.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment e, fmi2String n, fmi2Status s, fmi2String c,
                   fmi2String m, ...) {
    (void)e; (void)n; (void)s; (void)c; (void)m;
}

static uint64_t rng = 88172645463325252ull;
static uint64_t next(void) {
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return rng;
}
static double unif(void) { return (next() >> 11) * (1.0 / 9007199254740992.0); }
static double range(double a, double b) { return a + (b - a) * unif(); }

static double adversarial(void) {
    switch (next() % 12) {
    case 0: return NAN;
    case 1: return INFINITY;
    case 2: return -INFINITY;
    case 3: return 1e300;
    case 4: return -1e300;
    case 5: return DBL_MIN / 4.0;
    case 6: return -0.0;
    case 7: return DBL_MAX;
    case 8: return pow(10.0, range(-300, 300)) * (next() % 2 ? 1 : -1);
    case 9: return 0.0;
    case 10: return range(-1e4, 1e4);
    default: return -DBL_MAX;
    }
}

#define LOAD(f) f##TYPE *f = (f##TYPE *)dlsym(lib, #f); if (!f) return 2;
#define FAIL(...) do { printf(__VA_ARGS__); printf(" (step %ld)\n", k); return 1; } while (0)

int main(int argc, char **argv) {
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) { printf("dlopen: %s\n", dlerror()); return 2; }
    LOAD(fmi2Instantiate) LOAD(fmi2SetupExperiment) LOAD(fmi2EnterInitializationMode)
    LOAD(fmi2ExitInitializationMode) LOAD(fmi2SetReal) LOAD(fmi2GetReal) LOAD(fmi2DoStep)
    LOAD(fmi2GetInteger) LOAD(fmi2SetInteger) LOAD(fmi2Terminate) LOAD(fmi2FreeInstance)
    LOAD(fmi2GetFMUstate) LOAD(fmi2SetFMUstate) LOAD(fmi2FreeFMUstate)
    LOAD(fmi2SerializedFMUstateSize) LOAD(fmi2SerializeFMUstate) LOAD(fmi2DeSerializeFMUstate)
    long steps = atol(argv[4]), k = 0;
    int cpu_check = argc > 6 && atoi(argv[6]) != 0;
    double cpu_max = 0.0, cpu_ratio = 0.0;
    rng ^= (uint64_t)atol(argv[5]) * 0x9E3779B97F4A7C15ull;
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    enum { NI = 2, NS = 4 };
    fmi2Component c[NI];
    fmi2FMUstate slot[NI][NS];
    char *blob[NI][NS];
    size_t blen[NI][NS];
    memset(slot, 0, sizeof slot);
    memset(blob, 0, sizeof blob);
    for (int i = 0; i < NI; i++) {
        c[i] = fmi2Instantiate(i ? "b" : "a", fmi2CoSimulation, argv[3], argv[2], &cb,
                               fmi2False, fmi2True);
        if (!c[i] || fmi2SetupExperiment(c[i], 0, 0, 0, 0, 0) ||
            fmi2EnterInitializationMode(c[i]) || fmi2ExitInitializationMode(c[i]))
            return 3;
    }
    const fmi2ValueReference vin[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    const fmi2ValueReference vout[12] = {8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19};
    const fmi2ValueReference vstatus = 20;
    double t[NI] = {0, 0};
    long n_adv = 0, n_roll = 0, n_deser = 0, n_corrupt = 0, n_discard = 0, n_err = 0,
         n_warn = 0, n_det = 0;
    for (k = 0; k < steps; k++) {
        int i = (int)(next() % NI);
        double u[8], y[12], y2[12];
        u[0] = range(-40, 60);
        u[1] = range(-10, 10);
        u[2] = range(-200, 300);
        u[3] = range(-2000, 12000);
        u[4] = range(230, 420);
        u[5] = range(-0.5, 2.5);
        u[6] = range(-0.7, 0.7);
        u[7] = next() % 3 == 0 ? range(-0.002, 0.01) : 0.0;
        if (next() % 5 == 0) {
            u[next() % 8] = adversarial();
            n_adv++;
        }
        if (next() % 50 == 0) u[0] = u[2] = 0.0; /* standstill */
        if (next() % 20 == 0) u[2] = u[0] / 0.31 * range(-1.0, 0.0); /* locked, reversing */
        double h = 1e-3;
        int bad_h = 0;
        switch (next() % 40) {
        case 0: h = 0.0; break;
        case 1: h = range(1e-7, 1e-2); break;
        case 2: h = -1e-3; bad_h = 1; break;
        case 3: h = NAN; bad_h = 1; break;
        case 4: h = 1e9; bad_h = 1; break;
        case 5: h = range(0.05, 0.3); break; /* a master's long step */
        default: break;
        }
        if (fmi2SetReal(c[i], vin, 8, u) != fmi2OK) FAIL("setReal of inputs refused");
        clock_t c0 = clock();
        fmi2Status st = fmi2DoStep(c[i], t[i], h, fmi2True);
        double used = (double)(clock() - c0) / CLOCKS_PER_SEC;
        double bound = bad_h || !(h > 0.0) ? 0.05 : 0.05 + 5e-3 * ceil(h / 1.87e-4);
        if (used > cpu_max) cpu_max = used;
        if (used / bound > cpu_ratio) cpu_ratio = used / bound;
        if (cpu_check && used > bound) FAIL("doStep(%g) took %g s of CPU (bound %g s)", h, used,
                                            bound);
        if (bad_h) {
            if (st != fmi2Error) FAIL("doStep with h = %g returned %d", h, st);
            n_err++;
        } else if (st == fmi2Discard) {
            n_discard++;
        } else if (st == fmi2Warning) {
            n_warn++;
        } else if (st != fmi2OK) {
            FAIL("doStep returned %d", st);
        }
        if (!bad_h) t[i] += h;
        if (fmi2GetReal(c[i], vout, 12, y) != fmi2OK) FAIL("getReal");
        for (int j = 0; j < 12; j++)
            if (!isfinite(y[j])) FAIL("output %d = %g not finite", j, y[j]);
        fmi2Integer status;
        if (fmi2GetInteger(c[i], &vstatus, 1, &status) || status < 0 || status > 4095)
            FAIL("input_status %d", (int)status);
        uint64_t r = next() % 1000;
        int s = (int)(next() % NS);
        if (r < 20) { /* save */
            if (fmi2GetFMUstate(c[i], &slot[i][s])) FAIL("getFMUstate");
            size_t n;
            if (fmi2SerializedFMUstateSize(c[i], slot[i][s], &n)) FAIL("size");
            blob[i][s] = realloc(blob[i][s], n);
            blen[i][s] = n;
            if (fmi2SerializeFMUstate(c[i], slot[i][s], blob[i][s], n)) FAIL("serialize");
        } else if (r < 30 && slot[i][s]) { /* roll back */
            if (fmi2SetFMUstate(c[i], slot[i][s])) FAIL("setFMUstate");
            n_roll++;
        } else if (r < 35 && blob[i][s]) { /* deserialize, maybe into the other instance */
            fmi2FMUstate tmp = NULL;
            int j = (int)(next() % NI);
            if (fmi2DeSerializeFMUstate(c[j], blob[i][s], blen[i][s], &tmp) ||
                fmi2SetFMUstate(c[j], tmp))
                FAIL("deserialize/set");
            fmi2FreeFMUstate(c[j], &tmp);
            n_deser++;
        } else if (r < 40 && blob[i][s]) { /* corrupt: refused, nothing changes */
            char *b = malloc(blen[i][s]);
            memcpy(b, blob[i][s], blen[i][s]);
            size_t len = blen[i][s] - (next() % 3 == 0 ? 1 + next() % 8 : 0);
            b[next() % len] ^= (char)(1 + next() % 255);
            fmi2FMUstate tmp = NULL;
            double before[12], after[12];
            fmi2GetReal(c[i], vout, 12, before);
            if (fmi2DeSerializeFMUstate(c[i], b, len, &tmp) != fmi2Error)
                FAIL("a corrupt state blob was accepted");
            fmi2GetReal(c[i], vout, 12, after);
            if (memcmp(before, after, sizeof before)) FAIL("refused blob changed the outputs");
            free(b);
            n_corrupt++;
        } else if (r < 45) { /* determinism: step, roll back, step again: same bits */
            fmi2FMUstate tmp = NULL;
            if (fmi2GetFMUstate(c[i], &tmp)) FAIL("getFMUstate");
            fmi2DoStep(c[i], t[i], 1e-3, fmi2True);
            fmi2GetReal(c[i], vout, 12, y);
            fmi2SetFMUstate(c[i], tmp);
            fmi2DoStep(c[i], t[i], 1e-3, fmi2True);
            fmi2GetReal(c[i], vout, 12, y2);
            if (memcmp(y, y2, sizeof y)) FAIL("replay after rollback differs");
            fmi2FreeFMUstate(c[i], &tmp);
            t[i] += 1e-3;
            n_det++;
        } else if (r < 47) { /* misuse: fixed parameter after init, unknown reference */
            fmi2Integer ne = 10;
            fmi2ValueReference vne = 1000000;
            if (fmi2SetInteger(c[i], &vne, 1, &ne) != fmi2Error) FAIL("unknown vr accepted");
            if (fmi2SetReal(c[i], &vout[0], 1, y) != fmi2Error) FAIL("output set accepted");
        }
    }
    for (int i = 0; i < NI; i++) {
        for (int s = 0; s < NS; s++) {
            if (slot[i][s]) fmi2FreeFMUstate(c[i], &slot[i][s]);
            free(blob[i][s]);
        }
        fmi2Terminate(c[i]);
        fmi2FreeInstance(c[i]);
    }
    printf("steps %ld adversarial %ld warnings %ld discards %ld bad_h %ld rollbacks %ld "
           "deserialized %ld corrupt_refused %ld replays %ld cpu_max %g cpu_over_bound %g\n",
           steps, n_adv, n_warn, n_discard, n_err, n_roll, n_deser, n_corrupt, n_det, cpu_max,
           cpu_ratio);
    dlclose(lib);
    return 0;
}
