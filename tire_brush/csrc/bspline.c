/*
 * bspline.c: a tensor-product B-spline read at one point (bspline.h).
 *
 * At a point the spline is sum c[i, j, ..] B_i(x_1) B_j(x_2) .. over the k + 1 basis
 * functions per axis that do not vanish there (de Boor, A Practical Guide to Splines, 2001,
 * ch. X): the knot span by bisection (the first knot above x, as Python's bisect_right), the
 * values by the recurrence of de Boor's routine BSPLVB, written out for the cubic as in the
 * reference (tire_brush/braking/force_map.py, PointEvaluator._basis), and the coefficient
 * block contracted with the basis vectors, the last axis first.
 */
#include "bspline.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MAXK 5

struct tf_bspline {
    int n_axes;
    int input[TF_BSPLINE_NIN], degree[TF_BSPLINE_NIN], n_knots[TF_BSPLINE_NIN];
    int n_coef[TF_BSPLINE_NIN], log10[TF_BSPLINE_NIN];
    long stride[TF_BSPLINE_NIN];
    double lo[TF_BSPLINE_NIN], hi[TF_BSPLINE_NIN];
    double *knots[TF_BSPLINE_NIN];
    double *coef;
    double *mem;
};

tf_bspline *tf_bspline_new(int n_axes, const int *input, const int *degree,
                           const int *n_knots, const int *log10_, const double *lo,
                           const double *hi, const double *knots, const double *coef)
{
    long nk = 0, nc = 1;
    int a;
    tf_bspline *s;
    if (n_axes < 1 || n_axes > TF_BSPLINE_NIN)
        return NULL;
    for (a = 0; a < n_axes; a++) {
        if (input[a] < 0 || input[a] >= TF_BSPLINE_NIN || degree[a] < 1 || degree[a] > MAXK
            || n_knots[a] < 2 * degree[a] + 2 || !(lo[a] <= hi[a]))
            return NULL;
        nk += n_knots[a];
        nc *= n_knots[a] - degree[a] - 1;
    }
    s = (tf_bspline *)calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->mem = (double *)malloc((size_t)(nk + nc) * sizeof(double));
    if (!s->mem) {
        free(s);
        return NULL;
    }
    s->n_axes = n_axes;
    memcpy(s->mem, knots, (size_t)nk * sizeof(double));
    s->coef = s->mem + nk;
    memcpy(s->coef, coef, (size_t)nc * sizeof(double));
    nk = 0;
    for (a = 0; a < n_axes; a++) {
        s->input[a] = input[a];
        s->degree[a] = degree[a];
        s->n_knots[a] = n_knots[a];
        s->n_coef[a] = n_knots[a] - degree[a] - 1;
        s->log10[a] = log10_[a] != 0;
        s->lo[a] = lo[a];
        s->hi[a] = hi[a];
        s->knots[a] = s->mem + nk;
        nk += n_knots[a];
    }
    s->stride[n_axes - 1] = 1;
    for (a = n_axes - 2; a >= 0; a--)
        s->stride[a] = s->stride[a + 1] * s->n_coef[a + 1];
    return s;
}

void tf_bspline_free(tf_bspline *s)
{
    if (s) {
        free(s->mem);
        free(s);
    }
}

/* First index and values b[0 .. k] of the B-splines of degree k nonzero at x (knots t, n
 * coefficients): PointEvaluator._basis, operation for operation. */
static int basis(const double *t, int nt, int k, int n, double x, double *b)
{
    int lo = 0, hi = nt, m, j, r;
    while (lo < hi) {                      /* bisect_right: the first knot above x */
        int mid = (lo + hi) / 2;
        if (x < t[mid])
            hi = mid;
        else
            lo = mid + 1;
    }
    m = lo - 1;
    if (m < k)
        m = k;
    if (m > n - 1)
        m = n - 1;
    if (k == 3) {
        double tr1 = t[m + 1] - x, tr2 = t[m + 2] - x, tr3 = t[m + 3] - x;
        double tl1 = x - t[m], tl2 = x - t[m - 1], tl3 = x - t[m - 2];
        double temp, a0, a1, b0, b1, b2, c0, c1, saved;
        temp = 1.0 / (tr1 + tl1);
        a0 = tr1 * temp;
        a1 = tl1 * temp;
        temp = a0 / (tr1 + tl2);
        b0 = tr1 * temp;
        saved = tl2 * temp;
        temp = a1 / (tr2 + tl1);
        b1 = saved + tr2 * temp;
        b2 = tl1 * temp;
        temp = b0 / (tr1 + tl3);
        c0 = tr1 * temp;
        saved = tl3 * temp;
        temp = b1 / (tr2 + tl2);
        c1 = saved + tr2 * temp;
        saved = tl2 * temp;
        temp = b2 / (tr3 + tl1);
        b[0] = c0;
        b[1] = c1;
        b[2] = saved + tr3 * temp;
        b[3] = tl1 * temp;
        return m - 3;
    }
    b[0] = 1.0;
    for (j = 1; j <= k; j++) {
        double saved = 0.0, nxt[MAXK + 1];
        for (r = 0; r < j; r++) {
            double right = t[m + r + 1] - x, left = x - t[m + r + 1 - j];
            double temp = b[r] / (right + left);
            nxt[r] = saved + right * temp;
            saved = left * temp;
        }
        nxt[j] = saved;
        for (r = 0; r <= j; r++)
            b[r] = nxt[r];
    }
    return m - k;
}

double tf_bspline_eval(tf_bspline *s, double in0, double in1, double in2, double in3)
{
    const double in[TF_BSPLINE_NIN] = {in0, in1, in2, in3};
    double b[TF_BSPLINE_NIN][MAXK + 1];
    double acc[TF_BSPLINE_NIN];
    int first[TF_BSPLINE_NIN], idx[TF_BSPLINE_NIN];
    int na = s->n_axes, a;
    long base = 0;
    for (a = 0; a < na; a++) {
        double x = in[s->input[a]];
        if (isnan(x))
            return NAN;
        x = x < s->lo[a] ? s->lo[a] : x;
        x = x > s->hi[a] ? s->hi[a] : x;
        if (s->log10[a])
            x = log10(x);
        first[a] = basis(s->knots[a], s->n_knots[a], s->degree[a], s->n_coef[a], x, b[a]);
        base += first[a] * s->stride[a];
    }
    /* the block contracted as the reference does, the last axis first:
     * out = ((c[block] @ b_last) @ ...) @ b_first; acc[a] the sum of level a so far */
    for (a = 0; a < na; a++)
        idx[a] = 0;
    for (;;) {
        long off = base;
        double sum = 0.0;
        int kl = s->degree[na - 1], r;
        for (a = 0; a < na - 1; a++)
            off += idx[a] * s->stride[a];
        for (r = 0; r <= kl; r++)
            sum += s->coef[off + r] * b[na - 1][r];
        acc[na - 1] = sum;
        for (a = na - 2; a >= 0; a--) {      /* carry the finished level outward */
            if (idx[a] == 0)
                acc[a] = 0.0;
            acc[a] += acc[a + 1] * b[a][idx[a]];
            if (++idx[a] <= s->degree[a])
                break;
            idx[a] = 0;
        }
        if (a < 0)
            return acc[0];
    }
}
