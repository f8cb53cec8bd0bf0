/*
 * tirert.c: the real-time fidelity of the tire (tirert.h; method in docs/realtime.md).
 *
 * Every floating-point operation here is mirrored, in the same order, by the Python reference
 * tire_brush/realtime.py (PatchEval, rt_advance); the tests pin the two to each other. Built
 * with the core's flags (no contraction of multiply-adds, no fast-math).
 */
#include "tirert.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

struct tf_patch {
    int n[TF_PATCH_NAX];
    double *ax[TF_PATCH_NAX];
    size_t stride[TF_PATCH_NAX];   /* in doubles, the value index innermost */
    double *val;
    double *q;                     /* full-sliding slip share at the load nodes */
    double *f0;                    /* force at zero slip over Fz, (gamma, T, Fz, v, 2) */
    double vmin;                   /* 10^(first speed node) [m/s] */
    int nd;                        /* water-depth layers (1: the dry road only) */
    double *depth;                 /* their water depths [m], from 0 (the dry road) */
    size_t lval, lf0;              /* doubles per layer in val and f0 */
    double *law;                   /* the depth law's curvature between neighbouring layers,
                                    * (nd - 1, gamma, T, Fz, v, theta, rho), or NULL */
};

tf_patch *tf_patch_new(const int *n, const double *axes, const double *q, const double *f0,
                       const double *values) {
    const double dry = 0.0;
    return tf_patch_new_wet(n, 1, &dry, axes, q, f0, values);
}

tf_patch *tf_patch_new_wet(const int *n, int nd, const double *depth, const double *axes,
                           const double *q, const double *f0, const double *values) {
    if (!n || !axes || !q || !f0 || !values || !depth || nd < 1 || nd > 1000) return NULL;
    if (depth[0] != 0.0) return NULL;
    for (int i = 1; i < nd; i++)
        if (!isfinite(depth[i]) || !(depth[i] > depth[i - 1])) return NULL;
    size_t nax = 0, nn = 1;
    for (int k = 0; k < TF_PATCH_NAX; k++) {
        if (n[k] < 2 || n[k] > 100000) return NULL;
        nax += (size_t)n[k];
        nn *= (size_t)n[k];
    }
    const double *a = axes;
    for (int k = 0; k < TF_PATCH_NAX; k++) {
        for (int i = 0; i < n[k]; i++)
            if (!isfinite(a[i]) || (i > 0 && !(a[i] > a[i - 1]))) return NULL;
        a += n[k];
    }
    const double *g = axes, *th = axes + nax - n[5] - n[4], *rho = axes + nax - n[5];
    if (g[0] != 0.0 || rho[0] != 0.0 || rho[n[5] - 1] != 1.0 ||
        !(th[0] >= -1.5707963267948977) || !(th[n[4] - 1] <= 1.5707963267948977))
        return NULL;
    for (size_t i = 0; i < (size_t)nd * nn * TF_PATCH_NV; i++)
        if (!isfinite(values[i])) return NULL;
    for (int i = 0; i < n[2]; i++)
        if (!(q[i] > 0.0 && q[i] < 1.0)) return NULL;
    size_t n0 = (size_t)n[0] * n[1] * n[2] * n[3] * 2;
    for (size_t i = 0; i < (size_t)nd * n0; i++)
        if (!isfinite(f0[i])) return NULL;
    tf_patch *pt = calloc(1, sizeof *pt);
    if (!pt) return NULL;
    pt->ax[0] = malloc(sizeof(double) * nax);
    pt->val = malloc(sizeof(double) * nn * TF_PATCH_NV * (size_t)nd);
    pt->q = malloc(sizeof(double) * (size_t)n[2]);
    pt->f0 = malloc(sizeof(double) * n0 * (size_t)nd);
    pt->depth = malloc(sizeof(double) * (size_t)nd);
    if (!pt->ax[0] || !pt->val || !pt->q || !pt->f0 || !pt->depth) {
        free(pt->ax[0]);
        free(pt->val);
        free(pt->q);
        free(pt->f0);
        free(pt->depth);
        free(pt);
        return NULL;
    }
    memcpy(pt->ax[0], axes, sizeof(double) * nax);
    memcpy(pt->q, q, sizeof(double) * (size_t)n[2]);
    memcpy(pt->f0, f0, sizeof(double) * n0 * (size_t)nd);
    memcpy(pt->val, values, sizeof(double) * nn * TF_PATCH_NV * (size_t)nd);
    memcpy(pt->depth, depth, sizeof(double) * (size_t)nd);
    pt->nd = nd;
    pt->lval = nn * TF_PATCH_NV;
    pt->lf0 = n0;
    for (int k = 0; k < TF_PATCH_NAX; k++) {
        pt->n[k] = n[k];
        if (k > 0) pt->ax[k] = pt->ax[k - 1] + n[k - 1];
    }
    size_t st = TF_PATCH_NV;
    for (int k = TF_PATCH_NAX - 1; k >= 0; k--) {
        pt->stride[k] = st;
        st *= (size_t)n[k];
    }
    pt->vmin = pow(10.0, pt->ax[3][0]);
    return pt;
}

void tf_patch_free(tf_patch *pt) {
    if (!pt) return;
    free(pt->ax[0]);
    free(pt->val);
    free(pt->q);
    free(pt->f0);
    free(pt->depth);
    free(pt->law);
    free(pt);
}

static uint32_t rd_u32(const unsigned char *p) {
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static double rd_f64(const unsigned char *p) {
    uint64_t u = (uint64_t)rd_u32(p) | (uint64_t)rd_u32(p + 4) << 32;
    double d;
    memcpy(&d, &u, 8);
    return d;
}

static float rd_f32(const unsigned char *p) {
    uint32_t u = rd_u32(p);
    float f;
    memcpy(&f, &u, 4);
    return f;
}

tf_patch *tf_patch_from_bytes(const unsigned char *b, size_t n) {
    if (!b || n < 56 || memcmp(b, "TIREFRIC-PATCH\0\3", 16) != 0) return NULL;
    uint64_t nd = rd_u32(b + 16), law = rd_u32(b + 44), nax = 0, nn = 1;
    if (nd < 1 || nd > 1000 || !(law == 0 || (law == 1 && nd >= 2))) return NULL;
    int dims[TF_PATCH_NAX];
    for (int k = 0; k < TF_PATCH_NAX; k++) {
        uint32_t d = rd_u32(b + 20 + 4 * k);
        if (d < 2 || d > 100000) return NULL;
        dims[k] = (int)d;
        nax += d;
        nn *= d;
    }
    if (nn >= ((uint64_t)1 << 32)) return NULL;
    uint64_t n0 = (uint64_t)dims[0] * dims[1] * dims[2] * dims[3] * 2;
    uint64_t nhead = nd + nax + (uint64_t)dims[2] + nd * n0; /* float64s */
    uint64_t nval = nd * TF_PATCH_NV * nn;                    /* float32s */
    uint64_t nlaw = law * (nd - 1) * nn;                      /* float64s */
    if (n != 48 + 8 * nhead + 4 * nval + 8 * nlaw + 8) return NULL;
    double *a = malloc(sizeof(double) * (size_t)(nhead + nval + nlaw));
    if (!a) return NULL;
    for (size_t i = 0; i < nhead; i++) a[i] = rd_f64(b + 48 + 8 * i);
    const unsigned char *bv = b + 48 + 8 * nhead;
    for (size_t i = 0; i < nval; i++) a[nhead + i] = (double)rd_f32(bv + 4 * i);
    for (size_t i = 0; i < nlaw; i++) a[nhead + nval + i] = rd_f64(bv + 4 * nval + 8 * i);
    const double *ax = a + nd;
    tf_patch *pt = tf_patch_new_wet(dims, (int)nd, a, ax, ax + nax, ax + nax + dims[2],
                                    a + nhead);
    if (pt && law && tf_patch_set_depth_law(pt, a + nhead + nval)) {
        tf_patch_free(pt);
        pt = NULL;
    }
    free(a);
    return pt;
}

int tf_patch_set_depth_law(tf_patch *pt, const double *law) {
    if (!pt || !law || pt->nd < 2) return -1;
    size_t nn = pt->lval / TF_PATCH_NV, m = nn * (size_t)(pt->nd - 1);
    for (size_t i = 0; i < m; i++)
        if (!(fabs(law[i]) <= 1.0)) return -1;
    double *k = malloc(sizeof(double) * m);
    if (!k) return -1;
    memcpy(k, law, sizeof(double) * m);
    free(pt->law);
    pt->law = k;
    return 0;
}

int tf_patch_layers(const tf_patch *pt) { return pt ? pt->nd : 0; }

/* Cell i and weight f of x on an ascending axis, clamped to its ends; inv = 1 / (a[i+1] -
 * a[i]) inside, 0 where clamped (the derivative there is 0). */
static void locate_ax(int n, const double *a, double x, int *i, double *f, double *inv) {
    if (!(x > a[0])) { *i = 0; *f = 0.0; *inv = 0.0; return; }
    if (!(x < a[n - 1])) { *i = n - 2; *f = 1.0; *inv = 0.0; return; }
    int j = 0;
    while (a[j + 1] <= x) j++;
    *i = j;
    *inv = 1.0 / (a[j + 1] - a[j]);
    *f = (x - a[j]) * *inv;
}

int tf_patch_eval(const tf_patch *pt, double Vx, double Vy, double Vr, double Fz, double T,
                  double gamma, double *out) {
    return tf_patch_eval_wet(pt, Vx, Vy, Vr, Fz, T, gamma, 0.0, out);
}

int tf_patch_eval_wet(const tf_patch *pt, double Vx, double Vy, double Vr, double Fz,
                      double T, double gamma, double d_water, double *out) {
    double sx = Vx < 0.0 ? -1.0 : 1.0;
    double sg = gamma < 0.0 ? -1.0 : 1.0;
    double sv = Vr < 0.0 ? -1.0 : 1.0;
    double ax_ = fabs(Vx);
    double vy = Vy * sg;
    double s = sqrt(ax_ * ax_ + vy * vy);
    double vr = fabs(Vr);
    double vref = s + vr;
    double den = vref > pt->vmin ? vref : pt->vmin;
    double rho = s / den;
    double drho = vref > pt->vmin ? vr / (den * den) : 1.0 / den;
    double theta = s > 0.0 ? atan2(vy, ax_) : 0.0;
    double ux = 1.0, uy = 0.0;
    if (s > 0.0) {
        ux = ax_ / s;
        uy = vy / s;
    }
    int li[TF_PATCH_NAX];
    double lf[TF_PATCH_NAX], linv[TF_PATCH_NAX];
    /* the slip share on the load's own scale (tirert.h) */
    locate_ax(pt->n[2], pt->ax[2], Fz, &li[2], &lf[2], &linv[2]);
    double qs = pt->q[li[2]] + lf[2] * (pt->q[li[2] + 1] - pt->q[li[2]]);
    double D = rho + qs * (1.0 - rho);
    double rn = rho / D;
    drho = drho * (qs / (D * D));
    double xs[TF_PATCH_NAX] = {fabs(gamma), T, Fz, log10(den), theta, rn};
    for (int k = 0; k < TF_PATCH_NAX; k++)
        locate_ax(pt->n[k], pt->ax[k], xs[k], &li[k], &lf[k], &linv[k]);
    const double *Tax = pt->ax[1];
    int flags = (T >= Tax[0] && T <= Tax[pt->n[1] - 1]) ? 0 : TF_FLAG_T_RANGE;
    double acc[TF_PATCH_NV] = {0.0}, dr[4] = {0.0}, dth[4] = {0.0};
    size_t base = 0;
    for (int k = 0; k < TF_PATCH_NAX; k++) base += (size_t)li[k] * pt->stride[k];
    /* the outer (gamma, T, Fz, v) cell's first node in the zero-slip force array */
    size_t ob = (((size_t)li[0] * pt->n[1] + li[1]) * pt->n[2] + li[2]) * pt->n[3] + li[3];
    double g0x = 0.0, g0y = 0.0;
    double ft = lf[4], fr = lf[5];
    /* the 16 outer corners (gamma, T, Fz, v) with a weight: their weights and offsets from
     * the cell's first node, each corner with its 2 x 2 (theta, rho) cell */
    double cw[16];
    size_t co[16];
    int nc = 0;
    for (int c = 0; c < 16; c++) {
        double w = 1.0;
        size_t off = 0;
        for (int k = 0; k < 4; k++) {
            int bit = (c >> (3 - k)) & 1;
            double f = lf[k];
            w *= bit ? f : 1.0 - f;
            off += (size_t)bit * pt->stride[k];
        }
        if (w == 0.0) continue;
        cw[nc] = w;
        co[nc++] = off;
    }
    /* the water depth: the two layers about it, clamped to the layers' depths as the full
     * model clamps the wet branch (a dry-only table: its one layer) */
    int il = 0;
    double fl = 0.0;
    if (pt->nd > 1) {
        double dinv;
        locate_ax(pt->nd, pt->depth, d_water, &il, &fl, &dinv);
        if (pt->law && fl > 0.0 && fl < 1.0) {
            /* the full model's depth law between the two layers (tirert.h): its curvature
             * at the point, multilinear over the node cell as the values */
            size_t s4 = pt->stride[4] / TF_PATCH_NV, s5 = pt->stride[5] / TF_PATCH_NV;
            const double *law = pt->law + (size_t)il * (pt->lval / TF_PATCH_NV) +
                                base / TF_PATCH_NV;
            double kap = 0.0;
            for (int i = 0; i < nc; i++) {
                const double *k00 = law + co[i] / TF_PATCH_NV, *k10 = k00 + s4;
                double a00 = k00[0], a01 = k00[s5], a10 = k10[0], a11 = k10[s5];
                double lo = a00 + fr * (a01 - a00);
                double hi = a10 + fr * (a11 - a10);
                kap += cw[i] * (lo + ft * (hi - lo));
            }
            fl = fl - kap * (fl * (1.0 - fl));
        }
    }
    for (int l = 0; l < 2; l++) {
        double wl = l ? fl : 1.0 - fl;
        if (wl == 0.0) continue;
        const double *val = pt->val + (size_t)(il + l) * pt->lval;
        const double *f0 = pt->f0 + (size_t)(il + l) * pt->lf0;
        for (int i = 0; i < nc; i++) {
            double w = wl * cw[i];
            size_t off = base + co[i];
            size_t o0 = 2 * (ob + co[i] / pt->stride[3]);
            g0x += w * f0[o0];
            g0y += w * f0[o0 + 1];
            const double *v00 = val + off, *v01 = v00 + pt->stride[5];
            const double *v10 = v00 + pt->stride[4], *v11 = v10 + pt->stride[5];
            for (int q = 0; q < TF_PATCH_NV; q++) {
                double a00 = v00[q], a01 = v01[q], a10 = v10[q], a11 = v11[q];
                double lo = a00 + fr * (a01 - a00);
                double hi = a10 + fr * (a11 - a10);
                acc[q] += w * (lo + ft * (hi - lo));
                if (q < 4) {
                    dr[q] += w * ((a01 - a00) + ft * ((a11 - a10) - (a01 - a00)));
                    dth[q] += w * (hi - lo);
                }
            }
        }
        if (pt->nd == 1) break;
    }
    for (int q = 0; q < 4; q++) {
        dr[q] *= linv[5];
        dth[q] *= linv[4];
    }
    double fa = acc[0], fc = acc[1], mz = acc[2], mb = acc[3];
    /* the force in the folded frame: -f_along along the slip, f_across across it */
    double nx = -uy, ny = ux;
    double Fxf = Fz * (g0x + (-fa * ux + fc * nx));
    double Fyf = Fz * (g0y + (-fa * uy + fc * ny));
    /* derivatives by the folded velocity (|Vx|, sg Vy); the turn of the slip's direction is
     * taken over at least half the first slip-share cell */
    double r1 = pt->ax[5][1];
    double s1 = 0.5 * ((r1 * qs) / (1.0 - r1 * (1.0 - qs))) * den;
    double se = s > s1 ? s : s1;
    double J[8];
    for (int j = 0; j < 2; j++) {
        double sj = j == 0 ? ux : uy;
        double nj = j == 0 ? nx : ny;
        double dfa = dr[0] * drho * sj + dth[0] * nj / se;
        double dfc = dr[1] * drho * sj + dth[1] * nj / se;
        double dmz = dr[2] * drho * sj + dth[2] * nj / se;
        double dmb = dr[3] * drho * sj + dth[3] * nj / se;
        J[j] = Fz * (-dfa * ux + dfc * nx - fa * nx * nj / se - fc * ux * nj / se);
        J[2 + j] = Fz * (-dfa * uy + dfc * ny - fa * ny * nj / se - fc * uy * nj / se);
        J[4 + j] = Fz * dmz;
        J[6 + j] = Fz * dmb;
    }
    out[0] = sx * Fxf;
    out[1] = sg * Fyf;
    out[2] = sg * sv * (Fz * mz);
    out[3] = sg * sv * (Fz * mb);
    /* unfold: d/dVx = sx d/d|Vx|, d/dVy = sg d/d(sg Vy) */
    out[4] = J[0];
    out[5] = sx * sg * J[1];
    out[6] = sg * sx * J[2];
    out[7] = J[3];
    out[8] = sg * sv * sx * J[4];
    out[9] = sv * J[5];
    out[10] = sg * sv * sx * J[6];
    out[11] = sv * J[7];
    out[12] = acc[4];
    out[13] = acc[5];
    out[14] = acc[6];
    out[15] = acc[7] * Fz * vref;
    return flags;
}

/* One sub-step h of the real-time fidelity (docs/realtime.md): belt translation and yaw and
 * the patch's slip velocity together by linearly implicit Euler (the patch's forces linearised
 * about the sub-step's start with the table's derivatives), the tread temperature by implicit
 * Euler. fin as the full model's outer step. */
void tf_rt_advance(const tf_params *p, const tf_patch *pt, tf_rt_state *s, double h,
                   double Vsx, double Vsy, double V_r, double Fz, double a, double Ts,
                   double mus, double gam, double q_roll, double d_water, double *fin) {
    for (int k = 0; k < 8; k++) fin[k] = 0.0;
    int rigid = p->rigid != 0;
    if (!(Fz > 0.0 && a > 0.0) || !(mus > 1e-6)) {
        /* no contact (or no friction): the belt relaxes on its dampers, as the full model's */
        if (!rigid) {
            s->delta[0] *= p->dc_x / (p->kc_x * h + p->dc_x);
            s->delta[1] *= p->dc_y / (p->kc_y * h + p->dc_y);
            s->psi *= p->dc_psi / (p->kc_psi * h + p->dc_psi);
        }
        s->Vp[0] = Vsx;
        s->Vp[1] = Vsy - V_r * s->psi;
        s->wpsi = 0.0;
        s->F[0] = s->F[1] = 0.0;
        s->M = 0.0;
        if (p->thermal)
            s->T_tread = (s->T_tread + h / p->heat_capacity * (p->conductance * Ts)) /
                         (1.0 + h * p->conductance / p->heat_capacity);
        return;
    }
    double T0 = p->thermal ? s->T_tread : Ts;
    /* the patch at the sub-step's start; a friction scale by the similarity method (Pacejka
     * 2012, ch. 4): the patch at mu_scale and slip V responds as mu_scale times the patch at 1
     * and V / mu_scale (sliding speeds and friction power scale once more) */
    double ims = 1.0 / mus;
    double o[TF_PATCH_NOUT];
    s->flags |= tf_patch_eval_wet(pt, s->Vp[0] * ims, s->Vp[1] * ims, V_r, Fz, T0, gam,
                                  d_water, o);
    double F0x = mus * o[0], F0y = mus * o[1], Mz0 = mus * o[2], M0 = mus * o[3];
    double J[8];
    memcpy(J, o + 4, sizeof J);
    double frac = o[13];
    if (frac > 1.0) frac = 1.0;
    if (!(frac > 0.0)) frac = 0.0;
    double vr = fabs(V_r);
    if (vr < pt->vmin) vr = pt->vmin;
    /* the tread's lag: the transit of the adhesion zone (the mean delay 2a/3 of the brush's
     * linear response to a step of slip, docs/realtime.md), and at least the tip's own response
     * time sqrt(m / k) (a sliding patch is still a tread of massive tips on springs in series
     * with the belt: without it a falling friction would close an algebraic loop through the
     * massless belt) */
    double tau = ((2.0 / 3.0) * a) * (1.0 - frac) / vr;
    double kmax = p->k_x > p->k_y ? p->k_x : p->k_y;
    double tau_tip = sqrt(p->mass / kmax);
    if (tau < tau_tip) tau = tau_tip;
    if (!rigid) {
        /* where the patch's force falls with its slip (J_xx or J_yy > 0: a falling friction),
         * the loop patch -> massless belt -> patch is stable only while J < d_c + k_c tau; the
         * lag is made long enough for twice the slope (the full model stick-slips there, its
         * mean is what the table holds; docs/realtime.md) */
        double t_x = (2.0 * J[0] - p->dc_x) / p->kc_x;
        double t_y = (2.0 * J[3] - p->dc_y) / p->kc_y;
        if (tau < t_x) tau = t_x;
        if (tau < t_y) tau = t_y;
    }
    double t_ = tau + h;
    double iAx = 0.0, iAy = 0.0, iB = 0.0, kcx = 0.0, kcy = 0.0, kps = 0.0;
    if (!rigid) {
        iAx = 1.0 / (p->kc_x + p->dc_x / h);
        iAy = 1.0 / (p->kc_y + p->dc_y / h);
        iB = 1.0 / (p->kc_psi + p->dc_psi / h);
        kcx = p->kc_x;
        kcy = p->kc_y;
        kps = p->kc_psi;
    }
    double hv = h * V_r * iB;
    double m11 = t_ - J[0] * iAx;
    double m12 = -J[1] * iAx;
    double m21 = -J[2] * iAy + hv * J[6];
    double m22 = t_ - J[3] * iAy + hv * J[7];
    double r1 = h * (Vsx - s->Vp[0]) + (F0x - kcx * s->delta[0]) * iAx;
    double r2 = h * ((Vsy - V_r * s->psi) - s->Vp[1]) + (F0y - kcy * s->delta[1]) * iAy -
                hv * (M0 - kps * s->psi);
    double det = m11 * m22 - m12 * m21;
    if (!(det > 0.25 * t_ * t_)) {
        /* the linearisation would not be a contraction here: the patch's force held over the
         * sub-step (explicit in the force, implicit in the belt) */
        for (int k = 0; k < 8; k++) J[k] = 0.0;
        m11 = m22 = t_;
        m12 = m21 = 0.0;
        det = t_ * t_;
    }
    double dVx = (r1 * m22 - m12 * r2) / det;
    double dVy = (m11 * r2 - m21 * r1) / det;
    double Fx = F0x + (J[0] * dVx + J[1] * dVy);
    double Fy = F0y + (J[2] * dVx + J[3] * dVy);
    double Mz = Mz0 + (J[4] * dVx + J[5] * dVy);
    double Mb = M0 + (J[6] * dVx + J[7] * dVy);
    double ddx = 0.0, ddy = 0.0;
    if (!rigid) {
        ddx = (Fx - kcx * s->delta[0]) * iAx;
        ddy = (Fy - kcy * s->delta[1]) * iAy;
        s->delta[0] += ddx;
        s->delta[1] += ddy;
        double dpsi = (Mb - kps * s->psi) * iB;
        s->psi += dpsi;
        s->wpsi = dpsi / h;
    }
    s->Vp[0] += dVx;
    s->Vp[1] += dVy;
    s->F[0] = Fx;
    s->F[1] = Fy;
    s->M = Mb;
    if (p->thermal) {
        /* the patch's friction heat, at most the work the belt does on the patch (its force
         * on the belt's slip velocity, Vs + d(delta)/dt - V_r psi): while the patch's slip
         * lags the belt's the table's power at it could exceed what the belt delivers */
        double P = (mus * mus) * o[15];
        double Pb = -(Fx * (Vsx + ddx / h) + Fy * ((Vsy + ddy / h) - V_r * s->psi));
        if (!(Pb > 0.0)) Pb = 0.0;
        if (P > Pb) P = Pb;
        double Q = P * h;
        s->T_tread = (s->T_tread + (p->heat_fraction * Q + h * q_roll +
                                    h * p->conductance * Ts) / p->heat_capacity) /
                     (1.0 + h * p->conductance / p->heat_capacity);
    }
    fin[0] = 1.0;
    fin[2] = o[13];
    fin[3] = mus * o[12];
    fin[4] = (mus * mus) * o[14];
    fin[5] = h * Fx;
    fin[6] = h * Fy;
    fin[7] = h * Mz;
}
