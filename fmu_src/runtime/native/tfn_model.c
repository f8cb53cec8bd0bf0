/*
 * Model callbacks of the native FMU: logging, the tire's parameters and the core tire built
 * from them, the input guard (a port of fmu_src/runtime/guard.py) and the model's own
 * conditions, the axis systems, the outputs before the first step. The FMI glue
 * (fmu_wrapper.c) calls these; the lists they walk (inputs, status bits, guard conditions)
 * come from tfn_interface.h, generated from the one interface table.
 */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tfn_model.h"

/* -- logging ---------------------------------------------------------------------------------- */
void logf_(comp *c, fmi2Status st, const char *fmt, ...) {
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
    if (!(v[TFN_VR_FIDELITY] == 0.0 || v[TFN_VR_FIDELITY] == 1.0)) {
        logf_(c, fmi2Error, "fidelity = %g must be 0 (full) or 1 (real-time)",
              v[TFN_VR_FIDELITY]);
        bad++;
    } else if (v[TFN_VR_FIDELITY] == 1.0) {
        if (!c->patch) {
            logf_(c, fmi2Error, "fidelity = 1 needs the real-time patch table, which this FMU "
                  "was built without (tirefric fmu build --fidelity realtime)");
            bad++;
        }
        /* the table was built from the steady march at these parameters' start values
         * (fmu_src.runtime.interface.realtime_parameters) */
        for (int i = 0; i < TFN_NV; i++) {
            const char *nm = TFN_VARS[i].name;
            int fixed = strncmp(nm, "tire.patch.", 11) == 0 || strncmp(nm, "tire.tread.", 11) == 0
                        || strcmp(nm, "tire.R_e") == 0 ||
                        strcmp(nm, "tire.carcass.camber_reduction") == 0 || strcmp(nm, "s0") == 0;
            if (fixed && TFN_VARS[i].causality == TFN_PARAMETER && v[i] != TFN_VARS[i].start) {
                logf_(c, fmi2Error, "fidelity = 1: the patch table was built for %s = %g, not "
                      "%g (rebuild the FMU for other values)", nm, TFN_VARS[i].start, v[i]);
                bad++;
            }
        }
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
int make_core(comp *c, const double *v, tf_table **tab, tf_tire **tire) {
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
    if (v[TFN_VR_FIDELITY] == 1.0) tf_tire_set_patch(*tire, c->patch);
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

void adopt_core(comp *c, const double *v, tf_table *tab, tf_tire *tire) {
    if (c->tire) tf_tire_free(c->tire);
    if (c->table) tf_table_free(c->table);
    c->table = tab;
    c->tire = tire;
    memcpy(c->built, v, sizeof c->built);
}

int same_params(const double *a, const double *b) {
    for (int i = 0; i < TFN_NV; i++)
        if (TFN_VARS[i].causality == TFN_PARAMETER && memcmp(&a[i], &b[i], 8) != 0) return 0;
    return 1;
}

/* -- input guard (fmu_src/runtime/guard.py) ----------------------------------------------------------- */
int guard_apply(comp *c, const double *u, double *x, const char *when) {
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
            found[TFN_NONFINITE[i]] = 1;
            x[i] = c->last[i];
        }
    }
    double Fz = x[TFN_IN_FZ], T = x[TFN_IN_T_SURFACE], mu = x[TFN_IN_MU_SCALE];
    static const int speed_in[3] = {TFN_IN_VX, TFN_IN_VY, TFN_IN_OMEGA};
    static const int speed_g[3] = {TFN_G_SPEED_CLAMPED_VX, TFN_G_SPEED_CLAMPED_VY,
                                   TFN_G_SPEED_CLAMPED_OMEGA};
    for (int j = 0; j < 3; j++) {
        int i = speed_in[j];
        double lim = i == TFN_IN_OMEGA ? wmax : vmax;
        if (fabs(x[i]) > lim) {
            found[speed_g[j]] = 1;
            x[i] = copysign(lim, x[i]);
        }
    }
    if (Fz < 0.0) {
        found[TFN_G_NEGATIVE_LOAD] = 1;
        x[TFN_IN_FZ] = 0.0;
    } else if (Fz > Fzmax) {
        found[TFN_G_LOAD_CLAMPED] = 1;
        x[TFN_IN_FZ] = Fzmax;
    }
    if (!(Tmin <= T && T <= Tmax)) {
        found[TFN_G_TEMPERATURE_CLAMPED] = 1;
        x[TFN_IN_T_SURFACE] = fmin(fmax(T, Tmin), Tmax);
    }
    if (!(0.0 <= mu && mu <= mumax)) {
        found[TFN_G_MU_SCALE_CLAMPED] = 1;
        x[TFN_IN_MU_SCALE] = fmin(fmax(mu, 0.0), mumax);
    }
    double *g = &x[TFN_IN_GAMMA], *d = &x[TFN_IN_WATER_DEPTH];
    if (fabs(*g) > gmax) {
        found[TFN_G_CAMBER_CLAMPED] = 1;
        *g = copysign(gmax, *g);
    }
    if (!(0.0 <= *d && *d <= dmax)) {
        found[TFN_G_WATER_CLAMPED] = 1;
        *d = fmin(fmax(*d, 0.0), dmax);
    }
    if (*d > 0.0 && !c->wet) {
        found[TFN_G_NO_WET_BRANCH] = 1;
        *d = 0.0;
    }
    int bits = 0;
    for (int k = 0; k < TFN_NGUARD; k++) {
        any |= found[k];
        any_active |= c->active[k] != 0;
        if (found[k]) bits |= TFN_GUARD_BIT[k];
    }
    if (!any && !any_active) return 0;
    for (int k = 0; k < TFN_NGUARD; k++) {
        if (found[k] && c->active[k]) {
            c->active[k]++;
        } else if (found[k]) {
            c->active[k] = 1;
            int i = TFN_GUARD_INPUT[k], nonfinite = TFN_NONFINITE[i] == k;
            logf_(c, fmi2Warning, "%s: input %s = %g is %s: %s (input_status bit %d; logged "
                  "once until it clears)", when, TFN_IN_NAME[i], raw[i],
                  nonfinite ? "not finite" : k == TFN_G_NEGATIVE_LOAD ? "negative"
                  : k == TFN_G_NO_WET_BRANCH ? "water on the road"
                  : "outside the envelope",
                  nonfinite ? "holding its last finite value" : k == TFN_G_NEGATIVE_LOAD ?
                  "taken as lift-off (Fz = 0, no forces)" : k == TFN_G_NO_WET_BRANCH ?
                  "this FMU's grid has no wet branch, the road is taken as dry" : "clamped",
                  TFN_GUARD_BIT[k]);
        } else if (c->active[k]) {
            logf_(c, fmi2OK, "%s: input condition '%s' cleared after %d step(s)", when,
                  TFN_GUARD_NAME[k], (int)c->active[k]);
            c->active[k] = 0;
        }
    }
    return bits;
}

/* Status bits of the model's conditions in the step just taken (core flags fl, tread
 * temperature T [K]), logged when a condition starts (warning) and when it clears. */
int model_conditions(comp *c, int fl, double T, const char *when) {
    int bits = 0;
    for (int k = 0; k < TFN_NMODEL; k++) {
        int32_t *a = &c->active[TFN_NGUARD + k];
        if (fl & TFN_MODEL_FLAG[k]) {
            bits |= TFN_MODEL_BIT[k];
            if (*a) {
                (*a)++;
            } else {
                *a = 1;
                if (TFN_MODEL_FLAG[k] == TF_FLAG_BUDGET)
                    logf_(c, fmi2Warning, "%s: the element integrator's work budget of an outer "
                          "step was spent: its remaining elements finished it with one "
                          "implicit Euler stage (docs/tire-core.md, \"work budget\"; "
                          "input_status bit %d; logged once until it clears)", when,
                          TFN_MODEL_BIT[k]);
                else
                    logf_(c, fmi2Warning, "%s: the friction was read at a temperature outside "
                          "the friction grid's temperature range [%g, %g] K, at its edge's "
                          "values (T_tread = %g K; input_status bit %d; logged once until it "
                          "clears)", when, c->axes[c->nv], c->axes[c->nv + c->nT - 1], T,
                          TFN_MODEL_BIT[k]);
            }
        } else if (*a) {
            logf_(c, fmi2OK, "%s: model condition '%s' cleared after %d step(s)", when,
                  TFN_MODEL_NAME[k], (int)*a);
            *a = 0;
        }
    }
    return bits;
}

void guard_reset(comp *c) {
    for (int i = 0; i < TFN_NIN; i++) c->last[i] = TFN_VARS[TFN_VR_INPUT0 + i].start;
    memset(c->active, 0, sizeof c->active);
}

/* Factor taking vy, Fy, Mz, My and alpha between the brush's axes (Pacejka's adapted SAE) and
 * those of parameter axes (fmu_src/runtime/interface.py, axis_signs): 0 adapted SAE (all +1),
 * 1 ISO-W (vy, Fy, Mz, My flip; alpha keeps its sign), 2 SAE (alpha flips); Mx and gamma keep
 * their sign in all three. */
double axis_sign(const comp *c, int quantity) {
    int axes = (int)c->v[TFN_VR_AXES];
    if (axes == 1) return quantity == 3 ? 1.0 : -1.0;   /* 0 vy, 1 Fy, 2 Mz, 3 alpha, 4 My */
    if (axes == 2) return quantity == 3 ? -1.0 : 1.0;
    return 1.0;
}

/* Outputs in the brush's axes o[] to those of parameter axes. */
void outputs_to_axes(const comp *c, double *o) {
    o[TFN_OUT_FY] *= axis_sign(c, 1);
    o[TFN_OUT_MZ] *= axis_sign(c, 2);
    o[TFN_OUT_ALPHA] *= axis_sign(c, 3);
    o[TFN_OUT_MY] *= axis_sign(c, 4);
}

/* Outputs of the undeflected tire at guarded inputs x in the brush's axes
 * (tire_brush.slip.slip_from_kinematics). */
void initial_outputs(comp *c, const double *x) {
    double *o = c->v + TFN_VR_OUTPUT0;
    double vx = x[TFN_IN_VX], vy = x[TFN_IN_VY], omega = x[TFN_IN_OMEGA];
    double ref = fabs(vx) >= c->v[TFN_VR_V_FLOOR] ? fabs(vx) : c->v[TFN_VR_V_FLOOR];
    double kappa = (omega * c->v[TFN_VR_R_E] - vx) / ref;
    if (vx < 0.0) kappa = -kappa;
    for (int k = 0; k < TF_NOUT; k++) o[k] = 0.0;
    o[TFN_OUT_KAPPA] = kappa;
    o[TFN_OUT_ALPHA] = atan2(-vy, ref);
    o[TFN_OUT_T_TREAD] = x[TFN_IN_T_SURFACE];
    outputs_to_axes(c, o);
}

int build_model(comp *c) {
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
