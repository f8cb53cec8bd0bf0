/*
 * tirert: the real-time fidelity of the tirefric tire (docs/realtime.md).
 *
 * A quasi-steady contact patch, its response tabulated at build time from the steady march of
 * the full model (tf_steady, tire_brush/realtime_build.py), on the full model's belt
 * (translation and yaw) with the tread's transit lag and the same tread temperature. A tire of
 * tirecore.h steps in this fidelity once it is given a patch table (tf_tire_set_patch); its
 * inputs, outputs, state vector, flags and rolling resistance are those of the full tire.
 * tire_brush/realtime.py is the readable reference of this file, pinned to it by the tests.
 */
#ifndef TIRERT_H
#define TIRERT_H

#include <stddef.h>

#include "tirecore.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Values per node of a patch table: the force along the slip (opposing it) and across it over
 * Fz, Mz over Fz [m], the moment of the tread's stress on the belt over Fz [m], mu_slide,
 * sliding_fraction, dT_flash_max [K], the friction power over Fz (|V| + |V_r|) [1]. */
#define TF_PATCH_NV 8
/* Axes of a patch table, outermost first: |gamma| [rad] (from 0), T [K], Fz [N], log10 of
 * |V| + |V_r| [m/s], slip direction theta = atan2(V_y, |V_x|) [rad] in [-pi/2, pi/2], and the
 * normalised slip share rho_n = rho / (rho + q (1 - rho)) [1] from 0 to 1, of the slip share
 * rho = |V| / max(|V| + |V_r|, v_0) (v_0 the first speed node) on the scale of the full-sliding
 * share q (3 Fz / C at the load nodes, linear between them; docs/realtime.md). */
#define TF_PATCH_NAX 6
/* Results of tf_patch_eval: Fx, Fy, Mz, M_belt [N, N m]; their derivatives by V_x and V_y
 * (row-major 4 x 2); mu_slide, sliding_fraction, dT_flash_max [K], friction power [W]. */
#define TF_PATCH_NOUT 16

/* A patch table from its axis lengths n[TF_PATCH_NAX] (each >= 2), the axes one after another
 * (strictly ascending), q at the load nodes (in (0, 1)), the force at zero slip over Fz (x, y)
 * at the (gamma, T, Fz, v) nodes (C order), and the node values (C order over the axes,
 * TF_PATCH_NV per node; their forces are those less the zero-slip force, in the slip's frame).
 * Copies the data; NULL on bad input. */
TF_API tf_patch *tf_patch_new(const int *n, const double *axes, const double *q,
                              const double *f0, const double *values);
/* A patch table with water-depth layers: nd >= 1 layers at the water depths depth[nd] [m]
 * (strictly ascending from 0, the dry road), f0 and values each nd of tf_patch_new's one after
 * another (tabulated on the wet branch of the grid at each depth, docs/realtime.md). */
TF_API tf_patch *tf_patch_new_wet(const int *n, int nd, const double *depth, const double *axes,
                                  const double *q, const double *f0, const double *values);
/* The full model's depth law between neighbouring layers of a table with nd >= 2 layers:
 * law[(nd - 1) * nodes] (C order, the layer interval outermost, then the axes), the curvature
 * kappa in [-1, 1] at each node: at the fraction f of the way from a layer's depth to the
 * next the table reads the two layers with the weights 1 - s and s, s = f - kappa f (1 - f),
 * the share of the way the full model's friction has moved between them (its wet branch is
 * the product of two interpolations linear in the depth: docs/realtime.md). Without it the
 * weights are 1 - f and f. Copies the data; 0, or -1 on bad input. */
TF_API int tf_patch_set_depth_law(tf_patch *pt, const double *law);
TF_API void tf_patch_free(tf_patch *pt);
/* A patch table from its file's bytes (tire_brush.realtime.PatchTable.to_bytes, format 3,
 * little endian: the magic "TIREFRIC-PATCH\0\3"; int32 the number of water-depth layers nd,
 * the six axis lengths and a flag (1 when the depth law follows); float64 the depths, the
 * axes, q and the zero-slip force of every layer; float32 the node values of every layer;
 * float64 the depth law when flagged; a uint64 FNV-1a 64 trailer, which the caller checks).
 * NULL when the bytes are not that layout or the tables refuse their content. */
TF_API tf_patch *tf_patch_from_bytes(const unsigned char *b, size_t n);
/* Water-depth layers of a table (1: the dry road only). */
TF_API int tf_patch_layers(const tf_patch *pt);
/* The patch response at the patch's slip velocity (Vx, Vy) and rolling speed Vr [m/s], load
 * Fz > 0 [N], tread temperature T [K] and inclination gamma [rad] (out: TF_PATCH_NOUT).
 * Returns TF_FLAG_T_RANGE when T lies outside the table's temperature axis (read at its
 * edge), else 0. */
TF_API int tf_patch_eval(const tf_patch *pt, double Vx, double Vy, double Vr, double Fz,
                         double T, double gamma, double *out);
/* The same on water of depth d_water [m]: between the two layers about it (linearly, or by
 * the depth law of tf_patch_set_depth_law), clamped to the layers' depths (tf_patch_eval
 * reads depth 0, the dry road). */
TF_API int tf_patch_eval_wet(const tf_patch *pt, double Vx, double Vy, double Vr, double Fz,
                             double T, double gamma, double d_water, double *out);

/* Internal (tirecore.c): the state the real-time sub-step advances, and the sub-step. */
typedef struct {
    double delta[2], Vp[2], F[2], M, psi, wpsi, T_tread;
    int flags;
} tf_rt_state;
void tf_rt_advance(const tf_params *p, const tf_patch *pt, tf_rt_state *s, double h,
                   double Vsx, double Vsy, double V_r, double Fz, double a, double Ts,
                   double mus, double gam, double q_roll, double d_water, double *fin);

#ifdef __cplusplus
}
#endif
#endif
