/*
 * A minimal C host for the native brush-tire FMU (BrushTireNative): loads the binary with
 * dlopen, instantiates N tires, steps them at 1 kHz through a braking manoeuvre and prints the
 * last forces of tire 0 and the time per doStep. No FMI library needed, only the FMI 2.0
 * headers (shipped in the FMU's sources/ folder).
 *
 *   cc -std=c99 -O2 -I <unzipped FMU>/sources host_example.c -o host -ldl -lm
 *   ./host <unzipped FMU>/binaries/linux64/BrushTireNative.so \
 *          file://<unzipped FMU>/resources '<guid from modelDescription.xml>' 1000 4 [h [vr k]]
 *
 * (optional h: the communication step [s], default 1e-3; h = 0 times the wrapper alone;
 * optional vr k: set the Integer parameter of value reference vr to k before initialisation,
 * e.g. the parameter fidelity: 1 the real-time fidelity, the start value of an FMU built with
 * `tirefric fmu build --native --fidelity realtime`, 0 the full tire).
 * Output: "Fx Fy Mz" of tire 0 after the last step (%.17g), then
 * "median_us <median of one doStep> mean_us <mean> rtf <real-time factor of all tires>".
 * Value references: inputs vx..mu_scale 0..5, outputs Fx..T_tread 6..15
 * (modelDescription.xml).
 */
#define _POSIX_C_SOURCE 200809L
#include <dlfcn.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "fmi2Functions.h"

/* loggingOn of fmi2Instantiate (-DHOST_LOGGING=fmi2True to see every message) */
#ifndef HOST_LOGGING
#define HOST_LOGGING fmi2False
#endif

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status,
                   fmi2String category, fmi2String message, ...) {
    (void)env;
    (void)category;
    if (status != fmi2OK) fprintf(stderr, "[%s status %d] %s\n", name, (int)status, message);
}

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

#define LOAD(f)                                                                             \
    f##TYPE *f = (f##TYPE *)dlsym(lib, #f);                                                 \
    if (!f) { fprintf(stderr, "missing %s\n", #f); return 2; }

int main(int argc, char **argv) {
    if (argc < 5) {
        fprintf(stderr, "usage: %s binary resources-uri guid steps [tires [h]]\n", argv[0]);
        return 1;
    }
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (!lib) { fprintf(stderr, "dlopen: %s\n", dlerror()); return 2; }
    LOAD(fmi2Instantiate) LOAD(fmi2SetupExperiment) LOAD(fmi2EnterInitializationMode)
    LOAD(fmi2ExitInitializationMode) LOAD(fmi2SetReal) LOAD(fmi2GetReal) LOAD(fmi2DoStep)
    LOAD(fmi2SetInteger) LOAD(fmi2Terminate) LOAD(fmi2FreeInstance)
    int steps = atoi(argv[4]), n = argc > 5 ? atoi(argv[5]) : 1;
    if (steps < 1 || n < 1 || n > 64) return 1;
    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    fmi2Component c[64];
    for (int i = 0; i < n; i++) {
        char name[32];
        snprintf(name, sizeof name, "tire%d", i);
        c[i] = fmi2Instantiate(name, fmi2CoSimulation, argv[3], argv[2], &cb, fmi2False,
                               HOST_LOGGING);
        if (!c[i]) return 3;
        if (fmi2SetupExperiment(c[i], fmi2False, 0.0, 0.0, fmi2False, 0.0) != fmi2OK ||
            fmi2EnterInitializationMode(c[i]) != fmi2OK)
            return 4;
        if (argc > 8) {
            const fmi2ValueReference vr = (fmi2ValueReference)atol(argv[7]);
            const fmi2Integer k = atoi(argv[8]);
            if (fmi2SetInteger(c[i], &vr, 1, &k) != fmi2OK) return 4;
        }
        if (fmi2ExitInitializationMode(c[i]) != fmi2OK) return 4;
    }
    /* value references of modelDescription.xml: inputs 0-7, the 12 Real outputs 8-19 */
    const fmi2ValueReference vin[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    const fmi2ValueReference vout[12] = {8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19};
    double *dt_step = malloc(sizeof(double) * (size_t)steps);
    double t = 0.0, h = argc > 6 ? atof(argv[6]) : 1e-3, u[8], y[12], total = 0.0;
    for (int k = 0; k < steps; k++) {
        /* 20 m/s, slip angle ~1 deg, braking slip -5 % after 20 ms, 4 kN, 20 C */
        u[0] = 20.0;
        u[1] = 0.3;
        u[2] = 20.0 * (1.0 - 0.05 * (k > 20)) / 0.31;
        u[3] = 4000.0;
        u[4] = 293.15;
        u[5] = 1.0;
        u[6] = 0.0;
        u[7] = 0.0;
        double t0 = now();
        for (int i = 0; i < n; i++) {
            if (fmi2SetReal(c[i], vin, 8, u) != fmi2OK ||
                fmi2DoStep(c[i], t, h, fmi2True) > fmi2Warning ||
                fmi2GetReal(c[i], vout, 12, y) != fmi2OK)
                return 5;
            if (i == 0)
                for (int j = 0; j < 12; j++)
                    if (!isfinite(y[j])) return 6;
        }
        dt_step[k] = (now() - t0) / n;
        total += dt_step[k] * n;
        t += h;
    }
    double y0[12];
    fmi2GetReal(c[0], vout, 12, y0);
    printf("%.17g %.17g %.17g\n", y0[0], y0[1], y0[2]);
    qsort(dt_step, (size_t)steps, sizeof(double), cmp);
    printf("median_us %.4f mean_us %.4f rtf %.3f\n", 1e6 * dt_step[steps / 2],
           1e6 * total / steps / n, steps * 1e-3 / total);
    for (int i = 0; i < n; i++) {
        fmi2Terminate(c[i]);
        fmi2FreeInstance(c[i]);
    }
    free(dt_step);
    dlclose(lib);
    return 0;
}
