/*
 * bspline: a tensor-product B-spline of up to four inputs read at one point, the point reader
 * of a braking study's force map (tire_brush/braking/force_map.py, ForceMap.point_evaluator).
 * tire_brush/braking/force_map.py's PointEvaluator is the readable reference of this file,
 * operation for operation; the tests pin the two together.
 */
#ifndef TF_BSPLINE_H
#define TF_BSPLINE_H

#include "tirecore.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Inputs of a point read, in call order (kappa, vx, Fz, T_K). */
#define TF_BSPLINE_NIN 4

typedef struct tf_bspline tf_bspline;

/* A spline over n_axes (1 ... TF_BSPLINE_NIN) active axes. Per active axis a: input[a] its
 * position among the TF_BSPLINE_NIN inputs, degree[a] (1 ... 5), n_knots[a] its knot count
 * (>= 2 degree[a] + 2), log10[a] whether its coordinate is log10 of the input, lo[a], hi[a]
 * the input's clamp range; knots: the knot vectors one after another; coef: the
 * coefficients (C order over the active axes, n_knots[a] - degree[a] - 1 per axis). Copies
 * the data; NULL on bad input. */
TF_API tf_bspline *tf_bspline_new(int n_axes, const int *input, const int *degree,
                                  const int *n_knots, const int *log10, const double *lo,
                                  const double *hi, const double *knots, const double *coef);
TF_API void tf_bspline_free(tf_bspline *s);
/* The spline at one point (inputs clamped to their ranges; NaN in, NaN out). */
TF_API double tf_bspline_eval(tf_bspline *s, double in0, double in1, double in2, double in3);

#ifdef __cplusplus
}
#endif

#endif
