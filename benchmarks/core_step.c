/* Times tf_tire_step of the compiled tire core from C (no Python in the loop).
 *
 * Built and run by bench_brush.py, which writes the friction table and the parameters to a
 * binary file: int nv, nT, np; double log10_v[nv], T[nT], log10_p[np], values[nv*nT*np*3],
 * inv_s0; tf_params (as the struct); int n_warm, n_steps, n_tires; double in[TF_NIN], dt.
 * Prints the median and 90th percentile of the wall time per step [us] over n_steps steps,
 * each step advancing n_tires tires. With a second argument, a real-time patch table
 * (tire_brush.realtime.PatchTable.to_bytes, format 3), the tires step in the real-time
 * fidelity (bench_realtime.py); with a third, a wet branch (int nd, nt; double depth[nd],
 * log10_t[nt], mu[nd*nv*nT*np*4], w_dry[nd*nt*nv*nT*np], d_full, drain_scale, texture_depth),
 * the tires are given it (tf_tire_set_wet). */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
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
    if (argc > 2 && strcmp(argv[2], "-") != 0) { /* the patch table ("-": none) */
        FILE *g = fopen(argv[2], "rb");
        if (!g || fseek(g, 0, SEEK_END) != 0) return 2;
        long len = ftell(g);
        unsigned char *buf = len > 0 ? malloc((size_t)len) : NULL;
        rewind(g);
        if (!buf || fread(buf, 1, (size_t)len, g) != (size_t)len) return 2;
        fclose(g);
        pt = tf_patch_from_bytes(buf, (size_t)len);  /* format 3 (PatchTable.to_bytes) */
        free(buf);
        if (!pt) return 3;
    }
    tf_wet *wet = NULL;
    double texture = 0.0;
    if (argc > 3) {                 /* the wet branch on the friction table's nodes */
        FILE *g = fopen(argv[3], "rb");
        if (!g) return 2;
        int w[2];
        if (fread(w, sizeof(int), 2, g) != 2) return 2;
        size_t nn = (size_t)n[0] * n[1] * n[2];
        size_t m = (size_t)w[0] + w[1] + (size_t)w[0] * nn * 4 + (size_t)w[0] * w[1] * nn + 3;
        double *a = malloc(sizeof(double) * m);
        if (!a || fread(a, sizeof(double), m, g) != m) return 2;
        fclose(g);
        double *mu = a + w[0] + w[1], *wd = mu + (size_t)w[0] * nn * 4;
        double *tail = wd + (size_t)w[0] * w[1] * nn;
        wet = tf_wet_new(n[0], n[1], n[2], w[0], w[1], a, a + w[0], mu, wd, tail[0], tail[1]);
        texture = tail[2];
        if (!wet) return 3;
    }
    int nt = cfg[2];
    tf_tire **tires = malloc(sizeof(tf_tire *) * nt);
    for (int i = 0; i < nt; i++) {
        tires[i] = tf_tire_new(&p, t);
        if (!tires[i]) return 3;
        if (pt) tf_tire_set_patch(tires[i], pt);
        if (wet && tf_tire_set_wet(tires[i], wet, texture) != 0) return 3;
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
