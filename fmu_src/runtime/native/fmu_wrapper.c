/*
 * FMI 2.0 co-simulation wrapper of the tirefric transient brush tire (the "native" FMU).
 *
 * Compiled together with the tire core (tire_brush/csrc/tirecore.c) and a header generated at
 * build time (tfn_config.h, fmu_src/make/native_build.py: the variable table of
 * fmu_src/runtime/interface.py with start values, bounds, value references and the mapping of the
 * parameters onto tf_params). Needs nothing on the host but libc and libm.
 *
 * Behaviour (same as the pythonfmu slave fmu_src/runtime/slave.py, plus FMI status codes):
 *  - parameters are fixed: set them before fmi2ExitInitializationMode, which validates them and
 *    builds the core tire on the friction table of resources/tirefric-table.bin;
 *  - each doStep passes the inputs through the input guard of fmu_src/runtime/guard.py (same clamps,
 *    same input_status bits, messages once when a condition starts and when it clears), then
 *    advances the core by the communication step. Returns fmi2OK, or fmi2Warning when the step's
 *    inputs had to be repaired or the core reports a condition of its own (an outer step's work
 *    budget spent, the friction read outside the grid's temperature range: input_status bits
 *    1024 and 2048, logged like the guard's), fmi2Discard when the core failed (it is then
 *    reset to rest, input_status bit 64), fmi2Error for a communication step that is negative,
 *    not finite or longer than TFN_MAX_SUBSTEPS internal steps (nothing advanced);
 *  - misuse (unknown value reference, wrong type or causality, a fixed parameter set after
 *    initialisation, a call in the wrong state, a corrupt state blob) is fmi2Error and changes
 *    nothing; fmi2Fatal is never returned;
 *  - FMU state: get/set/serialize exactly (the serialized form is documented below).
 *
 * No global mutable state: instances are independent.
 */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "tirecore.h"
#include "tfn_config.h"

#define TFN_NIN 8
/* guard conditions: nonfinite x6, speed x3, neg. load, load, T, mu, nonfinite gamma, camber,
 * nonfinite water, water clamped, no wet branch */
#define TFN_NGUARD 18
/* conditions of the model's own step (fmu_src/runtime/guard.py, ModelConditions): the core's
 * work budget was spent, the friction was read outside the table's temperature axis */
#define TFN_NMODEL 2
#define TFN_NCOND (TFN_NGUARD + TFN_NMODEL)
#define TFN_MAX_SUBSTEPS 100000.0
#define TFN_TABLE_MAGIC "TIREFRIC-TABLE\0\0" /* 16 bytes */
#define TFN_STATE_MAGIC "TFNSTATE"           /* 8 bytes */
#define TFN_STATE_VERSION 3u

enum { PH_INSTANTIATED, PH_INIT, PH_STEP, PH_TERMINATED, PH_ERROR };

static const int GUARD_BIT[TFN_NGUARD] = {1, 1, 1, 1, 1, 1, 4, 4, 4, 2, 8, 16, 32, 1, 128,
                                          1, 256, 512};
/* the input each condition concerns, and the condition "not finite" of each input */
static const int GUARD_INPUT[TFN_NGUARD] = {0, 1, 2, 3, 4, 5, 0, 1, 2, 3, 3, 4, 5, 6, 6,
                                            7, 7, 7};
static const int NONFINITE[TFN_NIN] = {0, 1, 2, 3, 4, 5, 13, 15};
static const char *const IN_NAME[TFN_NIN] = {"vx", "vy", "omega", "Fz", "T_surface",
                                             "mu_scale", "gamma", "water_depth"};
/* the core's flags (tirecore.h, TF_FLAG_*), their input_status bits and names (STATUS_BITS of
 * fmu_src/runtime/interface.py) */
static const int MODEL_FLAG[TFN_NMODEL] = {TF_FLAG_BUDGET, TF_FLAG_T_RANGE};
static const int MODEL_BIT[TFN_NMODEL] = {1024, 2048};
static const char *const MODEL_NAME[TFN_NMODEL] = {"work_budget", "temperature_range"};
static const char *const GUARD_NAME[TFN_NGUARD] = {
    "nonfinite:vx", "nonfinite:vy", "nonfinite:omega", "nonfinite:Fz", "nonfinite:T_surface",
    "nonfinite:mu_scale", "speed_clamped:vx", "speed_clamped:vy", "speed_clamped:omega",
    "negative_load", "load_clamped", "temperature_clamped", "mu_scale_clamped",
    "nonfinite:gamma", "camber_clamped", "nonfinite:water_depth", "water_clamped",
    "no_wet_branch"};

typedef struct {
    double v[TFN_NV];          /* values of every non-string variable, by value reference */
    double last[TFN_NIN];      /* guard: last finite inputs */
    int32_t active[TFN_NCOND]; /* guard and model: steps each active condition has lasted */
    int32_t has_tire;
    double time;
    int32_t ncore;
    double *core;              /* tf_tire_get_state, ncore doubles */
} snapshot;

typedef struct {
    fmi2CallbackFunctions cb;
    char name[256];
    int logging, phase;
    double v[TFN_NV];
    double last[TFN_NIN];
    int32_t active[TFN_NCOND];
    double time;
    /* friction table from the resource file */
    int nv, nT, np;
    double *axes, *values;
    tf_table *table;
    tf_table *rr;              /* rolling-resistance table (NULL: none in this build) */
    tf_wet *wet;               /* wet branch of the grid (NULL: none in this build) */
    tf_tire *tire;
    double built[TFN_NV];      /* values the tire was built from (parameters compared) */
    double *buf;               /* core state scratch */
    int nbuf;
} comp;

/* -- logging ---------------------------------------------------------------------------------- */
static void logf_(comp *c, fmi2Status st, const char *fmt, ...) {
    char msg[1024], esc[2048];
    va_list ap;
    size_t j = 0;
    if (!c || !c->cb.logger) return;
    if (!c->logging && st == fmi2OK) return;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    for (size_t i = 0; msg[i] && j + 2 < sizeof esc; i++) { /* the logger formats: escape % */
        if (msg[i] == '%') esc[j++] = '%';
        esc[j++] = msg[i];
    }
    esc[j] = 0;
    const char *cat = st == fmi2OK ? "logAll" : st == fmi2Warning ? "logStatusWarning"
                    : st == fmi2Discard ? "logStatusDiscard" : "logStatusError";
    c->cb.logger(c->cb.componentEnvironment, c->name, st, cat, esc);
}

/* -- friction table resource -------------------------------------------------------------------
 * resources/tirefric-table.bin, little endian:
 *   16 bytes  magic "TIREFRIC-TABLE\0\0"
 *   uint32    format version (1)
 *   uint32    nv, nT, np (nodes along log10 v [m/s], T [K], log10 p [Pa])
 *   float64   log10_v[nv], T[nT], log10_p[np]
 *   float64   values[nv][nT][np][3] (mu_cold, mu_hot, dT_flash [K])
 *   uint64    FNV-1a 64 of all preceding bytes
 */
static uint64_t fnv1a(const unsigned char *p, size_t n) {
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
static int resource_path(const char *loc, const char *file, char *out, size_t n) {
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

static int load_table(comp *c, const char *path) {
    int n3[3];
    if (read_table(c, path, "friction table", n3, &c->axes, &c->values) != 0) return -1;
    c->nv = n3[0];
    c->nT = n3[1];
    c->np = n3[2];
    return 0;
}

/* The wet branch of the build (TFN_WET_FILE, fmu_src/runtime/table_file.py, wet_bytes), held
 * by the instance: its (v, T, p) nodes are the friction table's. */
static int load_wet(comp *c, const char *loc) {
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
static int load_rolling(comp *c, const char *loc) {
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

/* -- parameters and the core ------------------------------------------------------------------ */
/* 1/s0 of eq. (28) as tire_brush.friction.inverse_blend_length; -1 for s0 < 0 or NaN. */
static double inverse_blend_length(double s0) {
    if (!(s0 >= 0.0)) return -1.0;
    if (isinf(s0)) return 0.0;
    if (s0 > 0.0) { double x = 1.0 / s0; return x < 1e100 ? x : 1e100; }
    return 1e100;
}

/* Problems of the parameter values v (0: none; logs each). */
static int check_params(comp *c, const double *v) {
    int bad = 0;
    for (int i = 0; i < TFN_NV; i++) {
        const tfn_var *d = &TFN_VARS[i];
        double x = v[i];
        if (d->causality != TFN_PARAMETER || d->type != TFN_REAL) continue;
        if (d->bounds & TFN_FINITE && !isfinite(x)) {
            logf_(c, fmi2Error, "parameter %s = %g must be a finite number", d->name, x);
            bad++;
            continue;
        }
        if ((d->bounds & TFN_POSITIVE && !(x > 0.0)) ||
            (d->bounds & TFN_NONNEGATIVE && !(x >= 0.0)) ||
            (d->bounds & TFN_MAXIMUM && !(x <= d->maximum))) {
            logf_(c, fmi2Error, "parameter %s = %g is out of range (%s%s%s%g)", d->name, x,
                  d->bounds & TFN_POSITIVE ? "> 0 " : "",
                  d->bounds & TFN_NONNEGATIVE ? ">= 0 " : "",
                  d->bounds & TFN_MAXIMUM ? "<= " : "max ",
                  d->bounds & TFN_MAXIMUM ? d->maximum : INFINITY);
            bad++;
        }
    }
    if (!(v[TFN_VR_FZ_NOM] <= v[TFN_VR_FZ_MAX])) {
        logf_(c, fmi2Error, "tire.Fz_nom = %g N is above tire.patch.Fz_max = %g N",
              v[TFN_VR_FZ_NOM], v[TFN_VR_FZ_MAX]);
        bad++;
    }
    if (!(v[TFN_VR_AXES] == 0.0 || v[TFN_VR_AXES] == 1.0 || v[TFN_VR_AXES] == 2.0)) {
        logf_(c, fmi2Error, "axes = %g must be 0 (adapted SAE), 1 (ISO-W) or 2 (SAE)",
              v[TFN_VR_AXES]);
        bad++;
    }
    if (!(v[TFN_VR_N_ELEMENTS] >= 2.0)) {
        logf_(c, fmi2Error, "n_elements = %g must be >= 2", v[TFN_VR_N_ELEMENTS]);
        bad++;
    }
    if (inverse_blend_length(v[TFN_VR_S0]) < 0.0) {
        logf_(c, fmi2Error, "s0 = %g must be >= 0 m (inf allowed)", v[TFN_VR_S0]);
        bad++;
    }
    if (!(v[TFN_VR_LIMIT_T_MIN] < v[TFN_VR_LIMIT_T_MAX])) {
        logf_(c, fmi2Error, "limit.T_min = %g K must be below limit.T_max = %g K",
              v[TFN_VR_LIMIT_T_MIN], v[TFN_VR_LIMIT_T_MAX]);
        bad++;
    }
    return bad;
}

/* A table and a tire for the parameters v (NULLs and -1 on failure). */
static int make_core(comp *c, const double *v, tf_table **tab, tf_tire **tire) {
    tf_params P;
    memset(&P, 0, sizeof P);
    *tab = NULL;
    *tire = NULL;
    if (check_params(c, v)) return -1;
    tfn_fill_params(v, &P);
    P.tol = TFN_TOL;
    *tab = tf_table_new(c->nv, c->nT, c->np, c->axes, c->axes + c->nv,
                        c->axes + c->nv + c->nT, c->values, inverse_blend_length(v[TFN_VR_S0]));
    if (!*tab) { logf_(c, fmi2Error, "the tire core refused the friction table"); return -1; }
    *tire = tf_tire_new(&P, *tab);
    if (!*tire) {
        tf_table_free(*tab);
        *tab = NULL;
        logf_(c, fmi2Error, "the tire core refused these tire parameters");
        return -1;
    }
    tf_tire_set_rolling(*tire, c->rr);
    if (c->wet && tf_tire_set_wet(*tire, c->wet, v[TFN_VR_TEXTURE_DEPTH]) != 0) {
        tf_tire_free(*tire);
        tf_table_free(*tab);
        *tire = NULL;
        *tab = NULL;
        logf_(c, fmi2Error, "the tire core refused the wet branch (texture_depth = %g m must be "
              ">= 0)", v[TFN_VR_TEXTURE_DEPTH]);
        return -1;
    }
    return 0;
}

static void adopt_core(comp *c, const double *v, tf_table *tab, tf_tire *tire) {
    if (c->tire) tf_tire_free(c->tire);
    if (c->table) tf_table_free(c->table);
    c->table = tab;
    c->tire = tire;
    memcpy(c->built, v, sizeof c->built);
}

static int same_params(const double *a, const double *b) {
    for (int i = 0; i < TFN_NV; i++)
        if (TFN_VARS[i].causality == TFN_PARAMETER && memcmp(&a[i], &b[i], 8) != 0) return 0;
    return 1;
}

/* -- input guard (fmu_src/runtime/guard.py) ----------------------------------------------------------- */
static int guard_apply(comp *c, const double *u, double *x, const char *when) {
    int found[TFN_NGUARD] = {0}, any = 0, any_active = 0;
    const double *v = c->v;
    double vmax = v[TFN_VR_LIMIT_V], wmax = v[TFN_VR_LIMIT_OMEGA], Fzmax = v[TFN_VR_LIMIT_FZ];
    double Tmin = v[TFN_VR_LIMIT_T_MIN], Tmax = v[TFN_VR_LIMIT_T_MAX];
    double mumax = v[TFN_VR_LIMIT_MU_SCALE], gmax = v[TFN_VR_LIMIT_GAMMA];
    double dmax = v[TFN_VR_LIMIT_WATER_DEPTH];
    double raw[TFN_NIN];
    for (int i = 0; i < TFN_NIN; i++) {
        raw[i] = u[i];
        if (isfinite(u[i])) {
            c->last[i] = u[i];
            x[i] = u[i];
        } else {
            found[NONFINITE[i]] = 1;
            x[i] = c->last[i];
        }
    }
    double Fz = x[3], T = x[4], mu = x[5];
    for (int i = 0; i < 3; i++) {
        double lim = i == 2 ? wmax : vmax;
        if (fabs(x[i]) > lim) {
            found[6 + i] = 1;
            x[i] = copysign(lim, x[i]);
        }
    }
    if (Fz < 0.0) {
        found[9] = 1;
        x[3] = 0.0;
    } else if (Fz > Fzmax) {
        found[10] = 1;
        x[3] = Fzmax;
    }
    if (!(Tmin <= T && T <= Tmax)) {
        found[11] = 1;
        x[4] = fmin(fmax(T, Tmin), Tmax);
    }
    if (!(0.0 <= mu && mu <= mumax)) {
        found[12] = 1;
        x[5] = fmin(fmax(mu, 0.0), mumax);
    }
    if (fabs(x[6]) > gmax) {
        found[14] = 1;
        x[6] = copysign(gmax, x[6]);
    }
    if (!(0.0 <= x[7] && x[7] <= dmax)) {
        found[16] = 1;
        x[7] = fmin(fmax(x[7], 0.0), dmax);
    }
    if (x[7] > 0.0 && !c->wet) {
        found[17] = 1;
        x[7] = 0.0;
    }
    int bits = 0;
    for (int k = 0; k < TFN_NGUARD; k++) {
        any |= found[k];
        any_active |= c->active[k] != 0;
        if (found[k]) bits |= GUARD_BIT[k];
    }
    if (!any && !any_active) return 0;
    for (int k = 0; k < TFN_NGUARD; k++) {
        if (found[k] && c->active[k]) {
            c->active[k]++;
        } else if (found[k]) {
            c->active[k] = 1;
            int i = GUARD_INPUT[k], nonfinite = k < 6 || k == 13 || k == 15;
            logf_(c, fmi2Warning, "%s: input %s = %g is %s: %s (input_status bit %d; logged "
                  "once until it clears)", when, IN_NAME[i], raw[i],
                  nonfinite ? "not finite" : k == 9 ? "negative" : k == 17 ? "water on the road"
                  : "outside the envelope",
                  nonfinite ? "holding its last finite value" : k == 9 ? "taken as lift-off "
                  "(Fz = 0, no forces)" : k == 17 ? "this FMU's grid has no wet branch, the "
                  "road is taken as dry" : "clamped", GUARD_BIT[k]);
        } else if (c->active[k]) {
            logf_(c, fmi2OK, "%s: input condition '%s' cleared after %d step(s)", when,
                  GUARD_NAME[k], (int)c->active[k]);
            c->active[k] = 0;
        }
    }
    return bits;
}

/* Status bits of the model's conditions in the step just taken (core flags fl, tread
 * temperature T [K]), logged when a condition starts (warning) and when it clears. */
static int model_conditions(comp *c, int fl, double T, const char *when) {
    int bits = 0;
    for (int k = 0; k < TFN_NMODEL; k++) {
        int32_t *a = &c->active[TFN_NGUARD + k];
        if (fl & MODEL_FLAG[k]) {
            bits |= MODEL_BIT[k];
            if (*a) {
                (*a)++;
            } else {
                *a = 1;
                if (k == 0)
                    logf_(c, fmi2Warning, "%s: the element integrator's work budget of an outer "
                          "step was spent: its remaining elements finished it with one "
                          "implicit Euler stage (docs/tire-core.md, \"work budget\"; "
                          "input_status bit %d; logged once until it clears)", when,
                          MODEL_BIT[k]);
                else
                    logf_(c, fmi2Warning, "%s: the friction was read at a temperature outside "
                          "the friction grid's temperature range [%g, %g] K, at its edge's "
                          "values (T_tread = %g K; input_status bit %d; logged once until it "
                          "clears)", when, c->axes[c->nv], c->axes[c->nv + c->nT - 1], T,
                          MODEL_BIT[k]);
            }
        } else if (*a) {
            logf_(c, fmi2OK, "%s: model condition '%s' cleared after %d step(s)", when,
                  MODEL_NAME[k], (int)*a);
            *a = 0;
        }
    }
    return bits;
}

static void guard_reset(comp *c) {
    for (int i = 0; i < TFN_NIN; i++) c->last[i] = TFN_VARS[TFN_VR_INPUT0 + i].start;
    memset(c->active, 0, sizeof c->active);
}

/* Factor taking vy, Fy, Mz, My and alpha between the brush's axes (Pacejka's adapted SAE) and
 * those of parameter axes (fmu_src/runtime/interface.py, axis_signs): 0 adapted SAE (all +1),
 * 1 ISO-W (vy, Fy, Mz, My flip; alpha keeps its sign), 2 SAE (alpha flips); Mx and gamma keep
 * their sign in all three. */
static double axis_sign(const comp *c, int quantity) {
    int axes = (int)c->v[TFN_VR_AXES];
    if (axes == 1) return quantity == 3 ? 1.0 : -1.0;   /* 0 vy, 1 Fy, 2 Mz, 3 alpha, 4 My */
    if (axes == 2) return quantity == 3 ? -1.0 : 1.0;
    return 1.0;
}

/* Outputs in the brush's axes o[] to those of parameter axes. */
static void outputs_to_axes(const comp *c, double *o) {
    o[1] *= axis_sign(c, 1);
    o[2] *= axis_sign(c, 2);
    o[4] *= axis_sign(c, 3);
    o[11] *= axis_sign(c, 4);
}

/* Outputs of the undeflected tire at guarded inputs x in the brush's axes
 * (tire_brush.slip.slip_from_kinematics). */
static void initial_outputs(comp *c, const double *x) {
    double *o = c->v + TFN_VR_OUTPUT0;
    double vx = x[0], vy = x[1], omega = x[2];
    double ref = fabs(vx) >= c->v[TFN_VR_V_FLOOR] ? fabs(vx) : c->v[TFN_VR_V_FLOOR];
    double kappa = (omega * c->v[TFN_VR_R_E] - vx) / ref;
    if (vx < 0.0) kappa = -kappa;
    for (int k = 0; k < TF_NOUT; k++) o[k] = 0.0;
    o[3] = kappa;
    o[4] = atan2(-vy, ref);
    o[9] = x[4];
    outputs_to_axes(c, o);
}

static int build_model(comp *c) {
    tf_table *tab;
    tf_tire *tire;
    if (make_core(c, c->v, &tab, &tire) != 0) return -1;
    adopt_core(c, c->v, tab, tire);
    guard_reset(c);
    int n = tf_tire_state_size(tire);
    if (n > c->nbuf) {
        double *b = realloc(c->buf, sizeof(double) * (size_t)n);
        if (!b) return -1;
        c->buf = b;
        c->nbuf = n;
    }
    return 0;
}

/* -- FMI: inquiry, instantiation ------------------------------------------------------------- */
const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

static void reset_values(comp *c) {
    for (int i = 0; i < TFN_NV; i++) c->v[i] = TFN_VARS[i].start;
    guard_reset(c);
    c->time = 0.0;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String guid,
                              fmi2String resourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn) {
    comp tmp, *c;
    char path[4200];
    (void)visible;
    memset(&tmp, 0, sizeof tmp);
    if (functions) tmp.cb = *functions;
    snprintf(tmp.name, sizeof tmp.name, "%s", instanceName ? instanceName : "");
    tmp.logging = loggingOn != 0;
    if (fmuType != fmi2CoSimulation) {
        logf_(&tmp, fmi2Error, "this FMU is co-simulation only");
        return NULL;
    }
    if (!guid || strcmp(guid, TFN_GUID) != 0) {
        logf_(&tmp, fmi2Error, "GUID %s does not match this FMU's %s", guid ? guid : "(null)",
              TFN_GUID);
        return NULL;
    }
    if (resource_path(resourceLocation, TFN_TABLE_FILE, path, sizeof path) != 0) {
        logf_(&tmp, fmi2Error, "bad resource location %s",
              resourceLocation ? resourceLocation : "(null)");
        return NULL;
    }
    c = calloc(1, sizeof *c);
    if (!c) return NULL;
    *c = tmp;
    if (load_table(c, path) != 0 || load_rolling(c, resourceLocation) != 0 ||
        load_wet(c, resourceLocation) != 0) {
        free(c->axes);
        free(c->values);
        if (c->rr) tf_table_free(c->rr);
        if (c->wet) tf_wet_free(c->wet);
        free(c);
        return NULL;
    }
    reset_values(c);
    c->phase = PH_INSTANTIATED;
    return c;
}

void fmi2FreeInstance(fmi2Component comp_) {
    comp *c = comp_;
    if (!c) return;
    if (c->tire) tf_tire_free(c->tire);
    if (c->table) tf_table_free(c->table);
    if (c->rr) tf_table_free(c->rr);
    if (c->wet) tf_wet_free(c->wet);
    free(c->axes);
    free(c->values);
    free(c->buf);
    free(c);
}

fmi2Status fmi2SetDebugLogging(fmi2Component comp_, fmi2Boolean loggingOn, size_t n,
                               const fmi2String categories[]) {
    comp *c = comp_;
    (void)n;
    (void)categories;
    if (!c) return fmi2Error;
    c->logging = loggingOn != 0;
    return fmi2OK;
}

#define CHECK_C(c) do { if (!(c)) return fmi2Error; } while (0)

static fmi2Status wrong_phase(comp *c, const char *fn) {
    logf_(c, fmi2Error, "%s is not allowed in this state of the FMU", fn);
    return fmi2Error;
}

fmi2Status fmi2SetupExperiment(fmi2Component comp_, fmi2Boolean toleranceDefined,
                               fmi2Real tolerance, fmi2Real startTime,
                               fmi2Boolean stopTimeDefined, fmi2Real stopTime) {
    comp *c = comp_;
    (void)toleranceDefined; (void)tolerance; (void)stopTimeDefined; (void)stopTime;
    CHECK_C(c);
    if (c->phase != PH_INSTANTIATED) return wrong_phase(c, "fmi2SetupExperiment");
    c->time = startTime;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component comp_) {
    comp *c = comp_;
    CHECK_C(c);
    if (c->phase != PH_INSTANTIATED) return wrong_phase(c, "fmi2EnterInitializationMode");
    c->phase = PH_INIT;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component comp_) {
    comp *c = comp_;
    double x[TFN_NIN];
    CHECK_C(c);
    if (c->phase != PH_INIT) return wrong_phase(c, "fmi2ExitInitializationMode");
    if (build_model(c) != 0) return fmi2Error;
    int st = guard_apply(c, c->v + TFN_VR_INPUT0, x, "initialization");
    x[1] *= axis_sign(c, 0);
    initial_outputs(c, x);
    c->v[TFN_VR_STATUS] = st;
    c->phase = PH_STEP;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component comp_) {
    comp *c = comp_;
    CHECK_C(c);
    if (c->phase != PH_STEP && c->phase != PH_INIT) return wrong_phase(c, "fmi2Terminate");
    c->phase = PH_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component comp_) {
    comp *c = comp_;
    CHECK_C(c);
    if (c->tire) tf_tire_free(c->tire);
    if (c->table) tf_table_free(c->table);
    c->tire = NULL;
    c->table = NULL;
    reset_values(c);
    c->phase = PH_INSTANTIATED;
    return fmi2OK;
}

/* -- FMI: variables --------------------------------------------------------------------------- */
static const char *const TYPE_NAME[] = {"Real", "Integer", "Boolean", "String"};

/* Whether value reference r may be read (set = 0) or written (set = 1) as type t now. */
static int access_ok(comp *c, fmi2ValueReference r, int t, int set) {
    if (r >= TFN_NV) {
        logf_(c, fmi2Error, "unknown value reference %u", (unsigned)r);
        return 0;
    }
    const tfn_var *d = &TFN_VARS[r];
    if (d->type != t) {
        logf_(c, fmi2Error, "variable %s (value reference %u) is a %s, not a %s", d->name,
              (unsigned)r, TYPE_NAME[d->type], TYPE_NAME[t]);
        return 0;
    }
    if (!set) return 1;
    if (d->causality == TFN_INPUT) return c->phase != PH_TERMINATED;
    if (d->causality == TFN_PARAMETER) {
        if (c->phase == PH_INSTANTIATED || c->phase == PH_INIT) return 1;
        logf_(c, fmi2Error, "parameter %s is fixed: it cannot change after initialization",
              d->name);
        return 0;
    }
    logf_(c, fmi2Error, "variable %s is %s: it cannot be set", d->name,
          d->causality == TFN_OUTPUT ? "an output" : "a constant");
    return 0;
}

static fmi2Status check_all(comp *c, const fmi2ValueReference vr[], size_t n, int t, int set) {
    if (n && !vr) return fmi2Error;
    for (size_t i = 0; i < n; i++)
        if (!access_ok(c, vr[i], t, set)) return fmi2Error;
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component comp_, const fmi2ValueReference vr[], size_t n,
                       fmi2Real value[]) {
    comp *c = comp_;
    CHECK_C(c);
    if (check_all(c, vr, n, TFN_REAL, 0) != fmi2OK) return fmi2Error;
    for (size_t i = 0; i < n; i++) value[i] = c->v[vr[i]];
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component comp_, const fmi2ValueReference vr[], size_t n,
                          fmi2Integer value[]) {
    comp *c = comp_;
    CHECK_C(c);
    if (check_all(c, vr, n, TFN_INTEGER, 0) != fmi2OK) return fmi2Error;
    for (size_t i = 0; i < n; i++) value[i] = (fmi2Integer)c->v[vr[i]];
    return fmi2OK;
}

fmi2Status fmi2GetBoolean(fmi2Component comp_, const fmi2ValueReference vr[], size_t n,
                          fmi2Boolean value[]) {
    comp *c = comp_;
    CHECK_C(c);
    if (check_all(c, vr, n, TFN_BOOLEAN, 0) != fmi2OK) return fmi2Error;
    for (size_t i = 0; i < n; i++) value[i] = c->v[vr[i]] != 0.0 ? fmi2True : fmi2False;
    return fmi2OK;
}

fmi2Status fmi2GetString(fmi2Component comp_, const fmi2ValueReference vr[], size_t n,
                         fmi2String value[]) {
    comp *c = comp_;
    CHECK_C(c);
    if (check_all(c, vr, n, TFN_STRING, 0) != fmi2OK) return fmi2Error;
    for (size_t i = 0; i < n; i++) value[i] = TFN_VARS[vr[i]].str;
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component comp_, const fmi2ValueReference vr[], size_t n,
                       const fmi2Real value[]) {
    comp *c = comp_;
    CHECK_C(c);
    if (check_all(c, vr, n, TFN_REAL, 1) != fmi2OK) return fmi2Error;
    for (size_t i = 0; i < n; i++) c->v[vr[i]] = value[i];
    return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component comp_, const fmi2ValueReference vr[], size_t n,
                          const fmi2Integer value[]) {
    comp *c = comp_;
    CHECK_C(c);
    if (check_all(c, vr, n, TFN_INTEGER, 1) != fmi2OK) return fmi2Error;
    for (size_t i = 0; i < n; i++) c->v[vr[i]] = (double)value[i];
    return fmi2OK;
}

fmi2Status fmi2SetBoolean(fmi2Component comp_, const fmi2ValueReference vr[], size_t n,
                          const fmi2Boolean value[]) {
    comp *c = comp_;
    CHECK_C(c);
    if (check_all(c, vr, n, TFN_BOOLEAN, 1) != fmi2OK) return fmi2Error;
    for (size_t i = 0; i < n; i++) c->v[vr[i]] = value[i] ? 1.0 : 0.0;
    return fmi2OK;
}

fmi2Status fmi2SetString(fmi2Component comp_, const fmi2ValueReference vr[], size_t n,
                         const fmi2String value[]) {
    comp *c = comp_;
    (void)value;
    CHECK_C(c);
    return check_all(c, vr, n, TFN_STRING, 1) != fmi2OK ? fmi2Error : fmi2OK;
}

/* -- FMI: stepping ---------------------------------------------------------------------------- */
fmi2Status fmi2DoStep(fmi2Component comp_, fmi2Real t, fmi2Real h, fmi2Boolean noSetPrior) {
    comp *c = comp_;
    double x[TFN_NIN], out[TF_NOUT];
    (void)noSetPrior;
    CHECK_C(c);
    if (c->phase != PH_STEP) return wrong_phase(c, "fmi2DoStep");
    if (!c->tire && build_model(c) != 0) return fmi2Error;
    if (!(isfinite(h) && h >= 0.0) || h > TFN_MAX_SUBSTEPS * c->v[TFN_VR_DT_INTERNAL]) {
        logf_(c, fmi2Error, "doStep at t = %.17g s: communication step %g s is not finite, "
              "negative or longer than %.0f internal steps of %g s; nothing was advanced", t, h,
              TFN_MAX_SUBSTEPS, c->v[TFN_VR_DT_INTERNAL]);
        return fmi2Error;
    }
    char when[64];
    snprintf(when, sizeof when, "t = %.6g s", t);
    int st = guard_apply(c, c->v + TFN_VR_INPUT0, x, when);
    x[1] *= axis_sign(c, 0);
    int ok = tf_tire_step(c->tire, h, x, out) == 0;
    for (int k = 0; ok && k < TF_NOUT; k++) ok = isfinite(out[k]);
    c->time = t + h;
    if (ok) {
        st |= model_conditions(c, tf_tire_flags(c->tire), out[9], when);
        outputs_to_axes(c, out);
        memcpy(c->v + TFN_VR_OUTPUT0, out, sizeof out);
        c->v[TFN_VR_STATUS] = st;
        return st ? fmi2Warning : fmi2OK;
    }
    tf_tire_reset(c->tire, NAN);
    initial_outputs(c, x);
    c->v[TFN_VR_STATUS] = st | 64;
    logf_(c, fmi2Discard, "doStep at t = %.6g s: the tire model failed with inputs vx = %g, "
          "vy = %g, omega = %g, Fz = %g, T_surface = %g, mu_scale = %g, gamma = %g, "
          "water_depth = %g; it was reset to an undeflected tire at rest (input_status bit "
          "64)", t, x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]);
    return fmi2Discard;
}

fmi2Status fmi2CancelStep(fmi2Component comp_) {
    comp *c = comp_;
    CHECK_C(c);
    logf_(c, fmi2Error, "fmi2CancelStep: doStep never runs asynchronously");
    return fmi2Error;
}

static fmi2Status no_status(comp *c) {
    CHECK_C(c);
    logf_(c, fmi2Error, "status inquiry: doStep never returns fmi2Pending");
    return fmi2Error;
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *v) {
    (void)s; (void)v;
    return no_status(c);
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *v) {
    comp *cc = c;
    if (cc && s == fmi2LastSuccessfulTime && v) { *v = cc->time; return fmi2OK; }
    return no_status(c);
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *v) {
    (void)s; (void)v;
    return no_status(c);
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *v) {
    (void)s; (void)v;
    return no_status(c);
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *v) {
    (void)s; (void)v;
    return no_status(c);
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                       size_t n, const fmi2Integer order[],
                                       const fmi2Real value[]) {
    (void)vr; (void)n; (void)order; (void)value;
    CHECK_C(c);
    logf_(c, fmi2Error, "the FMU cannot interpolate inputs");
    return fmi2Error;
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                        size_t n, const fmi2Integer order[],
                                        fmi2Real value[]) {
    (void)vr; (void)n; (void)order; (void)value;
    CHECK_C(c);
    logf_(c, fmi2Error, "the FMU provides no output derivatives");
    return fmi2Error;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[],
                                        size_t nu, const fmi2ValueReference z[], size_t nz,
                                        const fmi2Real du[], fmi2Real dz[]) {
    (void)u; (void)nu; (void)z; (void)nz; (void)du; (void)dz;
    CHECK_C(c);
    logf_(c, fmi2Error, "the FMU provides no directional derivatives");
    return fmi2Error;
}

/* -- FMI: FMU state ----------------------------------------------------------------------------
 * Serialized form (host byte order: little endian on x86-64 and arm64):
 *   8 bytes   magic "TFNSTATE"
 *   uint32    format version (TFN_STATE_VERSION)
 *   uint32    number of variables TFN_NV
 *   40 bytes  GUID of the FMU (NUL padded): a state loads only into the same build
 *   int32     has_tire, ncore (doubles of the core state), active[TFN_NCOND] (guard and
 *             model conditions)
 *   float64   time, v[TFN_NV], last[TFN_NIN], core[ncore]
 *   uint64    FNV-1a 64 of all preceding bytes
 */
#define HDR (8 + 4 + 4 + 40)
#define NINT (2 + TFN_NCOND)

static size_t ser_size(int ncore) {
    return HDR + 4 * NINT + 8 * (1 + TFN_NV + TFN_NIN + (size_t)ncore) + 8;
}

static void snap_free(snapshot *s) {
    if (s) {
        free(s->core);
        free(s);
    }
}

fmi2Status fmi2GetFMUstate(fmi2Component comp_, fmi2FMUstate *state) {
    comp *c = comp_;
    CHECK_C(c);
    if (!state) return fmi2Error;
    int n = c->tire ? tf_tire_state_size(c->tire) : 0;
    snapshot *s = *state;
    if (!s) {
        s = calloc(1, sizeof *s);
        if (!s) return fmi2Error;
    }
    if (n > s->ncore || !s->core) {
        double *b = realloc(s->core, sizeof(double) * (size_t)(n > 0 ? n : 1));
        if (!b) {
            if (!*state) snap_free(s);
            return fmi2Error;
        }
        s->core = b;
    }
    memcpy(s->v, c->v, sizeof s->v);
    memcpy(s->last, c->last, sizeof s->last);
    memcpy(s->active, c->active, sizeof s->active);
    s->has_tire = c->tire != NULL;
    s->time = c->time;
    s->ncore = n;
    if (c->tire) tf_tire_get_state(c->tire, s->core);
    *state = s;
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component comp_, fmi2FMUstate state) {
    comp *c = comp_;
    const snapshot *s = state;
    CHECK_C(c);
    if (!s) {
        logf_(c, fmi2Error, "fmi2SetFMUstate: no state");
        return fmi2Error;
    }
    if (s->has_tire) {
        tf_table *tab = NULL;
        tf_tire *tire = NULL;
        int rebuild = !c->tire || !same_params(s->v, c->built);
        if (rebuild && make_core(c, s->v, &tab, &tire) != 0) return fmi2Error;
        tf_tire *target = rebuild ? tire : c->tire;
        if (tf_tire_state_size(target) != s->ncore) {
            logf_(c, fmi2Error, "fmi2SetFMUstate: the state's tire does not match");
            if (rebuild) { tf_tire_free(tire); tf_table_free(tab); }
            return fmi2Error;
        }
        int n = s->ncore;
        if (n > c->nbuf) {
            double *b = realloc(c->buf, sizeof(double) * (size_t)n);
            if (!b) {
                if (rebuild) { tf_tire_free(tire); tf_table_free(tab); }
                return fmi2Error;
            }
            c->buf = b;
            c->nbuf = n;
        }
        if (!rebuild) tf_tire_get_state(target, c->buf); /* to undo a refused state */
        if (tf_tire_set_state(target, s->core) != 0) {
            if (!rebuild) tf_tire_set_state(target, c->buf);
            else { tf_tire_free(tire); tf_table_free(tab); }
            logf_(c, fmi2Error, "fmi2SetFMUstate: the tire core refused the state");
            return fmi2Error;
        }
        if (rebuild) adopt_core(c, s->v, tab, tire);
    } else if (c->tire) {
        tf_tire_free(c->tire);
        tf_table_free(c->table);
        c->tire = NULL;
        c->table = NULL;
    }
    memcpy(c->v, s->v, sizeof c->v);
    memcpy(c->last, s->last, sizeof c->last);
    memcpy(c->active, s->active, sizeof c->active);
    c->time = s->time;
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component comp_, fmi2FMUstate *state) {
    CHECK_C(comp_);
    if (state) {
        snap_free(*state);
        *state = NULL;
    }
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component comp_, fmi2FMUstate state, size_t *size) {
    const snapshot *s = state;
    CHECK_C(comp_);
    if (!s || !size) return fmi2Error;
    *size = ser_size(s->ncore);
    return fmi2OK;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component comp_, fmi2FMUstate state, fmi2Byte out[],
                                 size_t size) {
    comp *c = comp_;
    const snapshot *s = state;
    CHECK_C(c);
    if (!s || !out || size != ser_size(s->ncore)) {
        logf_(c, fmi2Error, "fmi2SerializeFMUstate: wrong buffer size");
        return fmi2Error;
    }
    unsigned char *p = (unsigned char *)out;
    uint32_t u32;
    int32_t ints[NINT];
    memset(p, 0, HDR);
    memcpy(p, TFN_STATE_MAGIC, 8);
    u32 = TFN_STATE_VERSION;
    memcpy(p + 8, &u32, 4);
    u32 = TFN_NV;
    memcpy(p + 12, &u32, 4);
    memcpy(p + 16, TFN_GUID, strlen(TFN_GUID) < 40 ? strlen(TFN_GUID) : 40);
    p += HDR;
    ints[0] = s->has_tire;
    ints[1] = s->ncore;
    memcpy(ints + 2, s->active, sizeof s->active);
    memcpy(p, ints, sizeof ints);
    p += sizeof ints;
    memcpy(p, &s->time, 8);
    p += 8;
    memcpy(p, s->v, sizeof s->v);
    p += sizeof s->v;
    memcpy(p, s->last, sizeof s->last);
    p += sizeof s->last;
    memcpy(p, s->core, 8 * (size_t)s->ncore);
    p += 8 * (size_t)s->ncore;
    uint64_t h = fnv1a((const unsigned char *)out, size - 8);
    memcpy(p, &h, 8);
    return fmi2OK;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component comp_, const fmi2Byte in[], size_t size,
                                   fmi2FMUstate *state) {
    comp *c = comp_;
    const unsigned char *p = (const unsigned char *)in;
    uint32_t ver, nv;
    int32_t ints[NINT];
    char guid[41];
    uint64_t h;
    CHECK_C(c);
    if (!in || !state || size < HDR + sizeof ints + 8 || memcmp(p, TFN_STATE_MAGIC, 8) != 0) {
        logf_(c, fmi2Error, "fmi2DeSerializeFMUstate: not a tirefric native FMU state");
        return fmi2Error;
    }
    memcpy(&ver, p + 8, 4);
    memcpy(&nv, p + 12, 4);
    memcpy(guid, p + 16, 40);
    guid[40] = 0;
    memcpy(&h, p + size - 8, 8);
    if (ver != TFN_STATE_VERSION || nv != TFN_NV) {
        logf_(c, fmi2Error, "fmi2DeSerializeFMUstate: unsupported state version %u",
              (unsigned)ver);
        return fmi2Error;
    }
    if (fnv1a(p, size - 8) != h) {
        logf_(c, fmi2Error, "fmi2DeSerializeFMUstate: checksum mismatch (truncated or "
              "altered)");
        return fmi2Error;
    }
    if (strncmp(guid, TFN_GUID, 40) != 0) {
        logf_(c, fmi2Error, "fmi2DeSerializeFMUstate: the state comes from another build "
              "(%s)", guid);
        return fmi2Error;
    }
    memcpy(ints, p + HDR, sizeof ints);
    if (ints[1] < 0 || ints[1] > 100000000 || (ints[0] != 0 && ints[0] != 1) ||
        size != ser_size(ints[1])) {
        logf_(c, fmi2Error, "fmi2DeSerializeFMUstate: inconsistent sizes");
        return fmi2Error;
    }
    snapshot *s = calloc(1, sizeof *s);
    if (!s) return fmi2Error;
    s->core = malloc(sizeof(double) * (size_t)(ints[1] > 0 ? ints[1] : 1));
    if (!s->core) { free(s); return fmi2Error; }
    s->has_tire = ints[0];
    s->ncore = ints[1];
    memcpy(s->active, ints + 2, sizeof s->active);
    p += HDR + sizeof ints;
    memcpy(&s->time, p, 8);
    p += 8;
    memcpy(s->v, p, sizeof s->v);
    p += sizeof s->v;
    memcpy(s->last, p, sizeof s->last);
    p += sizeof s->last;
    memcpy(s->core, p, 8 * (size_t)s->ncore);
    if (*state) snap_free(*state);
    *state = s;
    return fmi2OK;
}
