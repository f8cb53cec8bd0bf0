/*
 * Resource readers of the native FMU: the friction table, the wet branch and the
 * rolling-resistance table (formats below; fmu_src/runtime/table_file.py writes them), and
 * the file URI of the resource folder.
 */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tfn_model.h"

/* -- friction table resource -------------------------------------------------------------------
 * resources/tirefric-table.bin, little endian:
 *   16 bytes  magic "TIREFRIC-TABLE\0\0"
 *   uint32    format version (1)
 *   uint32    nv, nT, np (nodes along log10 v [m/s], T [K], log10 p [Pa])
 *   float64   log10_v[nv], T[nT], log10_p[np]
 *   float64   values[nv][nT][np][3] (mu_cold, mu_hot, dT_flash [K])
 *   uint64    FNV-1a 64 of all preceding bytes
 */
uint64_t fnv1a(const unsigned char *p, size_t n) {
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; i++) { h ^= p[i]; h *= 1099511628211ull; }
    return h;
}

static uint32_t rd_u32(const unsigned char *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static uint64_t rd_u64(const unsigned char *p) {
    return (uint64_t)rd_u32(p) | (uint64_t)rd_u32(p + 4) << 32;
}

static double rd_f64(const unsigned char *p) {
    uint64_t u = rd_u64(p);
    double d;
    memcpy(&d, &u, 8);
    return d;
}

static int hexval(int ch) {
    if (ch >= '0' && ch <= '9') return ch - '0';
    if (ch >= 'a' && ch <= 'f') return ch - 'a' + 10;
    if (ch >= 'A' && ch <= 'F') return ch - 'A' + 10;
    return -1;
}

/* Path of a resource from the fmuResourceLocation URI (file:///..., file:/..., or a path). */
int resource_path(const char *loc, const char *file, char *out, size_t n) {
    char path[4096];
    size_t j = 0;
    if (!loc) return -1;
    if (strncmp(loc, "file://", 7) == 0) {
        loc += 7;
        if (strncmp(loc, "localhost/", 10) == 0) loc += 9;
    } else if (strncmp(loc, "file:", 5) == 0) {
        loc += 5;
    }
#ifdef _WIN32
    if (loc[0] == '/' && loc[1] && loc[2] == ':') loc++; /* /C:/... */
#endif
    for (size_t i = 0; loc[i] && j + 1 < sizeof path; i++) {
        if (loc[i] == '%' && hexval(loc[i + 1]) >= 0 && hexval(loc[i + 2]) >= 0) {
            path[j++] = (char)(hexval(loc[i + 1]) * 16 + hexval(loc[i + 2]));
            i += 2;
        } else {
            path[j++] = loc[i];
        }
    }
    while (j > 0 && (path[j - 1] == '/' || path[j - 1] == '\\')) j--;
    path[j] = 0;
    if ((size_t)snprintf(out, n, "%s/%s", path, file) >= n) return -1;
    return 0;
}

/* The whole file at path in a new buffer (its size in *n), or NULL (logged). */
static unsigned char *read_file(comp *c, const char *path, const char *what, size_t *n) {
    FILE *f = fopen(path, "rb");
    unsigned char *b = NULL;
    long size;
    if (!f) { logf_(c, fmi2Error, "cannot open the %s %s", what, path); return NULL; }
    if (fseek(f, 0, SEEK_END) != 0 || (size = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0 ||
        !(b = malloc((size_t)size + 1)) || fread(b, 1, (size_t)size, f) != (size_t)size) {
        fclose(f);
        free(b);
        logf_(c, fmi2Error, "cannot read the %s %s", what, path);
        return NULL;
    }
    fclose(f);
    *n = (size_t)size;
    return b;
}

/* Read a table file (format above; the rolling-resistance table uses it too, with the axes
 * log10 |V_r|, T_tread, log10 Fz and the values f_r, tread share, 0) into new arrays. */
static int read_table(comp *c, const char *path, const char *what, int *n3, double **axes_out,
                      double **values_out) {
    size_t n;
    *axes_out = *values_out = NULL;
    unsigned char *b = read_file(c, path, what, &n);
    if (!b) return -1;
    if (n < 40 || memcmp(b, TFN_TABLE_MAGIC, 16) != 0 || rd_u32(b + 16) != 1u) {
        free(b);
        logf_(c, fmi2Error, "%s is not a tirefric table file (version 1)", path);
        return -1;
    }
    uint32_t nv = rd_u32(b + 20), nT = rd_u32(b + 24), np = rd_u32(b + 28);
    if (nv < 2 || nT < 2 || np < 2 || nv > 100000 || nT > 100000 || np > 100000 ||
        (uint64_t)nv * nT * np > 50000000ull) {
        free(b);
        logf_(c, fmi2Error, "%s: bad table size", path);
        return -1;
    }
    size_t nax = (size_t)nv + nT + np, nval = (size_t)nv * nT * np * 3;
    if (n != 32 + 8 * (nax + nval) + 8 || fnv1a(b, n - 8) != rd_u64(b + n - 8)) {
        free(b);
        logf_(c, fmi2Error, "%s: size or checksum mismatch (corrupt file)", path);
        return -1;
    }
    double *axes = malloc(8 * nax), *values = malloc(8 * nval);
    if (!axes || !values) { free(b); free(axes); free(values); return -1; }
    for (size_t i = 0; i < nax; i++) axes[i] = rd_f64(b + 32 + 8 * i);
    for (size_t i = 0; i < nval; i++) values[i] = rd_f64(b + 32 + 8 * (nax + i));
    n3[0] = (int)nv;
    n3[1] = (int)nT;
    n3[2] = (int)np;
    *axes_out = axes;
    *values_out = values;
    free(b);
    return 0;
}

int load_table(comp *c, const char *path) {
    int n3[3];
    if (read_table(c, path, "friction table", n3, &c->axes, &c->values) != 0) return -1;
    c->nv = n3[0];
    c->nT = n3[1];
    c->np = n3[2];
    return 0;
}

/* The wet branch of the build (TFN_WET_FILE, fmu_src/runtime/table_file.py, wet_bytes), held
 * by the instance: its (v, T, p) nodes are the friction table's. */
int load_wet(comp *c, const char *loc) {
    char path[4200];
    if (!TFN_HAS_WET) return 0;
    size_t n;
    if (resource_path(loc, TFN_WET_FILE, path, sizeof path) != 0) return -1;
    unsigned char *b = read_file(c, path, "wet branch", &n);
    if (!b) return -1;
    if (n < 64 || memcmp(b, "TIREFRIC-WET\0\0\0\0", 16) != 0 || rd_u32(b + 16) != 1u) {
        free(b);
        logf_(c, fmi2Error, "%s is not a tirefric wet-branch file (version 1)", path);
        return -1;
    }
    uint32_t nd = rd_u32(b + 20), nt = rd_u32(b + 24), nv = rd_u32(b + 28), nT = rd_u32(b + 32),
             np = rd_u32(b + 36);
    uint64_t nn = (uint64_t)nv * nT * np;
    if (nd < 2 || nt < 2 || nd > 1000 || nt > 1000 || (int)nv != c->nv || (int)nT != c->nT ||
        (int)np != c->np || n != 48 + 8 * (2 + nd + nt + 4 * nd * nn + (uint64_t)nd * nt * nn) ||
        fnv1a(b, n - 8) != rd_u64(b + n - 8)) {
        free(b);
        logf_(c, fmi2Error, "%s: size, nodes or checksum mismatch (corrupt file)", path);
        return -1;
    }
    size_t m = (n - 48) / 8;
    double *a = malloc(sizeof(double) * m);
    if (!a) { free(b); return -1; }
    for (size_t i = 0; i < m; i++) a[i] = rd_f64(b + 40 + 8 * i);
    free(b);
    const double *depth = a + 2, *lt = depth + nd, *mu = lt + nt, *w = mu + 4 * nd * nn;
    c->wet = tf_wet_new((int)nv, (int)nT, (int)np, (int)nd, (int)nt, depth, lt, mu, w, a[0], a[1]);
    free(a);
    if (!c->wet) {
        logf_(c, fmi2Error, "the tire core refused the wet branch %s", path);
        return -1;
    }
    return 0;
}

/* The rolling-resistance table of the build (TFN_ROLLING_FILE), held by the instance. */
int load_rolling(comp *c, const char *loc) {
    char path[4200];
    int n3[3];
    double *axes, *values;
    if (!TFN_HAS_ROLLING) return 0;
    if (resource_path(loc, TFN_ROLLING_FILE, path, sizeof path) != 0 ||
        read_table(c, path, "rolling-resistance table", n3, &axes, &values) != 0)
        return -1;
    c->rr = tf_table_new(n3[0], n3[1], n3[2], axes, axes + n3[0], axes + n3[0] + n3[1],
                         values, 0.0);
    free(axes);
    free(values);
    if (!c->rr) {
        logf_(c, fmi2Error, "the tire core refused the rolling-resistance table %s", path);
        return -1;
    }
    return 0;
}

/* The real-time fidelity's patch table (tire_brush.realtime.PatchTable.to_bytes, format 3;
 * the core reads its layout, tf_patch_from_bytes), with its FNV-1a 64 trailer checked here as
 * the other resources'. */
int load_patch(comp *c, const char *loc) {
    char path[4200];
    if (!TFN_HAS_PATCH) return 0;
    size_t n;
    if (resource_path(loc, TFN_PATCH_FILE, path, sizeof path) != 0) return -1;
    unsigned char *b = read_file(c, path, "real-time patch table", &n);
    if (!b) return -1;
    c->patch = n >= 8 && fnv1a(b, n - 8) == rd_u64(b + n - 8) ? tf_patch_from_bytes(b, n) : NULL;
    free(b);
    if (!c->patch) {
        logf_(c, fmi2Error, "%s: not a tirefric patch table (format 3), or its size (%.0f "
              "bytes) does not match its axes or its checksum does not match (corrupt file), "
              "or the tire core refused its values", path, (double)n);
        return -1;
    }
    return 0;
}
