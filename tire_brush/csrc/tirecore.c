/*
 * tirecore.c: the transient and steady brush tire (tirecore.h; method in docs/tire-core.md).
 *
 * Every floating-point operation here is mirrored, in the same order, by the Python
 * reference tire_brush/element.py; the tests pin the two to each other. Build without
 * contraction of multiply-adds (-ffp-contract=off) and without fast-math so that both give
 * the same IEEE results.
 */
#include "tirecore.h"
#include "tirert.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* SDIRK2 diagonal coefficient gamma = 1 - 1/sqrt(2) (Alexander 1977, L-stable, order 2). */
#define GAMMA 0.2928932188134524
/* Elements slipping slower than this [m/s] count as adhering in the sliding fraction. */
#define CREEP_SPEED 1e-3
/* Smallest element sub-step [s]: a step this short is accepted whatever its error. */
#define H_MIN 1e-8
/* Largest slipped distance carried [m]. */
#define S_MAX 1e6
/* Contact-age length D per renewal length s0 of eq. (28): s0 = 0.2 D (D the macro-asperity
 * contact size, lookup/surface.py), so D = 5 s0 (docs/tire-core.md, "contact age"). */
#define AGE_D_PER_S0 5.0
/* Smallest rolling speed of the steady march [m/s] (a locked wheel). */
#define V_ROLL_MIN 1e-6
#define LN10 2.302585092994046
/* pi / 2: the inclination angle is refused at or beyond it */
#define HALF_PI 1.5707963267948966
/* Longest outer step in units of the tread tip's period over 2 pi, 1 / sqrt(k / m): the
 * linearly implicit belt coupling holds the belt's velocity over the step while the tips ring
 * against it; beyond omega h ~ 1.5 that sampled loop can grow (docs/tire-core.md, "belt
 * coupling at high rolling speed"). 1.4 keeps the shipped tire's 0.25 ms (omega h = 1.39). */
#define TIP_STEP 1.4
/* Largest loop gain of the belt's lateral-yaw coupling through the rolling speed over an
 * outer step (belt_gain; docs/tire-core.md): measured stable up to 0.52, unstable from 0.55. */
#define BELT_GAIN_MAX 0.5

struct tf_table {
    int n[3];
    double *ax[3];
    int uni[3];
    double lo[3], inv[3];
    double *val;      /* node values, (nv, nT, np, 3) */
    double *vnode;    /* 10^log10_v */
    double *ispan;    /* 1 / (log10 v_{j+1} - log10 v_j) */
    /* bounds of the friction for the node walk of the stage solve: the largest value of
     * either branch at nodes >= j and the smallest at nodes <= j, (nv, nT, np); NULL when the
     * table has a negative value (then nothing is skipped) */
    double *smax, *pmin;
    double inv_s0;
};

struct tf_tire {
    tf_params p;
    const tf_table *t;
    double a_max, dx;
    int L;
    double *el;
    double x_top, delta[2], Vb[2], F[2], T_tread, time;
    double psi, wpsi, M;   /* belt yaw [rad], its rate [rad/s], tread moment on the belt [N m] */
    double wc;             /* spin of the base from camber in the last step [rad/s] */
    const tf_table *rr;    /* rolling resistance (tf_tire_set_rolling), or NULL */
    const tf_wet *wet;     /* wet branch (tf_tire_set_wet), or NULL */
    const tf_patch *patch; /* patch table of the real-time fidelity (tf_tire_set_patch), or NULL */
    double texture_depth;  /* the road's mean texture depth [m] */
    tf_table scratch;      /* the friction of the current water depth and drainage time: the
                              dry table's axes, its own values and bounds (rows wkey[2] and the
                              next temperature row are valid) */
    double wkey[3];        /* water depth, log10 t_drain, temperature row of the scratch */
    int wvalid;
    double out[TF_NOUT];
    double work;
    double stages, fallbacks;  /* stage solves and budget fallbacks since creation */
    int flags;                 /* TF_FLAG_* of the last step */
};

/* ---------------------------------------------------------------- table ---------------- */

/* The node-walk bounds smax, pmin of the (T, p) columns k0 <= k < k1 from the values. */
static void table_bounds(tf_table *t, size_t k0, size_t k1) {
    int nv = t->n[0];
    size_t ntp = (size_t)t->n[1] * t->n[2];
    const double *values = t->val;
    for (size_t k = k0; k < k1; k++) {
        for (int j = nv - 1; j >= 0; j--) {
            const double *v = values + ((size_t)j * ntp + k) * 3;
            double hi = v[0] > v[1] ? v[0] : v[1];
            if (j < nv - 1 && t->smax[(j + 1) * ntp + k] > hi) hi = t->smax[(j + 1) * ntp + k];
            t->smax[j * ntp + k] = hi;
        }
        for (int j = 0; j < nv; j++) {
            const double *v = values + ((size_t)j * ntp + k) * 3;
            double lo = v[0] < v[1] ? v[0] : v[1];
            if (j > 0 && t->pmin[(j - 1) * ntp + k] < lo) lo = t->pmin[(j - 1) * ntp + k];
            t->pmin[j * ntp + k] = lo;
        }
    }
}

static int axis_ok(int n, const double *a) {
    if (n < 2) return 0;
    for (int i = 0; i < n; i++) {
        if (!isfinite(a[i])) return 0;
        if (i > 0 && !(a[i] > a[i - 1])) return 0;
    }
    return 1;
}

tf_table *tf_table_new(int nv, int nT, int np, const double *log10_v, const double *T,
                       const double *log10_p, const double *values, double inv_s0) {
    const double *axes[3] = {log10_v, T, log10_p};
    int n[3] = {nv, nT, np};
    if (!(inv_s0 >= 0.0) || !isfinite(inv_s0)) return NULL;
    for (int k = 0; k < 3; k++)
        if (!axis_ok(n[k], axes[k])) return NULL;
    size_t nval = (size_t)nv * nT * np * 3;
    for (size_t i = 0; i < nval; i++)
        if (!isfinite(values[i])) return NULL;
    tf_table *t = calloc(1, sizeof *t);
    if (!t) return NULL;
    t->inv_s0 = inv_s0;
    for (int k = 0; k < 3; k++) {
        t->n[k] = n[k];
        t->ax[k] = malloc(sizeof(double) * n[k]);
        if (!t->ax[k]) { tf_table_free(t); return NULL; }
        memcpy(t->ax[k], axes[k], sizeof(double) * n[k]);
        double d = (axes[k][n[k] - 1] - axes[k][0]) / (n[k] - 1);
        int uni = 1;
        for (int i = 1; i < n[k]; i++)
            if (fabs((axes[k][i] - axes[k][i - 1]) - d) > 1e-9 * fabs(d)) uni = 0;
        t->uni[k] = uni;
        t->lo[k] = axes[k][0];
        t->inv[k] = (n[k] - 1) / (axes[k][n[k] - 1] - axes[k][0]);
    }
    t->val = malloc(sizeof(double) * nval);
    t->vnode = malloc(sizeof(double) * nv);
    t->ispan = malloc(sizeof(double) * nv);
    if (!t->val || !t->vnode || !t->ispan) { tf_table_free(t); return NULL; }
    memcpy(t->val, values, sizeof(double) * nval);
    int nonneg = 1;
    for (size_t i = 0; i < nval; i++)
        if (i % 3 != 2 && values[i] < 0.0) nonneg = 0;
    if (nonneg) {
        size_t ntp = (size_t)nT * np;
        t->smax = malloc(sizeof(double) * nv * ntp);
        t->pmin = malloc(sizeof(double) * nv * ntp);
        if (!t->smax || !t->pmin) { tf_table_free(t); return NULL; }
        table_bounds(t, 0, ntp);
    }
    for (int j = 0; j < nv; j++) {
        t->vnode[j] = pow(10.0, log10_v[j]);
        t->ispan[j] = j < nv - 1 ? 1.0 / (log10_v[j + 1] - log10_v[j]) : 0.0;
    }
    return t;
}

void tf_table_free(tf_table *t) {
    if (!t) return;
    for (int k = 0; k < 3; k++) free(t->ax[k]);
    free(t->val);
    free(t->vnode);
    free(t->ispan);
    free(t->smax);
    free(t->pmin);
    free(t);
}

/* ---------------------------------------------------------------- wet branch ----------- */

struct tf_wet {
    int n[3];         /* nodes of the friction table: nv, nT, np */
    int nd, nt;
    double *depth, *log10_t;
    double *mu;       /* (nd, nv, nT, np, 4): cold_w0, cold_w1, hot_w0, hot_w1 */
    double *w;        /* (nd, nt, nv, nT, np): dry share */
    double d_full, drain_scale;
};

void tf_wet_free(tf_wet *w) {
    if (!w) return;
    free(w->depth);
    free(w->log10_t);
    free(w->mu);
    free(w->w);
    free(w);
}

tf_wet *tf_wet_new(int nv, int nT, int np, int nd, int nt, const double *depth,
                   const double *log10_t, const double *mu, const double *w_dry,
                   double d_full, double drain_scale) {
    if (nv < 2 || nT < 2 || np < 2 || !axis_ok(nd, depth) || depth[0] != 0.0 ||
        !axis_ok(nt, log10_t))
        return NULL;
    if (!(isfinite(d_full) && d_full > 0.0) || !(isfinite(drain_scale) && drain_scale > 0.0))
        return NULL;
    size_t nn = (size_t)nv * nT * np;
    size_t nmu = (size_t)nd * nn * 4, nw = (size_t)nd * nt * nn;
    for (size_t i = 0; i < nmu; i++)
        if (!(isfinite(mu[i]) && mu[i] >= 0.0)) return NULL;
    for (size_t i = 0; i < nw; i++)
        if (!isfinite(w_dry[i])) return NULL;
    tf_wet *w = calloc(1, sizeof *w);
    if (!w) return NULL;
    w->n[0] = nv;
    w->n[1] = nT;
    w->n[2] = np;
    w->nd = nd;
    w->nt = nt;
    w->depth = malloc(sizeof(double) * nd);
    w->log10_t = malloc(sizeof(double) * nt);
    w->mu = malloc(sizeof(double) * nmu);
    w->w = malloc(sizeof(double) * nw);
    if (!w->depth || !w->log10_t || !w->mu || !w->w) { tf_wet_free(w); return NULL; }
    memcpy(w->depth, depth, sizeof(double) * nd);
    memcpy(w->log10_t, log10_t, sizeof(double) * nt);
    memcpy(w->mu, mu, sizeof(double) * nmu);
    memcpy(w->w, w_dry, sizeof(double) * nw);
    w->d_full = d_full;
    w->drain_scale = drain_scale;
    return w;
}

/* |(x, y)| as sqrt(x^2 + y^2): libm's hypot and Python's math.hypot round differently, and
 * the Python reference must give the same bits. The magnitudes here (speeds, stresses,
 * forces) are far from overflow. */
static double norm2(double x, double y) { return sqrt(x * x + y * y); }

/* The cold weight exp(-a) of eq. (28) for a = s / s0 >= 0 (taken as 0 beyond a = 700, where
 * it is below 1e-304 anyway: fully developed elements skip the exponential). */
static double cold_weight(double a) { return a > 700.0 ? 0.0 : exp(-a); }

/* Cell index and fraction of x on an ascending axis a[n], clamped (a NaN-free x). */
static void locate_arr(int n, const double *a, double x, int *i, double *f) {
    if (!(x > a[0])) { *i = 0; *f = 0.0; return; }
    if (!(x < a[n - 1])) { *i = n - 2; *f = 1.0; return; }
    int lo = 0, hi = n - 1;
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (a[mid] <= x) lo = mid; else hi = mid;
    }
    *i = lo;
    *f = (x - a[lo]) / (a[lo + 1] - a[lo]);
}

/* Cell index i (0..n-2) and fraction f of x on axis k, clamped to the axis. */
static void locate(const tf_table *t, int k, double x, int *i, double *f) {
    int n = t->n[k];
    const double *a = t->ax[k];
    if (!(x > a[0])) { *i = 0; *f = 0.0; return; }
    if (!(x < a[n - 1])) { *i = n - 2; *f = 1.0; return; }
    if (t->uni[k]) {
        double tt = (x - t->lo[k]) * t->inv[k];
        int j = (int)tt;
        if (j > n - 2) j = n - 2;
        *i = j;
        *f = tt - j;
        return;
    }
    locate_arr(n, a, x, i, f);
}

/* Bilinear (T, p) weights and offset of one query. */
typedef struct {
    int b;
    double w00, w01, w10, w11;
} tf_tp;

static void prep_tp(const tf_table *t, int iT, double fT, double p_rubber, tf_tp *q) {
    int ip;
    double fp;
    double lp = p_rubber > 0.0 ? log10(p_rubber) : -INFINITY;
    locate(t, 2, lp, &ip, &fp);
    q->b = (iT * t->n[2] + ip) * 3;
    q->w00 = (1.0 - fT) * (1.0 - fp);
    q->w01 = (1.0 - fT) * fp;
    q->w10 = fT * (1.0 - fp);
    q->w11 = fT * fp;
}

/* Branch values (mu_cold, mu_hot, dT_flash) at speed node j for a prepared query. */
static void node(const tf_table *t, const tf_tp *q, int j, double *out) {
    const double *v = t->val + (size_t)j * t->n[1] * t->n[2] * 3 + q->b;
    int o2 = t->n[2] * 3;
    for (int k = 0; k < 3; k++)
        out[k] = q->w00 * v[k] + q->w01 * v[3 + k] + q->w10 * v[o2 + k] + q->w11 * v[o2 + 3 + k];
}

/* A bound of the branch values at speed node j for a prepared query: the bilinear (T, p)
 * interpolation of arr (smax or pmin), which bounds the interpolated values of both branches
 * (and every blend of them) at the nodes >= j (smax) or <= j (pmin). */
static double node_bound(const tf_table *t, const double *arr, const tf_tp *q, int j) {
    const double *v = arr + (size_t)j * t->n[1] * t->n[2] + q->b / 3;
    int o2 = t->n[2];
    return q->w00 * v[0] + q->w01 * v[1] + q->w10 * v[o2] + q->w11 * v[o2 + 1];
}

/* Relative margin of the bounds of the node walk: a node skipped as "R < 0" (or "R >= 0")
 * has |R| > 1e-7, far above the rounding of its evaluation, so skipping never changes which
 * node the walk stops at. */
#define WALK_MARGIN 1e-6

/* ---------------------------------------------------------------- one stage ------------ */

/* Work of one outer step (docs/tire-core.md, "work budget"): the element sub-step attempts
 * (SDIRK steps, accepted or not, and event steps) it may still take, the stage solves and
 * the implicit Euler stages that finished elements once the budget was spent. */
typedef struct {
    double left, stages, fallbacks;
} tf_work;

/* Context of one outer step (constant over it). */
typedef struct {
    const tf_table *t;
    int iT;
    double fT;
    double kx, ky, dx, dy, m;
    double Vbx, Vby, Vr;
    double wpsi;               /* belt yaw rate: the base's lateral speed is Vby + x wpsi */
    double inv_void, mu_scale;
    double p_amp, c_flat, inv_ac;  /* p(x) = p_amp on |x| <= c_flat, then p_amp (1 - t^2),
                                      t = (|x| - c_flat) / (a - c_flat) */
    double tol_abs;            /* stress tolerance [Pa] */
    double zx, zy;             /* velocity-error weights sqrt(k m) + d [N s/m^3] */
    double D;                  /* contact-age length [m] (0: the friction read at |w|) */
    tf_work *w;                /* the outer step's work budget and counts (NULL: none) */
} tf_ctx;

/* The friction root problem of one stage (docs/tire-core.md, "stage solve"). */
typedef struct {
    const tf_table *t;
    tf_tp q;
    double Ax, Ay, Amin, Amax, gx, gy, G, pf, Zs, Hs, inv_s0;
    double D, th;                   /* contact age: D (0: off) and Z_theta + Hs > 0 */
    int iso, cell, jlo;             /* jlo: the highest speed node below reach (V_j <= 0) */
    double c0[3], c1[3], lvj, ispan;
    double P, E, dT;                /* of the last residual evaluation */
} tf_stg;

/* Speed node j of the table as the stage's slip speed V: v_j itself, or with the contact
 * age the V at which v_eff(V) = (D + Hs V) / th reaches v_j, V_j = (th v_j - D) / Hs
 * (monotone in v_j; V_j <= 0 is below reach). */
static double vn(const tf_stg *S, int j) {
    double v = S->t->vnode[j];
    return S->D > 0.0 ? (S->th * v - S->D) / S->Hs : v;
}

/* The largest node j in [lo, nv - 1] with vn(j) <= V (vn(lo) <= V, lo = -1 for none). */
static int cell_of(const tf_stg *S, int lo, double V) {
    int hi = S->t->n[0];
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (vn(S, mid) <= V) lo = mid; else hi = mid;
    }
    return lo;
}

static void set_cell(tf_stg *S, int j) {
    const tf_table *t = S->t;
    int nv = t->n[0];
    S->cell = j;
    if (j < 0 || j >= nv - 1) {
        node(t, &S->q, j < 0 ? 0 : nv - 1, S->c0);
        S->c1[0] = S->c1[1] = S->c1[2] = 0.0;
        S->lvj = 0.0;
        S->ispan = 0.0;
    } else {
        double n1[3];
        node(t, &S->q, j, S->c0);
        node(t, &S->q, j + 1, n1);
        for (int k = 0; k < 3; k++) S->c1[k] = n1[k] - S->c0[k];
        S->lvj = t->ax[0][j];
        S->ispan = t->ispan[j];
    }
}

/* Residual R(V) = 1 / |(A V + P(V))^-1 g| - 1 of the stage and its derivative; the friction
 * stress P = pf mu(V, s), the cold weight E = exp(-s/s0) at s = Zs + Hs V and the flash
 * temperature of the last evaluation are kept in S. */
static double resid(tf_stg *S, double V, double *dR) {
    double mc, mh, dT, dmc, dmh;
    if (S->ispan > 0.0) {
        /* with the contact age the table is read at v_eff = (D + Hs V) / th, whose slope
         * dv_eff/dV = Hs / th enters the derivative */
        double ve = S->D > 0.0 ? (S->D + S->Hs * V) / S->th : V;
        double tt = (log10(ve) - S->lvj) * S->ispan;
        double dl = S->ispan / (ve * LN10);
        if (S->D > 0.0) dl *= S->Hs / S->th;
        mc = S->c0[0] + S->c1[0] * tt;
        mh = S->c0[1] + S->c1[1] * tt;
        dT = S->c0[2] + S->c1[2] * tt;
        dmc = S->c1[0] * dl;
        dmh = S->c1[1] * dl;
    } else {
        mc = S->c0[0];
        mh = S->c0[1];
        dT = S->c0[2];
        dmc = 0.0;
        dmh = 0.0;
    }
    double E = S->inv_s0 > 0.0 ? cold_weight((S->Zs + S->Hs * V) * S->inv_s0) : 1.0;
    double dm = mc - mh;
    double P = S->pf * (mh + dm * E);
    double dP = S->pf * ((dmh + (dmc - dmh) * E) - dm * E * (S->Hs * S->inv_s0));
    double R, d;
    if (S->iso) {
        R = (S->Ax * V + P) / S->G - 1.0;
        d = (S->Ax + dP) / S->G;
    } else {
        double Dx = S->Ax * V + P, Dy = S->Ay * V + P;
        double rx = S->gx / Dx, ry = S->gy / Dy;
        double Q = rx * rx + ry * ry;
        double sq = sqrt(Q);
        R = 1.0 / sq - 1.0;
        d = (rx * rx * (S->Ax + dP) / Dx + ry * ry * (S->Ay + dP) / Dy) / (Q * sq);
    }
    S->P = P;
    S->E = E;
    S->dT = dT;
    *dR = d;
    return R;
}

/* Root of R in [lo, hi] (R(lo) < 0 <= R(hi)) by Newton's method from x (where R = r,
 * R' = d), safeguarded by bisection; returns the last point evaluated (S holds its P, E,
 * dT). */
static double solve_cell(tf_stg *S, double lo, double hi, double x, double r, double d) {
    for (int it = 0; it < 200; it++) {
        if (r == 0.0) return x;
        if (r < 0.0) lo = x; else hi = x;
        double xn = x - r / d;
        if (!(d > 0.0) || !(xn > lo && xn < hi)) xn = 0.5 * (lo + hi);
        if (fabs(xn - x) <= 1e-14 * xn || hi - lo <= 1e-15 * hi) return x;
        x = xn;
        r = resid(S, x, &d);
    }
    return x;
}

/* R at speed node j from the node's values alone (no interpolation; for the cell walk). */
static double node_resid(const tf_stg *S, int j) {
    const tf_table *t = S->t;
    const double *v = t->val + (size_t)j * t->n[1] * t->n[2] * 3 + S->q.b;
    int o2 = t->n[2] * 3;
    double n[2];
    for (int k = 0; k < 2; k++)
        n[k] = S->q.w00 * v[k] + S->q.w01 * v[3 + k] + S->q.w10 * v[o2 + k] +
               S->q.w11 * v[o2 + 3 + k];
    double V = vn(S, j);
    double E = S->inv_s0 > 0.0 ? cold_weight((S->Zs + S->Hs * V) * S->inv_s0) : 1.0;
    double P = S->pf * (n[1] + (n[0] - n[1]) * E);
    if (S->iso) return (S->Ax * V + P) / S->G - 1.0;
    double rx = S->gx / (S->Ax * V + P), ry = S->gy / (S->Ay * V + P);
    return 1.0 / sqrt(rx * rx + ry * ry) - 1.0;
}

typedef struct {
    double ux, uy, wx, wy, s, V, P, E, dT, fx, fy;   /* f: friction stress on the tip [Pa] */
    double th;                                       /* contact age [s] */
} tf_stage;

/* One implicit stage Y = Z + Hs F(Y) of an element at pressure p [Pa]: stick, or slide with
 * the root of R(V) = 0 followed from V_start in the direction of its sign (docs/tire-core.md,
 * "stage solve"). */
static void stage(const tf_ctx *c, double Hs, double p, double Vby, double Zux, double Zuy,
                  double Zwx, double Zwy, double Zs, double Zth, double V_start, tf_stage *o) {
    const tf_table *t = c->t;
    tf_stg S;
    double mdt = c->m / Hs;
    double kdx = c->kx * Hs + c->dx, kdy = c->ky * Hs + c->dy;
    S.t = t;
    S.Ax = mdt + kdx;
    S.Ay = mdt + kdy;
    S.gx = mdt * Zwx - c->kx * Zux + kdx * c->Vbx;
    S.gy = mdt * Zwy - c->ky * Zuy + kdy * Vby;
    S.G = norm2(S.gx, S.gy);
    S.pf = c->mu_scale * p;
    S.Zs = Zs;
    S.Hs = Hs;
    S.inv_s0 = t->inv_s0;
    S.iso = S.Ax == S.Ay;
    S.Amin = S.Ax < S.Ay ? S.Ax : S.Ay;
    S.Amax = S.Ax < S.Ay ? S.Ay : S.Ax;
    prep_tp(t, c->iT, c->fT, p * c->inv_void, &S.q);
    /* contact age (docs/tire-core.md, "contact age"): the stage's age is implicit,
     * theta = (Z_theta + Hs) / (1 + Hs V / D), and the friction is read at
     * v_eff = D / theta = (D + Hs V) / th, th = Z_theta + Hs (a second-stage extrapolation
     * below 0, a stiff relaxation step, counts as a fresh contact: Z_theta = 0) */
    S.D = c->D;
    S.th = Zth > 0.0 ? Zth + Hs : Hs;
    S.jlo = S.D > 0.0 ? cell_of(&S, -1, 0.0) : -1;
    set_cell(&S, S.jlo);
    /* the friction at rest: at v_eff(0) = D / th with the contact age, else at the first
     * node (without the age the cell is below the table, ispan = 0: its first node) */
    double E0 = S.inv_s0 > 0.0 ? cold_weight(Zs * S.inv_s0) : 1.0;
    double mc = S.c0[0], mh = S.c0[1], dT0 = S.c0[2];
    if (S.D > 0.0 && S.ispan > 0.0) {
        double tt = (log10(S.D / S.th) - S.lvj) * S.ispan;
        mc = S.c0[0] + S.c1[0] * tt;
        mh = S.c0[1] + S.c1[1] * tt;
        dT0 = S.c0[2] + S.c1[2] * tt;
    }
    double mu0 = mh + (mc - mh) * E0;
    S.dT = dT0;
    if (S.G <= mu0 * S.pf) {                  /* the tip sticks */
        o->V = 0.0;
        o->wx = 0.0;
        o->wy = 0.0;
        o->ux = Zux - Hs * c->Vbx;
        o->uy = Zuy - Hs * Vby;
        o->s = Zs;
        o->P = 0.0;
        o->E = E0;
        o->dT = S.dT;
        o->fx = -S.gx;
        o->fy = -S.gy;
        o->th = S.D > 0.0 ? S.th : Zth;
        return;
    }
    double V_hi = S.G / (S.Ax < S.Ay ? S.Ax : S.Ay);
    double Vs = V_start < V_hi ? V_start : V_hi;
    int nv = t->n[0];
    if (S.D > 0.0) {                          /* the cells in V of the mapped nodes */
        if (!(Vs > 0.0)) {
            double v1 = S.jlo + 1 <= nv - 1 ? vn(&S, S.jlo + 1) : V_hi;
            Vs = 0.5 * v1 < V_hi ? 0.5 * v1 : 0.5 * V_hi;
        }
        int j = cell_of(&S, S.jlo, Vs);
        if (j != S.cell) set_cell(&S, j);
    } else if (!(Vs > t->vnode[0])) {
        if (!(Vs > 0.0)) Vs = 0.5 * t->vnode[0] < V_hi ? 0.5 * t->vnode[0] : 0.5 * V_hi;
    } else if (Vs >= t->vnode[nv - 1]) {
        set_cell(&S, nv - 1);
    } else {
        int j;
        double f;
        locate(t, 0, log10(Vs), &j, &f);
        if (Vs < t->vnode[j]) j -= 1;             /* rounding of log10 */
        else if (Vs >= t->vnode[j + 1]) j += 1;
        set_cell(&S, j);
    }
    double d, r = resid(&S, Vs, &d);
    double V;
    if (r < 0.0) {                            /* accelerating: the first root above */
        double lo = Vs;
        for (;;) {
            int last = 0;
            double ub = S.cell < nv - 1 ? vn(&S, S.cell + 1) : V_hi;
            if (ub >= V_hi) { ub = V_hi; last = 1; }
            int found = 0;
            for (int k = 0; k < 50 && d > 0.0; k++) {     /* Newton from below */
                double x = lo - r / d;
                if (!(x < ub)) break;
                double dx_, rx_ = resid(&S, x, &dx_);
                if (rx_ >= 0.0) { V = solve_cell(&S, lo, x, x, rx_, dx_); found = 1; break; }
                int tiny = x - lo <= 1e-14 * x;
                lo = x; r = rx_; d = dx_;
                if (tiny) { V = x; found = 1; break; }
            }
            if (found) break;
            if (last) {
                double d_ub, r_ub = resid(&S, ub, &d_ub);
                V = r_ub >= 0.0 ? solve_cell(&S, lo, ub, ub, r_ub, d_ub) : V_hi;
                break;
            }
            /* walk the nodes above from their values alone (R is continuous across a
             * node) up to the first where R >= 0, or to the cell that holds V_hi */
            int j = S.cell + 1;
            double rj;
            for (;;) {
                /* nodes below (G - P_max) / A_max have R < 0 whatever the friction there:
                 * skipped without evaluating them (the walk stops where it would anyway) */
                if (t->smax) {
                    double Pm = S.pf * node_bound(t, t->smax, &S.q, j);
                    double Vb = (S.G * (1.0 - WALK_MARGIN) - Pm) / S.Amax;
                    if (vn(&S, j) < Vb) {  /* the bound holds at every node above j too */
                        int stop = 0;
                        do {
                            if (!(j + 1 <= nv - 1 && vn(&S, j + 1) < V_hi)) { stop = 1; break; }
                            j += 1;
                        } while (vn(&S, j) < Vb);
                        rj = -1.0;
                        if (stop) break;
                        continue;
                    }
                }
                rj = node_resid(&S, j);
                if (!(rj < 0.0 && j + 1 <= nv - 1 && vn(&S, j + 1) < V_hi)) break;
                j += 1;
            }
            if (rj >= 0.0) {                  /* the root is in [vnode[j-1], vnode[j]] */
                if (j - 1 != S.cell) {
                    set_cell(&S, j - 1);
                    lo = vn(&S, j - 1);
                }
                double d_, r_ = resid(&S, vn(&S, j), &d_);
                V = solve_cell(&S, lo, vn(&S, j), vn(&S, j), r_, d_);
                break;
            }
            set_cell(&S, j);                  /* R < 0 up to node j: go on in cell j */
            lo = vn(&S, j);
            r = resid(&S, lo, &d);
        }
    } else if (r > 0.0) {                     /* decelerating: the first root below */
        double hi = Vs;
        for (;;) {
            double lb = S.cell <= S.jlo ? 0.0 : vn(&S, S.cell);
            int found = 0;
            for (int k = 0; k < 50 && d > 0.0; k++) {     /* Newton from above */
                double x = hi - r / d;
                if (!(x > lb)) break;
                double dx_, rx_ = resid(&S, x, &dx_);
                if (rx_ < 0.0) { V = solve_cell(&S, x, hi, x, rx_, dx_); found = 1; break; }
                int tiny = hi - x <= 1e-14 * hi;
                hi = x; r = rx_; d = dx_;
                if (tiny) { V = x; found = 1; break; }
            }
            if (found) break;
            if (S.cell <= S.jlo) {             /* R(0) < 0: the stick test failed */
                V = solve_cell(&S, 0.0, hi, hi, r, d);
                break;
            }
            /* walk the nodes below from their values alone down to the first where R < 0
             * (R(0) < 0: the stick test failed) */
            int j = S.cell;
            double rj;
            for (;;) {
                /* nodes above (G - P_min) / A_min have R >= 0 whatever the friction there */
                if (t->pmin) {
                    double Pn = S.pf * node_bound(t, t->pmin, &S.q, j);
                    double Vd = (S.G * (1.0 + WALK_MARGIN) - Pn) / S.Amin;
                    if (vn(&S, j) >= Vd) {  /* the bound holds at every node below j too */
                        int stop = 0;
                        do {
                            if (!(j > S.jlo + 1)) { stop = 1; break; }
                            j -= 1;
                        } while (vn(&S, j) >= Vd);
                        rj = 1.0;
                        if (stop) break;
                        continue;
                    }
                }
                rj = node_resid(&S, j);
                if (!(rj >= 0.0 && j > S.jlo + 1)) break;
                j -= 1;
            }
            if (rj < 0.0) {                   /* the root is in [vnode[j], vnode[j+1]] */
                if (j != S.cell) {
                    set_cell(&S, j);
                    hi = vn(&S, j + 1);
                }
                double d_, r_ = resid(&S, vn(&S, j), &d_);
                V = solve_cell(&S, vn(&S, j), hi, vn(&S, j), r_, d_);
                break;
            }
            set_cell(&S, S.jlo);              /* R >= 0 down to the first node in reach */
            hi = vn(&S, S.jlo + 1);
            r = resid(&S, hi, &d);
        }
    } else {
        V = Vs;
    }
    double P = S.P;
    double Dx = S.Ax * V + P, Dy = S.Ay * V + P;
    o->V = V;
    o->wx = S.gx * V / Dx;
    o->wy = S.gy * V / Dy;
    o->ux = Zux + Hs * (o->wx - c->Vbx);
    o->uy = Zuy + Hs * (o->wy - Vby);
    o->s = Zs + Hs * V;
    if (o->s > S_MAX) o->s = S_MAX;
    o->th = S.D > 0.0 ? S.th / (1.0 + Hs * V / S.D) : Zth;
    o->P = P;
    o->E = S.E;
    o->dT = S.dT;
    o->fx = S.Ax * o->wx - S.gx;
    o->fy = S.Ay * o->wy - S.gy;
}

static double shape(double c_flat, double inv_ac, double x) {
    double ax = fabs(x);
    if (ax <= c_flat) return 1.0;
    double t = (ax - c_flat) * inv_ac;
    double w = 1.0 - t * t;
    return w > 0.0 ? w : 0.0;
}

static double pressure(const tf_ctx *c, double x) {
    return c->p_amp * shape(c->c_flat, c->inv_ac, x);
}

/* What an element's integration over one outer step leaves besides its state. */
typedef struct {
    double energy;    /* friction work per unit area [J/m^2] */
    double Jx, Jy, Jm;  /* impulse of the friction per unit area [N s/m^2] and its moment
                           about the patch centre [N s/m] */
    double Jt;          /* moment of the impulse of the tread's lateral stress on the belt
                           about the patch centre [N s/m] */
    double V, P, E, dT, p, fx, fy;
    double steps;
} tf_eres;

/* Integrate one element e[TF_ELEM] over its contact time h_e [s], ending at position x_end
 * [m] (docs/tire-core.md, "element integration"): SDIRK2 sub-steps with an embedded
 * first-order error estimate and step-size control. */
static void integrate(const tf_ctx *c, double *e, double x_end, double h_e, tf_eres *r) {
    double ux = e[0], uy = e[1], wx = e[2], wy = e[3], s = e[4], th = e[7];
    double Hn = e[5];
    if (!(Hn > 0.0) || Hn > h_e) Hn = h_e;
    double t = 0.0;
    double energy = 0.0, steps = 0.0, Jx = 0.0, Jy = 0.0, Jm = 0.0, Jt = 0.0;
    double g1 = (1.0 - GAMMA) / GAMMA, ig = 1.0 / GAMMA;
    tf_stage o1, o2;
    o2.V = norm2(wx, wy);
    o2.P = 0.0;
    o2.E = c->t->inv_s0 > 0.0 ? cold_weight(s * c->t->inv_s0) : 1.0;
    o2.dT = 0.0;
    o2.fx = 0.0;
    o2.fy = 0.0;
    double p2 = pressure(c, x_end);
    while (h_e - t > 1e-12 * h_e) {
        double rest = h_e - t;
        int cut = Hn >= rest;
        double H = cut ? rest : Hn;
        if (c->w && !(c->w->left > 0.0)) {
            /* the outer step's budget is spent: the rest of the element's time in one
             * implicit Euler stage (L-stable: it lands on the stuck or sliding equilibrium
             * of the end of the step, whatever its length) */
            double pe = pressure(c, x_end);
            double vbe = c->Vby + x_end * c->wpsi;
            stage(c, rest, pe, vbe, ux, uy, wx, wy, s, th, norm2(wx, wy), &o2);
            ux = o2.ux; uy = o2.uy; wx = o2.wx; wy = o2.wy; s = o2.s; th = o2.th;
            energy += rest * (o2.P * o2.V);
            Jx += rest * o2.fx;
            Jy += rest * o2.fy;
            Jm += rest * (x_end * o2.fy);
            Jt += rest * (x_end * (c->ky * o2.uy + c->dy * (o2.wy - vbe)));
            steps += 1.0;
            c->w->stages += 1.0;
            c->w->fallbacks += 1.0;
            p2 = pe;
            break;
        }
        if (c->w) c->w->left -= 1.0;
        if (H <= H_MIN) {
            /* event step: at the smallest step a stick-slip event (a snap, instantaneous for
             * a massless tip) is taken with one implicit Euler stage, which lands on the new
             * equilibrium; the SDIRK extrapolation would overshoot it */
            double xe = x_end + c->Vr * (rest - H);
            double pe = pressure(c, xe);
            double vbe = c->Vby + xe * c->wpsi;
            stage(c, H, pe, vbe, ux, uy, wx, wy, s, th, norm2(wx, wy), &o2);
            if (c->w) c->w->stages += 1.0;
            ux = o2.ux; uy = o2.uy; wx = o2.wx; wy = o2.wy; s = o2.s; th = o2.th;
            energy += H * (o2.P * o2.V);
            Jx += H * o2.fx;
            Jy += H * o2.fy;
            Jm += H * (xe * o2.fy);
            Jt += H * (xe * (c->ky * o2.uy + c->dy * (o2.wy - vbe)));
            steps += 1.0;
            p2 = pe;
            t += H;
            Hn = cut ? Hn : 4.0 * H;
            continue;
        }
        double Hs = GAMMA * H;
        double x1 = x_end + c->Vr * (rest - Hs);
        double p1 = pressure(c, x1);
        double vb1 = c->Vby + x1 * c->wpsi;
        stage(c, Hs, p1, vb1, ux, uy, wx, wy, s, th, norm2(wx, wy), &o1);
        double Zux = ux + g1 * (o1.ux - ux), Zuy = uy + g1 * (o1.uy - uy);
        double Zwx = wx + g1 * (o1.wx - wx), Zwy = wy + g1 * (o1.wy - wy);
        double Zs = s + g1 * (o1.s - s);
        double Zth = th + g1 * (o1.th - th);
        double xe = x_end + c->Vr * (rest - H);
        double pe = pressure(c, xe);
        double vbe = c->Vby + xe * c->wpsi;
        stage(c, Hs, pe, vbe, Zux, Zuy, Zwx, Zwy, Zs, Zth, o1.V, &o2);
        if (c->w) c->w->stages += 2.0;
        double ex = fabs(o2.ux - (ux + (o1.ux - ux) * ig)) * c->kx;
        double ey = fabs(o2.uy - (uy + (o1.uy - uy) * ig)) * c->ky;
        double evx = fabs(o2.wx - (wx + (o1.wx - wx) * ig)) * c->zx;
        double evy = fabs(o2.wy - (wy + (o1.wy - wy) * ig)) * c->zy;
        double err = ex;
        if (ey > err) err = ey;
        if (evx > err) err = evx;
        if (evy > err) err = evy;
        if (c->D > 0.0) {
            /* the age's error as a friction stress: a relative error e of theta moves v_eff
             * by the factor 1 + e, and the friction by mu_scale p e |dmu / dln v|, taken
             * with |dmu / dln v| <= 1 (the grids change by less than 1 per e-fold); e is
             * relative to the step's end age (what the friction reads) and filtered by the
             * age's own implicit factor 1 / (1 + Hs V / D) (Hairer and Wanner, sec. IV.8:
             * a fresh contact relaxing to D / V within the step is then accepted, a step
             * whose first stage read a stale age is not) */
            double the = th + (o1.th - th) * ig;
            double eth = fabs(o2.th - the) / (1.0 + Hs * o2.V / c->D) / o2.th *
                         (c->mu_scale * pe);
            /* the friction is constant beyond the table's speed axis: between two ages that
             * both read there (the embedded age <= 0 reads v_eff = inf) it moves nothing */
            double vlo = c->t->vnode[0], vhi = c->t->vnode[c->t->n[0] - 1];
            if ((c->D >= vhi * o2.th && c->D >= vhi * the) ||
                (c->D <= vlo * o2.th && c->D <= vlo * the))
                eth = 0.0;
            if (eth > err) err = eth;
        }
        err /= c->tol_abs;
        double fac = err > 0.0 ? 0.9 / sqrt(err) : 4.0;
        if (fac > 4.0) fac = 4.0;
        if (fac < 0.2) fac = 0.2;
        if (err <= 1.0) {
            ux = o2.ux; uy = o2.uy; wx = o2.wx; wy = o2.wy; s = o2.s; th = o2.th;
            energy += H * ((1.0 - GAMMA) * o1.P * o1.V + GAMMA * o2.P * o2.V);
            Jx += H * ((1.0 - GAMMA) * o1.fx + GAMMA * o2.fx);
            Jy += H * ((1.0 - GAMMA) * o1.fy + GAMMA * o2.fy);
            Jm += H * ((1.0 - GAMMA) * (x1 * o1.fy) + GAMMA * (xe * o2.fy));
            Jt += H * ((1.0 - GAMMA) * (x1 * (c->ky * o1.uy + c->dy * (o1.wy - vb1))) +
                       GAMMA * (xe * (c->ky * o2.uy + c->dy * (o2.wy - vbe))));
            steps += 1.0;
            p2 = pe;
            t += H;
            double Hf = H * fac;
            Hn = cut ? (Hf > Hn ? Hf : Hn) : Hf;
        } else {
            Hn = H * fac;
            if (Hn < H_MIN) Hn = H_MIN;
        }
    }
    e[0] = ux; e[1] = uy; e[2] = wx; e[3] = wy; e[4] = s; e[5] = Hn; e[7] = th;
    r->energy = energy;
    r->Jx = Jx;
    r->Jy = Jy;
    r->Jm = Jm;
    r->Jt = Jt;
    r->V = o2.V;
    r->P = o2.P;
    r->E = o2.E;
    r->dT = o2.dT;
    r->p = p2;
    r->fx = o2.fx;
    r->fy = o2.fy;
    r->steps = steps;
}

/* ---------------------------------------------------------------- patch ---------------- */

/* Vertical stiffness at the inflation pressure (MF 6.2; Pacejka 2012, sec. 4.3.2). */
static double vertical_stiffness(const tf_params *p) {
    return p->C_z * (1.0 + p->p_fz1 * ((p->p_inflation - p->p_nom) / p->p_nom));
}

static void patch_size(const tf_params *p, double Fz, double *a, double *b) {
    if (!(Fz > 0.0)) { *a = 0.0; *b = 0.0; return; }
    double r = (Fz < p->Fz_max ? Fz : p->Fz_max) / (vertical_stiffness(p) * p->R0);
    *a = p->R0 * (p->q_ra2 * r + p->q_ra1 * sqrt(r));
    *b = 2.0 * p->width * (p->q_rb2 * r + p->q_rb1 * cbrt(r));
}

/* Half-length of the flat centre of the pressure distribution (docs/tire-core.md, "pressure
 * along the patch"): the flat part carries the inflation pressure; its share of the
 * half-length follows from the load, f = 3 Fz / (2 a b p_inflation) - 2, between 0 (the
 * parabola) and 1 - end_zone. */
static double flat_half_length(const tf_params *p, double Fz, double a, double b) {
    double f = 3.0 * (Fz / (2.0 * a * b * p->p_inflation)) - 2.0;
    if (!(f > 0.0)) f = 0.0;
    if (f > 1.0 - p->end_zone) f = 1.0 - p->end_zone;
    return f * a;
}

/* The pressure amplitude p_amp is such that the element pressures at the sample positions
 * (lattice or cell midpoints) add up to Fz exactly: full sliding then gives mu Fz. */
static void ctx_init(tf_ctx *c, const tf_params *p, const tf_table *t, double T, double Fz,
                     double a, double b, double c_flat, double p_amp, double mu_scale,
                     double Vbx, double Vby, double Vr) {
    c->t = t;
    locate(t, 1, T, &c->iT, &c->fT);
    c->kx = p->k_x;
    c->ky = p->k_y;
    c->dx = p->d_x;
    c->dy = p->d_y;
    c->m = p->mass;
    c->Vbx = Vbx;
    c->Vby = Vby;
    c->wpsi = 0.0;
    c->Vr = Vr;
    c->inv_void = 1.0 / (1.0 - p->void_ratio);
    c->mu_scale = mu_scale;
    c->p_amp = p_amp;
    c->c_flat = c_flat;
    c->inv_ac = 1.0 / (a - c_flat);
    c->tol_abs = p->tol * (0.5 * Fz / (a * b));
    c->zx = sqrt(p->k_x * p->mass) + p->d_x;
    c->zy = sqrt(p->k_y * p->mass) + p->d_y;
    c->D = p->contact_ageing && t->inv_s0 > 0.0 ? AGE_D_PER_S0 / t->inv_s0 : 0.0;
    c->w = NULL;
}

static int params_ok(const tf_params *p) {
    const double pos[] = {p->R_e, p->Fz_nom, p->R0, p->width, p->C_z, p->q_ra1, p->q_rb1,
                          p->Fz_max, p->k_x, p->k_y, p->dt_internal, p->tol, p->v_floor,
                          p->kc_x, p->kc_y, p->heat_capacity, p->p_inflation, p->p_nom,
                          p->end_zone, p->kc_psi};
    const double nonneg[] = {p->mass, p->d_x, p->d_y, p->void_ratio, p->dc_x, p->dc_y,
                             p->conductance, p->heat_fraction, p->p_fz1, p->dc_psi};
    for (size_t i = 0; i < sizeof pos / sizeof pos[0]; i++)
        if (!(isfinite(pos[i]) && pos[i] > 0.0)) return 0;
    for (size_t i = 0; i < sizeof nonneg / sizeof nonneg[0]; i++)
        if (!(isfinite(nonneg[i]) && nonneg[i] >= 0.0)) return 0;
    if (!isfinite(p->q_ra2) || !isfinite(p->q_rb2) || !(p->void_ratio < 0.95)) return 0;
    if (!(p->end_zone <= 1.0) || !(vertical_stiffness(p) > 0.0)) return 0;
    if (!(p->camber_reduction >= 0.0 && p->camber_reduction <= 1.0)) return 0;
    if (p->n_elements < 2) return 0;
    if (p->contact_ageing != 0 && p->contact_ageing != 1) return 0;
    return 1;
}

/* ---------------------------------------------------------------- steady --------------- */

/* One steady point with the belt at rest on the rim and yawed by psi = 0 (the march of
 * docs/tire-core.md, "steady model"), its base spinning at wc (camber, for the march's
 * direction of travel): the element is followed to the trailing edge; the
 * forces are the impulse of its friction over the transit time times b V_r (the patch
 * integral, no sampling); the diagnostics are read at the n_cells cell midpoints. */
static double steady_march(const tf_params *p, const tf_table *t, int n_cells, double Vsx,
                           double Vsy, double Vr, double Fz, double a, double b, double T,
                           double mu_scale, double wc, double *o) {
    double sgn = Vr < 0.0 ? -1.0 : 1.0;
    double vr = fabs(Vr) > V_ROLL_MIN ? fabs(Vr) : V_ROLL_MIN;
    double cf = flat_half_length(p, Fz, a, b);
    double mean = (cf + (2.0 / 3.0) * (a - cf)) / a;
    tf_ctx c;
    ctx_init(&c, p, t, T, Fz, a, b, cf, Fz / (2.0 * a * b * mean), mu_scale, Vsx, Vsy, vr);
    c.wpsi = wc;
    double e[TF_ELEM] = {0.0, 0.0, Vsx, Vsy + a * wc, 0.0, 0.0, 1.0, 0.0};
    double Jx = 0.0, Jy = 0.0, Jm = 0.0, Jt = 0.0, nsl = 0.0, fsl = 0.0, psl = 0.0, dTm = 0.0;
    double steps = 0.0, x_prev = a, work = 0.0;
    for (int j = 0; j <= n_cells; j++) {
        double x = j < n_cells ? a * (1.0 - (2.0 * j + 1.0) / n_cells) : -a;
        tf_eres r;
        integrate(&c, e, x, (x_prev - x) / vr, &r);
        x_prev = x;
        steps += r.steps;
        Jx += r.Jx;
        Jy += r.Jy;
        Jm += r.Jm;
        Jt += r.Jt;
        work += r.energy;
        if (j < n_cells && r.V > CREEP_SPEED) {
            nsl += 1.0;
            fsl += r.P;
            psl += r.p;
            double dT = r.dT * (1.0 - r.E);
            if (dT > dTm) dTm = dT;
        }
    }
    double Fx = Jx * b * vr, Fy = Jy * b * vr;
    o[0] = Fx;
    o[1] = Fy;
    o[2] = Jm * b * vr * sgn;
    o[3] = Fz > 0.0 ? norm2(Fx, Fy) / Fz : 0.0;
    o[4] = psl > 0.0 ? fsl / psl : 0.0;
    o[5] = nsl / n_cells;
    o[6] = dTm;
    o[7] = steps;
    o[8] = work * b * vr;
    /* the moment of the tread's stress on the belt, which yaws it: the friction moment Mz
     * less the moment of the momentum the tread carries through the patch */
    o[9] = Jt * b * vr * sgn;
    return o[9];
}

/* Largest number of marches of the belt-yaw iteration of one steady point. */
#define YAW_MAX_IT 60

int tf_steady(const tf_params *p, const tf_table *t, int n_cells, int n, const double *in,
              double T, double mu_scale, double *out) {
    if (!p || !t || !params_ok(p) || n_cells < 2 || n < 0 || !(T > 0.0) || !isfinite(T) ||
        !(mu_scale >= 0.0) || !isfinite(mu_scale))
        return -1;
    for (int i = 0; i < n * TF_STEADY_IN; i++)
        if (!isfinite(in[i])) return -1;
    for (int i = 0; i < n; i++) {
        const double *q = in + (size_t)i * TF_STEADY_IN;
        double *o = out + (size_t)i * TF_STEADY_OUT;
        double Vsx = q[0], Vsy = q[1], Vr = q[2], Fz = q[3], gam = q[4];
        if (!(fabs(gam) < HALF_PI)) return -1;
        /* the march runs forward; for V_r < 0 it is the mirror image, in which the spin of
         * the base is that of forward rolling */
        double wc = -(1.0 - p->camber_reduction) * (fabs(Vr) / p->R_e) * sin(gam);
        double a, b;
        patch_size(p, Fz, &a, &b);
        for (int k = 0; k < TF_STEADY_OUT; k++) o[k] = 0.0;
        if (!(a > 0.0 && b > 0.0)) continue;
        double Mb = steady_march(p, t, n_cells, Vsx, Vsy, Vr, Fz, a, b, T, mu_scale, wc, o);
        if (p->rigid || Mb == 0.0) continue;
        /* belt yaw psi = M_belt / kc_psi, which turns the base's lateral slip speed into
         * Vsy - V_r psi (docs/tire-core.md, "belt"): the root of g(psi) = M_belt(psi) /
         * kc_psi - psi, bracketed between 0 (g > 0 or < 0) and where the sign changes,
         * found by the Illinois variant of regula falsi */
        double steps = o[7];
        double lo = 0.0, glo = Mb / p->kc_psi;
        double hi = glo, ghi;
        double oh[TF_STEADY_OUT];
        int it = 0;
        for (;;) {
            double Mh = steady_march(p, t, n_cells, Vsx, Vsy - Vr * hi, Vr, Fz, a, b, T,
                                     mu_scale, wc, oh);
            steps += oh[7];
            it++;
            ghi = Mh / p->kc_psi - hi;
            if (ghi == 0.0 || (ghi > 0.0) != (glo > 0.0) || it >= YAW_MAX_IT) break;
            lo = hi;
            glo = ghi;
            hi = 2.0 * hi;
        }
        memcpy(o, oh, sizeof oh);
        while (ghi != 0.0 && it < YAW_MAX_IT && fabs(hi - lo) > 1e-12 + 1e-9 * fabs(hi)) {
            double x = hi - ghi * (hi - lo) / (ghi - glo);
            double ox[TF_STEADY_OUT];
            double Mx = steady_march(p, t, n_cells, Vsx, Vsy - Vr * x, Vr, Fz, a, b, T,
                                     mu_scale, wc, ox);
            steps += ox[7];
            it++;
            double gx = Mx / p->kc_psi - x;
            memcpy(o, ox, sizeof ox);
            if (gx == 0.0) break;
            if ((gx > 0.0) != (ghi > 0.0)) {    /* the root lies between x and hi */
                lo = hi;
                glo = ghi;
            } else {                            /* Illinois: halve the kept end's value */
                glo *= 0.5;
            }
            hi = x;
            ghi = gx;
        }
        o[7] = steps;
    }
    return 0;
}

/* ---------------------------------------------------------------- transient ------------ */

#define STATE_HEAD 27   /* version, L, x_top, delta[2], Vb[2], F[2], T_tread, time, out[12],
                          psi, wpsi, M, wc */

tf_tire *tf_tire_new(const tf_params *p, const tf_table *t) {
    if (!p || !t || !params_ok(p) || !(p->Fz_nom <= p->Fz_max)) return NULL;
    tf_tire *tire = calloc(1, sizeof *tire);
    if (!tire) return NULL;
    tire->p = *p;
    tire->t = t;
    double a_nom, b_nom, b_max;
    patch_size(p, p->Fz_nom, &a_nom, &b_nom);
    patch_size(p, p->Fz_max, &tire->a_max, &b_max);
    if (!(a_nom > 0.0) || !(tire->a_max >= a_nom)) { free(tire); return NULL; }
    tire->dx = 2.0 * a_nom / p->n_elements;
    tire->L = (int)ceil(2.0 * tire->a_max / tire->dx) + 2;
    tire->el = calloc((size_t)tire->L * TF_ELEM, sizeof(double));
    if (!tire->el) { free(tire); return NULL; }
    tf_tire_reset(tire, NAN);
    return tire;
}

void tf_tire_free(tf_tire *tire) {
    if (!tire) return;
    free(tire->scratch.val);
    free(tire->scratch.smax);
    free(tire->scratch.pmin);
    free(tire->el);
    free(tire);
}

void tf_tire_reset(tf_tire *tire, double T_tread) {
    memset(tire->el, 0, sizeof(double) * (size_t)tire->L * TF_ELEM);
    tire->x_top = tire->a_max;
    tire->delta[0] = tire->delta[1] = 0.0;
    tire->Vb[0] = tire->Vb[1] = 0.0;
    tire->F[0] = tire->F[1] = 0.0;
    tire->psi = tire->wpsi = tire->M = tire->wc = 0.0;
    tire->T_tread = T_tread;
    tire->time = 0.0;
    tire->flags = 0;
    for (int k = 0; k < TF_NOUT; k++) tire->out[k] = 0.0;
}

int tf_tire_set_rolling(tf_tire *tire, const tf_table *rr) {
    if (!tire) return -1;
    tire->rr = rr;
    return 0;
}

int tf_tire_set_patch(tf_tire *tire, const tf_patch *pt) {
    if (!tire) return -1;
    tire->patch = pt;
    return 0;
}

int tf_tire_set_wet(tf_tire *tire, const tf_wet *w, double texture_depth) {
    if (!tire || !(isfinite(texture_depth) && texture_depth >= 0.0)) return -1;
    if (w && (w->n[0] != tire->t->n[0] || w->n[1] != tire->t->n[1] || w->n[2] != tire->t->n[2]))
        return -1;
    tire->wet = NULL;
    tire->wvalid = 0;
    if (!w) return 0;
    const tf_table *t = tire->t;
    size_t nn = (size_t)t->n[0] * t->n[1] * t->n[2];
    if (!tire->scratch.val) {
        tf_table s = *t;
        s.val = malloc(sizeof(double) * nn * 3);
        s.smax = malloc(sizeof(double) * nn);
        s.pmin = malloc(sizeof(double) * nn);
        if (!s.val || !s.smax || !s.pmin) {
            free(s.val);
            free(s.smax);
            free(s.pmin);
            return -1;
        }
        memcpy(s.val, t->val, sizeof(double) * nn * 3);
        tire->scratch = s;
    }
    tire->wet = w;
    tire->texture_depth = texture_depth;
    return 0;
}

/* The friction table of one outer step: the dry table, or on water of depth d > 0 the wet
 * branch at d and drainage time t_drain [s] (log10 lt), filled in for the temperature rows
 * the step reads (those of the background temperature T0) and kept while d, lt and the rows
 * stay the same. */
static const tf_table *step_table(tf_tire *tire, double T0, double d, double lt) {
    const tf_wet *w = tire->wet;
    const tf_table *t = tire->t;
    if (!w || !(d > 0.0)) return t;
    int iT;
    double fT;
    locate(t, 1, T0, &iT, &fT);
    if (tire->wvalid && tire->wkey[0] == d && tire->wkey[1] == lt && tire->wkey[2] == iT)
        return &tire->scratch;
    int id, it;
    double fd, ft;
    locate_arr(w->nd, w->depth, d, &id, &fd);
    locate_arr(w->nt, w->log10_t, lt, &it, &ft);
    int nv = t->n[0], nT = t->n[1], np = t->n[2];
    size_t nn = (size_t)nv * nT * np;
    const double *w00 = w->w + ((size_t)id * w->nt + it) * nn;
    const double *w01 = w00 + nn, *w10 = w00 + (size_t)w->nt * nn, *w11 = w10 + nn;
    const double *m0 = w->mu + (size_t)id * nn * 4, *m1 = m0 + nn * 4;
    for (int j = 0; j < nv; j++) {
        for (int r = iT; r <= iT + 1; r++) {
            for (int q = 0; q < np; q++) {
                size_t node = ((size_t)j * nT + r) * np + q;
                double ws = (1.0 - fd) * ((1.0 - ft) * w00[node] + ft * w01[node]) +
                            fd * ((1.0 - ft) * w10[node] + ft * w11[node]);
                if (!(ws > 0.0)) ws = 0.0;
                if (ws > 1.0) ws = 1.0;
                const double *a0 = m0 + node * 4, *a1 = m1 + node * 4;
                double c0 = (1.0 - fd) * a0[0] + fd * a1[0];
                double c1 = (1.0 - fd) * a0[1] + fd * a1[1];
                double h0 = (1.0 - fd) * a0[2] + fd * a1[2];
                double h1 = (1.0 - fd) * a0[3] + fd * a1[3];
                double *v = tire->scratch.val + node * 3;
                v[0] = (1.0 - ws) * c0 + ws * c1;
                v[1] = (1.0 - ws) * h0 + ws * h1;
            }
        }
    }
    table_bounds(&tire->scratch, (size_t)iT * np, (size_t)(iT + 2) * np);
    tire->wkey[0] = d;
    tire->wkey[1] = lt;
    tire->wkey[2] = iT;
    tire->wvalid = 1;
    return &tire->scratch;
}

int tf_tire_lattice(const tf_tire *tire) { return tire->L; }

int tf_tire_state_size(const tf_tire *tire) { return STATE_HEAD + TF_ELEM * tire->L; }

double tf_tire_work(const tf_tire *tire) { return tire->work; }

void tf_tire_counters(const tf_tire *tire, double *out) {
    out[0] = tire->work;
    out[1] = tire->stages;
    out[2] = tire->fallbacks;
}

int tf_tire_flags(const tf_tire *tire) { return tire->flags; }

void tf_tire_get_state(const tf_tire *tire, double *buf) {
    buf[0] = TF_VERSION;
    buf[1] = tire->L;
    buf[2] = tire->x_top;
    buf[3] = tire->delta[0];
    buf[4] = tire->delta[1];
    buf[5] = tire->Vb[0];
    buf[6] = tire->Vb[1];
    buf[7] = tire->F[0];
    buf[8] = tire->F[1];
    buf[9] = tire->T_tread;
    buf[10] = tire->time;
    memcpy(buf + 11, tire->out, sizeof(double) * TF_NOUT);
    buf[23] = tire->psi;
    buf[24] = tire->wpsi;
    buf[25] = tire->M;
    buf[26] = tire->wc;
    memcpy(buf + STATE_HEAD, tire->el, sizeof(double) * (size_t)tire->L * TF_ELEM);
}

int tf_tire_set_state(tf_tire *tire, const double *buf) {
    if (buf[0] != TF_VERSION || buf[1] != tire->L) return -1;
    for (int i = 2; i < STATE_HEAD + TF_ELEM * tire->L; i++)
        if (i != 9 && !isfinite(buf[i])) return -1;   /* T_tread may be NaN (not yet set) */
    for (int i = 0; i < tire->L; i++)                 /* contact ages are >= 0 */
        if (!(buf[STATE_HEAD + i * TF_ELEM + 7] >= 0.0)) return -1;
    tire->x_top = buf[2];
    tire->delta[0] = buf[3];
    tire->delta[1] = buf[4];
    tire->Vb[0] = buf[5];
    tire->Vb[1] = buf[6];
    tire->F[0] = buf[7];
    tire->F[1] = buf[8];
    tire->T_tread = buf[9];
    tire->time = buf[10];
    memcpy(tire->out, buf + 11, sizeof(double) * TF_NOUT);
    tire->psi = buf[23];
    tire->wpsi = buf[24];
    tire->M = buf[25];
    tire->wc = buf[26];
    memcpy(tire->el, buf + STATE_HEAD, sizeof(double) * (size_t)tire->L * TF_ELEM);
    return 0;
}

/* Stiffness [N s/m^3] of one element against its base over an outer step h: the stress it
 * puts on the belt at the end of the step, per unit step of the base velocity at its start,
 * for the element linearised with the secant friction stiffness c = p mu / |w| >= 0 (tip
 * mass m, spring k, damper d; docs/tire-core.md, "belt"). The linearised element is
 *     y'' + 2 q y' + w^2 y = 0,  q = (c + d) / 2m,  w^2 = k / m,  y(0) = c / k,  y'(0) = -1
 * (y the deflection change plus c / k, y' the relative velocity of tip and base), and the
 * stiffness is J = c - k y(h) - d y'(h): closed forms for the under- and overdamped cases
 * (trigonometric, hyperbolic, and the two exponential modes when the friction dominates, where
 * the slow mode's rate -w^2 / (q + s) is taken without cancellation), and for a massless tip
 * or one whose mass the damping and friction dwarf (q beyond 1e300: one exponential).
 * c -> infinity gives the stuck element's k h + d. */
static double element_stiffness(double k, double d, double m, double c, double h) {
    if (!(c < 1e300)) return k * h + d;        /* held like a stuck tip (the limit c -> inf) */
    double q = m > 0.0 ? (c + d) / (2.0 * m) : INFINITY;
    if (!(q < 1e300)) {                        /* massless, or the mass negligible */
        double cd = c + d;
        if (!(cd > 0.0)) return 0.0;           /* a free massless tip carries nothing */
        return c * (d - c * expm1(-k * h / cd)) / cd;
    }
    double w2 = k / m, w = sqrt(w2);
    double C, S;
    if (q < w) {                               /* underdamped */
        double Om = sqrt((w - q) * (w + q));
        C = cos(Om * h);
        S = sin(Om * h) / Om;
    } else {
        double r = w / q;
        double s = q * sqrt((1.0 - r) * (1.0 + r));
        if (s > 0.5 * q) {                     /* friction-dominated: two real modes */
            double l1 = -w2 / (q + s), l2 = -(q + s);
            double e1 = exp(l1 * h), e2 = exp(l2 * h);
            double dA = -(k + l1 * c) / (2.0 * s);  /* k y = (c + dA) e1 - dA e2 */
            double A = (c + dA) / k, B = -dA / k;
            return -c * expm1(l1 * h) - dA * (e1 - e2) - d * (l1 * A * e1 + l2 * B * e2);
        }
        C = cosh(s * h);                       /* near critical damping */
        S = s > 0.0 ? sinh(s * h) / s : h;
    }
    double e = exp(-q * h);
    return c - e * ((c - d) * C + ((c * c + d * d) / (2.0 * m) - k) * S);
}

/* Stiffness of the tread against the belt over an outer step h (linearly implicit belt
 * coupling, docs/tire-core.md): element_stiffness per element, k h + d when it sticks. */
static void tread_stiffness(const tf_tire *tire, const tf_ctx *c, double h, double *Jx,
                            double *Jy, double *S1, double *S2) {
    const tf_params *p = &tire->p;
    double jx = 0.0, jy = 0.0, s1 = 0.0, s2 = 0.0;
    double kdx = p->k_x * h + p->d_x, kdy = p->k_y * h + p->d_y;
    for (int i = 0; i < tire->L; i++) {
        const double *e = tire->el + (size_t)i * TF_ELEM;
        if (e[6] == 0.0) continue;
        double V = norm2(e[2], e[3]);
        double x = tire->x_top - i * tire->dx;
        if (V == 0.0) {
            jx += kdx;
            jy += kdy;
            s1 += x * kdy;
            s2 += x * (x * kdy);
            continue;
        }
        tf_tp q;
        double pr = pressure(c, x);
        prep_tp(c->t, c->iT, c->fT, pr * c->inv_void, &q);
        tf_stg S;
        S.t = c->t;
        S.q = q;
        int j = -1;
        if (V > c->t->vnode[0]) {
            if (V >= c->t->vnode[c->t->n[0] - 1]) {
                j = c->t->n[0] - 1;
            } else {
                double f;
                locate(c->t, 0, log10(V), &j, &f);
            }
        }
        set_cell(&S, j);
        S.Ax = S.Ay = 1.0;
        S.gx = S.gy = 0.0;
        S.G = 1.0;
        S.pf = c->mu_scale * pr;
        S.Zs = e[4];
        S.Hs = 0.0;
        S.inv_s0 = c->t->inv_s0;
        S.D = 0.0;                             /* the secant at |w| (a linearisation) */
        S.th = 1.0;
        S.iso = 1;
        double dR_;
        resid(&S, V, &dR_);
        double cs = S.P / V;
        if (!(cs > 0.0)) cs = 0.0;             /* no friction (or a negative table value) */
        double ex = element_stiffness(p->k_x, p->d_x, p->mass, cs, h);
        double ey = element_stiffness(p->k_y, p->d_y, p->mass, cs, h);
        jx += ex;
        jy += ey;
        s1 += x * ey;
        s2 += x * (x * ey);
    }
    *Jx = jx;
    *Jy = jy;
    *S1 = s1;
    *S2 = s2;
}

/* One outer step of length h (docs/tire-core.md, "outer step"). */
static void advance(tf_tire *tire, double h, double Vsx, double Vsy, double V_r, double Fz,
                    double a, double b, double T_surface, double mu_scale, double wc,
                    double q_roll, double d_water, double lt_drain, double *fin) {
    const tf_params *p = &tire->p;
    double dx = tire->dx;
    int L = tire->L;
    double x_top = tire->x_top - V_r * h;
    double shift = floor((x_top - tire->a_max) / dx);
    x_top -= shift * dx;
    tire->x_top = x_top;
    int sh = (int)shift;
    if (sh != 0) {
        if (sh >= L || sh <= -L) {
            memset(tire->el, 0, sizeof(double) * (size_t)L * TF_ELEM);
        } else if (sh > 0) {
            memmove(tire->el, tire->el + (size_t)sh * TF_ELEM,
                    sizeof(double) * (size_t)(L - sh) * TF_ELEM);
            memset(tire->el + (size_t)(L - sh) * TF_ELEM, 0, sizeof(double) * (size_t)sh * TF_ELEM);
        } else {
            int k = -sh;
            memmove(tire->el + (size_t)k * TF_ELEM, tire->el,
                    sizeof(double) * (size_t)(L - k) * TF_ELEM);
            memset(tire->el, 0, sizeof(double) * (size_t)k * TF_ELEM);
        }
    }
    double T0 = p->thermal ? tire->T_tread : T_surface;
    double area = b * dx;
    int any = 0;
    double wsum = 0.0;
    double cf = a > 0.0 && b > 0.0 ? flat_half_length(p, Fz, a, b) : 0.0;
    double iac = a > 0.0 ? 1.0 / (a - cf) : 0.0;
    for (int i = 0; i < L; i++) {
        double x = x_top - i * dx;
        double *e = tire->el + (size_t)i * TF_ELEM;
        int inside = a > 0.0 && area > 0.0 && x < a && x > -a;
        int exiting = !inside && a > 0.0 && area > 0.0 && e[6] != 0.0 &&
                      ((V_r > 0.0 && x <= -a && x + V_r * h > -a) ||
                       (V_r < 0.0 && x >= a && x + V_r * h < a));
        if (!inside && !exiting) {
            memset(e, 0, sizeof(double) * TF_ELEM);
            continue;
        }
        /* time mean over the step of the element's pressure shape (Simpson over its
         * contact within the step) */
        double x0 = x + V_r * h, x1 = x;
        if (x0 > a) x0 = a;
        if (x0 < -a) x0 = -a;
        if (x1 > a) x1 = a;
        if (x1 < -a) x1 = -a;
        double frac = V_r != 0.0 ? (x0 - x1) / (V_r * h) : 1.0;
        double wm = (shape(cf, iac, x0) + 4.0 * shape(cf, iac, 0.5 * (x0 + x1)) +
                     shape(cf, iac, x1)) / 6.0;
        if (V_r == 0.0) wm = shape(cf, iac, x1);
        if (inside) any = 1;
        wsum += frac * wm;
    }
    if (!(wsum > 0.0)) any = 0;
    if (!any) {
        if (!p->rigid) {
            tire->delta[0] *= p->dc_x / (p->kc_x * h + p->dc_x);
            tire->delta[1] *= p->dc_y / (p->kc_y * h + p->dc_y);
            tire->psi *= p->dc_psi / (p->kc_psi * h + p->dc_psi);
        }
        tire->Vb[0] = Vsx;
        tire->Vb[1] = Vsy - V_r * tire->psi;
        tire->wpsi = 0.0;
        tire->wc = wc;
        tire->F[0] = tire->F[1] = 0.0;
        tire->M = 0.0;
        if (p->thermal)
            tire->T_tread = (tire->T_tread + h / p->heat_capacity * (p->conductance * T_surface)) /
                            (1.0 + h * p->conductance / p->heat_capacity);
        fin[0] = 0.0;
        fin[5] = fin[6] = fin[7] = 0.0;
        return;
    }
    tf_ctx c;
    ctx_init(&c, p, step_table(tire, T0, d_water, lt_drain), T0, Fz, a, b, cf,
             Fz / (area * wsum), mu_scale, Vsx, Vsy, V_r);
    /* the friction is read at T0: outside the table's temperature axis it is its edge's */
    const double *Tax = tire->t->ax[1];
    if (!(T0 >= Tax[0] && T0 <= Tax[tire->t->n[1] - 1])) tire->flags |= TF_FLAG_T_RANGE;
    tf_work w = {(double)TF_BUDGET * p->n_elements, 0.0, 0.0};
    c.w = &w;
    double Vbx = Vsx, Vby = Vsy, wpsi = 0.0;
    if (!p->rigid) {
        /* belt translation and yaw, linearly implicit (docs/tire-core.md, "belt"): the
         * base of element i moves at Vby + x_i (wpsi + wc) laterally, Vby = Vsy + uy -
         * V_r psi, wc the spin from camber; the tread force is linearised in the change of
         * the total spin, hence wpsi_n + wc_n - wc below */
        double Jx, Jy, S1, S2;
        tread_stiffness(tire, &c, h, &Jx, &Jy, &S1, &S2);
        Jx *= area;
        Jy *= area;
        S1 *= area;
        S2 *= area;
        double ux = (tire->F[0] - Jx * (Vsx - tire->Vb[0]) - p->kc_x * tire->delta[0]) /
                    (p->kc_x * h + p->dc_x + Jx);
        double D0 = (Vsy - V_r * tire->psi) - tire->Vb[1];
        double a11 = p->kc_y * h + p->dc_y + Jy, a12 = S1 - V_r * h * Jy;
        double a21 = S1, a22 = p->kc_psi * h + p->dc_psi + S2 - V_r * h * S1;
        double wn = tire->wpsi + (tire->wc - wc);
        double b1 = tire->F[1] - p->kc_y * tire->delta[1] - Jy * D0 + S1 * wn;
        double b2 = tire->M - p->kc_psi * tire->psi - S1 * D0 + S2 * wn;
        double det = a11 * a22 - a12 * a21;
        double uy = (b1 * a22 - a12 * b2) / det;
        wpsi = (a11 * b2 - a21 * b1) / det;
        tire->delta[0] += h * ux;
        tire->delta[1] += h * uy;
        tire->psi += h * wpsi;
        Vbx = Vsx + ux;
        Vby = (Vsy + uy) - V_r * tire->psi;
    }
    c.Vbx = Vbx;
    c.Vby = Vby;
    c.wpsi = wpsi + wc;
    double Jx = 0.0, Jy = 0.0, Jm = 0.0, heat = 0.0, nsl = 0.0, fsl = 0.0, psl = 0.0, dTm = 0.0;
    double n_in = 0.0, Tx = 0.0, Ty = 0.0, Tm = 0.0;
    for (int i = 0; i < L; i++) {
        double x = x_top - i * dx;
        double *e = tire->el + (size_t)i * TF_ELEM;
        if (!(x < a && x > -a)) {
            if (e[6] == 0.0) continue;
            /* left the patch during the step: integrated up to the trailing edge */
            double xe = V_r > 0.0 ? -a : a;
            double h_x = (x + V_r * h - xe) / V_r;
            if (!(h_x > 0.0)) { memset(e, 0, sizeof(double) * TF_ELEM); continue; }
            tf_eres rx;
            integrate(&c, e, xe, h_x, &rx);
            tire->work += rx.steps;
            Jx += rx.Jx;
            Jy += rx.Jy;
            Jm += rx.Jm;
            heat += rx.energy;
            memset(e, 0, sizeof(double) * TF_ELEM);
            continue;
        }
        double h_e = h;
        if (e[6] == 0.0) {                        /* enters: tip moving with the belt */
            if (V_r > 0.0) h_e = (a - x) / V_r;
            else if (V_r < 0.0) h_e = (a + x) / -V_r;
            if (h_e > h) h_e = h;
            double x_in = x + V_r * h_e;          /* where it entered */
            e[0] = 0.0;
            e[1] = 0.0;
            e[2] = Vbx;
            e[3] = Vby + x_in * c.wpsi;
            e[4] = 0.0;
            e[5] = h_e;
            e[6] = 1.0;
            e[7] = 0.0;                           /* a fresh contact */
        }
        tf_eres r;
        integrate(&c, e, x, h_e, &r);
        tire->work += r.steps;
        Tx += c.kx * e[0] + c.dx * (e[2] - Vbx);
        double ty = c.ky * e[1] + c.dy * (e[3] - (Vby + x * c.wpsi));
        Ty += ty;
        Tm += x * ty;
        Jx += r.Jx;
        Jy += r.Jy;
        Jm += r.Jm;
        heat += r.energy;
        n_in += 1.0;
        if (r.V > CREEP_SPEED) {
            nsl += 1.0;
            fsl += r.P;
            psl += r.p;
            double dT = r.dT * (1.0 - r.E);
            if (dT > dTm) dTm = dT;
        }
    }
    tire->stages += w.stages;
    tire->fallbacks += w.fallbacks;
    if (w.fallbacks > 0.0) tire->flags |= TF_FLAG_BUDGET;
    tire->Vb[0] = Vbx;
    tire->Vb[1] = Vby;
    tire->wpsi = wpsi;
    tire->wc = wc;
    tire->F[0] = Tx * area;
    tire->F[1] = Ty * area;
    tire->M = Tm * area;
    fin[5] = Jx * area;
    fin[6] = Jy * area;
    fin[7] = Jm * area;
    if (p->thermal) {
        /* friction heat (its share heat_fraction enters the rubber) and the tread's share
         * of the rolling loss q_roll [W], generated inside the tread */
        double Q = heat * area;
        tire->T_tread = (tire->T_tread + (p->heat_fraction * Q + h * q_roll +
                                          h * p->conductance * T_surface) /
                         p->heat_capacity) / (1.0 + h * p->conductance / p->heat_capacity);
    }
    fin[0] = 1.0;
    fin[2] = nsl / n_in;
    fin[3] = psl > 0.0 ? fsl / psl : 0.0;
    fin[4] = dTm;
}

/* Rolling resistance coefficient and the tread's share of the loss at rolling speed |V_r|,
 * tread temperature T and load Fz > 0 (tf_tire_set_rolling): trilinear in (log10 |V_r|, T,
 * log10 Fz), clamped to the table, and proportional to |V_r| below the first speed node. */
static void rolling(const tf_table *rr, double vr, double T, double Fz, double *f, double *sh) {
    double v0 = rr->vnode[0];
    double scale = 1.0;
    if (vr < v0) { scale = vr / v0; vr = v0; }
    int iv, iT, ip;
    double fv, fT, fp;
    locate(rr, 0, log10(vr), &iv, &fv);
    locate(rr, 1, T, &iT, &fT);
    locate(rr, 2, log10(Fz), &ip, &fp);
    int nT = rr->n[1], np = rr->n[2];
    double acc[2] = {0.0, 0.0};
    for (int c = 0; c < 8; c++) {
        int dv = c >> 2, dT = (c >> 1) & 1, dp = c & 1;
        double w = (dv ? fv : 1.0 - fv) * (dT ? fT : 1.0 - fT) * (dp ? fp : 1.0 - fp);
        if (w == 0.0) continue;
        const double *q = rr->val + ((size_t)((iv + dv) * nT + iT + dT) * np + ip + dp) * 3;
        acc[0] += w * q[0];
        acc[1] += w * q[1];
    }
    *f = scale * acc[0];
    *sh = acc[1];
}

/* Upper bound of the loop gain of the belt's lateral translation and yaw through the rolling
 * speed over an outer step h (docs/tire-core.md, "belt coupling at high rolling speed"): the
 * yaw psi turns the base's lateral slip by -V_r psi, the lateral stress it raises is carried
 * V_r h along the patch in a step, and its moment yaws the belt:
 *     G = (V_r h)^2 J^2 / ((k_cy h + d_cy + J)(k_psi h + d_psi + S2)),
 * J = (k_y h + d_y) 2 a b and S2 = (k_y h + d_y) 2 a^3 b / 3 the stiffness of a stuck patch
 * against the belt and its second moment (the largest the tread can have: G grows with them). */
static double belt_gain(const tf_params *p, double V_r, double a, double b, double h) {
    double kd = p->k_y * h + p->d_y;
    double J = kd * (2.0 * a * b), S2 = kd * ((2.0 * a * a * a * b) / 3.0);
    double vh = V_r * h;
    return (vh * vh) * (J * J) / ((p->kc_y * h + p->dc_y + J) * (p->kc_psi * h + p->dc_psi + S2));
}

/* Longest outer step [s] at rolling speed V_r and patch a, b: dt_internal, shortened to
 * resolve the tread tip's period (TIP_STEP) and to keep the belt's lateral-yaw loop gain at
 * most BELT_GAIN_MAX (the largest such step, by bisection: the gain grows with h). */
static double outer_step(const tf_params *p, double V_r, double a, double b) {
    double h = p->dt_internal;
    if (p->mass > 0.0) {
        double kmax = p->k_x > p->k_y ? p->k_x : p->k_y;
        double ht = TIP_STEP / sqrt(kmax / p->mass);
        if (ht < h) h = ht;
    }
    if (p->rigid || !(a > 0.0 && b > 0.0) || !(belt_gain(p, V_r, a, b, h) > BELT_GAIN_MAX))
        return h;
    double lo = 0.0, hi = h;
    for (int it = 0; it < 60; it++) {
        double mid = 0.5 * (lo + hi);
        if (belt_gain(p, V_r, a, b, mid) > BELT_GAIN_MAX) hi = mid; else lo = mid;
    }
    return lo;
}

int tf_tire_step(tf_tire *tire, double dt, const double *in, double *out) {
    double vx = in[0], vy = in[1], omega = in[2], Fz = in[3], Ts = in[4], mus = in[5];
    double gam = in[6], d_water = in[7];
    if (!(isfinite(dt) && isfinite(vx) && isfinite(vy) && isfinite(omega) && isfinite(Fz) &&
          isfinite(Ts) && isfinite(mus) && isfinite(gam) && isfinite(d_water)) || dt < 0.0 ||
        !(Ts > 0.0) || mus < 0.0 || !(fabs(gam) < HALF_PI) || d_water < 0.0)
        return -1;
    const tf_params *p = &tire->p;
    if (isnan(tire->T_tread)) tire->T_tread = Ts;
    tire->flags = 0;
    if (dt > 0.0 && dt < TF_DT_FLOOR) {
        tire->time += dt;
    } else if (dt > 0.0) {
        if (Fz < 0.0) Fz = 0.0;
        double V_r = omega * p->R_e;
        /* water: dynamic hydroplaning lifts the share L of the load off the road (tirecore.h,
         * tf_wet_new); the tread carries Fz_road = (1 - L) Fz */
        double Fz_road = Fz, lt_drain = 0.0;
        const tf_wet *wet = d_water > 0.0 ? tire->wet : NULL;
        if (wet) {
            double Vp = 6.35 * sqrt(p->p_inflation / 1e3) / 3.6;
            double de = d_water - (p->void_ratio * p->tread_depth + tire->texture_depth);
            double sd = de > 0.0 ? de / wet->d_full : 0.0;
            if (sd > 1.0) sd = 1.0;
            double rv = (vx / Vp) * (vx / Vp);
            if (rv > 1.0) rv = 1.0;
            Fz_road = (1.0 - sd * rv) * Fz;
        }
        double a, b;
        patch_size(p, Fz_road, &a, &b);
        /* equal outer steps no longer than dt_internal and the coupling's limits (the
         * real-time fidelity: no longer than dt_internal) */
        double h_max = tire->patch ? p->dt_internal : outer_step(p, V_r, a, b);
        double ns = ceil(dt / h_max - 1e-9);
        if (!(ns <= 2147483647.0)) return -1;     /* more outer steps than an int counts */
        int n_sub = ns > 1.0 ? (int)ns : 1;
        double h = dt / n_sub;
        if (wet && a > 0.0) {   /* drainage time: drain_scale times the time the water film
                                 * spends under the patch at the entrainment speed
                                 * U = (|vx| + |V_r|)/2 (tire_brush.wet_friction) */
            double U = 0.5 * (fabs(vx) + fabs(V_r));
            lt_drain = U > 0.0 ? log10(wet->drain_scale * (2.0 * a / U)) : INFINITY;
        }
        /* camber: the base spins at -(1 - eps) omega sin(gamma) (tirecore.h) */
        double wc = -(1.0 - p->camber_reduction) * omega * sin(gam);
        /* rolling resistance at the start of the step, held over it */
        double f_r = 0.0, share = 0.0;
        if (tire->rr && Fz > 0.0)
            rolling(tire->rr, fabs(V_r), p->thermal ? tire->T_tread : Ts, Fz, &f_r, &share);
        double q_roll = share * f_r * Fz * fabs(V_r);
        double fin[8] = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
        double Ix = 0.0, Iy = 0.0, Im = 0.0;
        tf_rt_state rs;
        if (tire->patch) {
            memcpy(rs.delta, tire->delta, sizeof rs.delta);
            memcpy(rs.Vp, tire->Vb, sizeof rs.Vp);
            memcpy(rs.F, tire->F, sizeof rs.F);
            rs.M = tire->M;
            rs.psi = tire->psi;
            rs.wpsi = tire->wpsi;
            rs.T_tread = tire->T_tread;
            rs.flags = 0;
        }
        for (int k = 0; k < n_sub; k++) {
            if (tire->patch)
                tf_rt_advance(p, tire->patch, &rs, h, vx - V_r, vy, V_r, Fz_road, a, Ts, mus,
                              gam, q_roll, wet ? d_water : 0.0, fin);
            else
                advance(tire, h, vx - V_r, vy, V_r, Fz_road, a, b, Ts, mus, wc, q_roll,
                        d_water, lt_drain, fin);
            Ix += fin[5];
            Iy += fin[6];
            Im += fin[7];
        }
        if (tire->patch) {
            memcpy(tire->delta, rs.delta, sizeof rs.delta);
            memcpy(tire->Vb, rs.Vp, sizeof rs.Vp);
            memcpy(tire->F, rs.F, sizeof rs.F);
            tire->M = rs.M;
            tire->psi = rs.psi;
            tire->wpsi = rs.wpsi;
            tire->wc = wc;
            tire->T_tread = rs.T_tread;
            tire->flags |= rs.flags;
        }
        tire->time += dt;
        double ref = fabs(vx) > p->v_floor ? fabs(vx) : p->v_floor;
        double kappa = (omega * p->R_e - vx) / ref;
        if (vx < 0.0) kappa = -kappa;
        double alpha = atan2(-vy, ref);
        double T0 = p->thermal ? tire->T_tread : Ts;
        double *o = tire->out;
        /* the road force: the friction impulse of the step over its length; a step shorter
         * than the output window W = dt_internal moves the outputs towards its mean by dt/W
         * only (a first-order relaxation), so they change by O(dt) as dt -> 0 */
        double W = p->dt_internal;
        if (dt >= W) {
            o[0] = Ix / dt;
            o[1] = Iy / dt;
            o[2] = Im / dt;
            o[5] = Fz > 0.0 ? norm2(o[0], o[1]) / Fz : 0.0;
        } else {
            o[0] += (Ix - dt * o[0]) / W;
            o[1] += (Iy - dt * o[1]) / W;
            o[2] += (Im - dt * o[2]) / W;
            /* the utilised friction relaxes the same way, towards the step's own |I| / (dt Fz)
             * (at most mu_scale max(mu): the friction on every element is): the relaxed force
             * over the step's load would be unbounded as the load drops to 0 */
            o[5] = Fz > 0.0 ? o[5] + (norm2(Ix, Iy) / Fz - dt * o[5]) / W : 0.0;
        }
        if (fin[0] == 0.0) {
            o[6] = 0.0; o[7] = 0.0; o[8] = 0.0;
        } else {
            o[6] = fin[3];
            o[7] = fin[2];
            o[8] = fin[4];
        }
        o[3] = kappa;
        o[4] = alpha;
        o[9] = T0;
        /* overturning moment of the load, shifted sideways by the belt's deflection, about
         * the contact centre; rolling resistance moment against the spin */
        o[10] = p->rigid ? 0.0 : -tire->delta[1] * Fz;
        o[11] = (V_r > 0.0 ? 1.0 : V_r < 0.0 ? -1.0 : 0.0) * (f_r * Fz * p->R_e);
    }
    memcpy(out, tire->out, sizeof(double) * TF_NOUT);
    return 0;
}

#ifdef TF_PYTHON_EXTENSION
/* The package's install builds this library with setuptools as an "extension" file; it is
 * loaded with ctypes and never imported, but Windows' linker wants the init symbol. */
TF_API void *PyInit__tirecore(void) { return 0; }
#endif
