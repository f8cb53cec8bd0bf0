/* Times tf_tire_step of the compiled tire core from C (no Python in the loop).
 *
 * Built and run by bench_brush.py, which writes the friction table and the parameters to a
 * binary file: int nv, nT, np; double log10_v[nv], T[nT], log10_p[np], values[nv*nT*np*3],
 * inv_s0; tf_params (as the struct); int n_warm, n_steps, n_tires; double in[TF_NIN], dt.
 * Prints the median and 90th percentile of the wall time per step [us] over n_steps steps,
 * each step advancing n_tires tires. With a second argument, a real-time patch table
 * (tire_brush.realtime.PatchTable.to_bytes), the tires step in the real-time fidelity
 * (bench_realtime.py). */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "tirecore.h"
#include "tirert.h"

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int cmp(const void *a, const void *b) {
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv) {
    if (argc < 2) return 2;
    FILE *f = fopen(argv[1], "rb");
    if (!f) return 2;
    int n[3];
    if (fread(n, sizeof(int), 3, f) != 3) return 2;
    size_t nval = (size_t)n[0] * n[1] * n[2] * 3;
    double *ax[3], *val = malloc(sizeof(double) * nval), inv_s0;
    for (int k = 0; k < 3; k++) {
        ax[k] = malloc(sizeof(double) * n[k]);
        if (fread(ax[k], sizeof(double), n[k], f) != (size_t)n[k]) return 2;
    }
    tf_params p;
    int cfg[3];
    double in[TF_NIN], dt;
    if (fread(val, sizeof(double), nval, f) != nval || fread(&inv_s0, sizeof(double), 1, f) != 1 ||
        fread(&p, sizeof p, 1, f) != 1 || fread(cfg, sizeof(int), 3, f) != 3 ||
        fread(in, sizeof(double), TF_NIN, f) != TF_NIN || fread(&dt, sizeof(double), 1, f) != 1)
        return 2;
    fclose(f);
    tf_table *t = tf_table_new(n[0], n[1], n[2], ax[0], ax[1], ax[2], val, inv_s0);
    if (!t) return 3;
    tf_patch *pt = NULL;
    if (argc > 2) {                 /* the patch table: magic, 6 int32, doubles, 8-byte hash */
        FILE *g = fopen(argv[2], "rb");
        if (!g) return 2;
        char magic[16];
        int d[TF_PATCH_NAX];
        if (fread(magic, 1, 16, g) != 16 || fread(d, sizeof(int), TF_PATCH_NAX, g) != TF_PATCH_NAX)
            return 2;
        size_t nax = 0, nn = 1;
        for (int k = 0; k < TF_PATCH_NAX; k++) {
            nax += (size_t)d[k];
            nn *= (size_t)d[k];
        }
        size_t n0 = (size_t)d[0] * d[1] * d[2] * d[3] * 2;
        size_t m = nax + (size_t)d[2] + n0 + TF_PATCH_NV * nn;
        double *a = malloc(sizeof(double) * m);
        if (!a || fread(a, sizeof(double), m, g) != m) return 2;
        fclose(g);
        pt = tf_patch_new(d, a, a + nax, a + nax + d[2], a + nax + d[2] + n0);
        free(a);
        if (!pt) return 3;
    }
    int nt = cfg[2];
    tf_tire **tires = malloc(sizeof(tf_tire *) * nt);
    for (int i = 0; i < nt; i++) {
        tires[i] = tf_tire_new(&p, t);
        if (!tires[i]) return 3;
        if (pt) tf_tire_set_patch(tires[i], pt);
    }
    double out[TF_NOUT];
    for (int k = 0; k < cfg[0]; k++)
        for (int i = 0; i < nt; i++) tf_tire_step(tires[i], dt, in, out);
    double *us = malloc(sizeof(double) * cfg[1]);
    for (int k = 0; k < cfg[1]; k++) {
        double t0 = now();
        for (int i = 0; i < nt; i++) tf_tire_step(tires[i], dt, in, out);
        us[k] = (now() - t0) * 1e6;
    }
    qsort(us, cfg[1], sizeof(double), cmp);
    printf("%.3f %.3f %.6g\n", us[cfg[1] / 2], us[(cfg[1] * 9) / 10], out[0]);
    return 0;
}
