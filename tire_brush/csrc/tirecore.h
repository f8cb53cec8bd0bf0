/*
 * tirecore: the transient brush tire of tirefric as a small C99 library.
 *
 * Tread elements (tip mass on a Kelvin-Voigt shear spring to the belt) cross the contact
 * patch; each sticks or slides with the friction of the review's eq. (28) (cold and hot
 * branch blended by the slipped distance), read from a table on (log10 v, T, log10 p).
 * The belt is a massless ring on springs and dampers against the rim; the tread carries an
 * optional lumped temperature. docs/tire-core.md describes the method; the Python module
 * tire_brush/element.py is its readable reference, pinned to this file by the tests.
 *
 * No global state: every function works on the objects it is given, so several tires run in
 * one process. No allocation after tf_tire_new. The library needs only libm.
 */
#ifndef TIRECORE_H
#define TIRECORE_H

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define TF_API __declspec(dllexport)
#else
#define TF_API __attribute__((visibility("default")))
#endif

/* Version of this API and of the state layout (tf_tire_get_state). */
#define TF_VERSION 5
/* Shortest step [s] that advances the tire: a shorter one (subnormal included) only advances
 * the clock and leaves state and outputs as they are (nothing in the model moves in 1 ns:
 * the element sub-steps stop at 10 ns), so outputs are continuous as the step -> 0. */
#define TF_DT_FLOOR 1e-9
/* Inputs of tf_tire_step, in order: vx, vy [m/s], omega [rad/s], Fz [N], T_surface [K],
 * mu_scale [1], gamma (inclination angle) [rad], water_depth [m] (0: dry; read through the
 * wet branch, tf_tire_set_wet, and ignored without one). */
#define TF_NIN 8
/* Outputs of tf_tire_step, in order: Fx, Fy [N], Mz [N m], kappa [1], alpha [rad], mu_eff,
 * mu_slide, sliding_fraction [1], dT_flash_max [K], T_tread [K], Mx, My [N m] (overturning
 * moment of the belt's lateral deflection, rolling resistance moment; adapted SAE axes like
 * the rest: My > 0 opposes rolling forward). Fx, Fy, Mz are the friction
 * impulse of the step over its length when the step is at least dt_internal long; a shorter
 * step dt moves them towards its own mean by dt / dt_internal (a first-order relaxation with
 * time constant dt_internal), so the outputs change by O(dt) as dt -> 0. */
#define TF_NOUT 12
/* Columns of one lattice element in the state: u_x, u_y [m], w_x, w_y [m/s], s [m],
 * last sub-step [s], in contact (0/1), contact age theta [s] (0 unless contact_ageing). */
#define TF_ELEM 8
/* Columns of one steady operating point (tf_steady): V_sx, V_sy, V_r [m/s], Fz [N],
 * gamma [rad]. */
#define TF_STEADY_IN 5
/* Results of one steady point: Fx, Fy, Mz, mu_eff, mu_slide, sliding_fraction,
 * dT_flash_max, sub-steps taken, friction power [W] (the friction work on the road per unit
 * time: the heat of the patch, of which heat_fraction enters the tread), the moment of the
 * tread's stress on the belt [N m] (Mz less the moment of the momentum the tread carries
 * through the patch; it yaws the belt). */
#define TF_STEADY_OUT 10

typedef struct tf_table tf_table;
typedef struct tf_wet tf_wet;
typedef struct tf_tire tf_tire;
typedef struct tf_patch tf_patch;

/* Tire parameters, SI units (tire_brush/params.py documents each field). */
typedef struct {
    double R_e, Fz_nom;
    /* patch law, Pacejka 2012 eqs. (A3.7)-(A3.8), vertical stiffness with the inflation
     * pressure (MF 6.2: C_z (1 + p_fz1 (p_inflation - p_nom) / p_nom)), pressure shape
     * (flat centre at most 1 - end_zone of the half-length, docs/tire-core.md) */
    double R0, width, C_z, q_ra1, q_ra2, q_rb1, q_rb2, Fz_max, p_inflation, p_nom, p_fz1,
        end_zone;
    /* tread elements per unit area; groove depth [m] (hydroplaning) */
    double k_x, k_y, mass, d_x, d_y, void_ratio, tread_depth;
    /* belt on the rim */
    int rigid;
    double kc_x, kc_y, dc_x, dc_y;
    /* belt yaw (twist) on the rim: stiffness [N m/rad], damping [N m s/rad] */
    double kc_psi, dc_psi;
    /* camber: share eps of the tilted disk's path curvature sin(gamma) / R_e that the belt
     * does not follow (Pacejka 2012, ch. 3 and 4: the base spins at -(1 - eps) omega sin gamma) */
    double camber_reduction;
    /* lumped tread temperature */
    int thermal;
    double heat_capacity, conductance, heat_fraction;
    /* discretisation */
    int n_elements;     /* elements on the patch at Fz_nom */
    double dt_internal; /* longest outer (belt and lattice) step [s]; shorter where the belt
                         * coupling needs it (docs/tire-core.md) */
    double tol;         /* local error tolerance of the element integration [1] */
    double v_floor;     /* speed floor of the reported slips [m/s] */
    /* contact age (docs/tire-core.md, "contact age"): the element reads the friction at
     * v_eff = D / theta, theta its contact age (Dieterich's ageing law), D = s0 / 0.2 of the
     * table (0: the friction at |w|; a table with inv_s0 = 0 has no D and reads |w| too) */
    int contact_ageing;
} tf_params;

/* Friction table: axes (uniform or not, strictly ascending) and node values
 * values[((iv * nT + iT) * np + ip) * 3 + k], k = mu_cold, mu_hot, dT_flash.
 * inv_s0 = 1/s0 of eq. (28) [1/m] (0: cold only). Copies the data; NULL on bad input. */
TF_API tf_table *tf_table_new(int nv, int nT, int np, const double *log10_v, const double *T,
                              const double *log10_p, const double *values, double inv_s0);
TF_API void tf_table_free(tf_table *t);

/* Wet branch of a friction table (docs/tire-core.md, "wet road"): over the water depth
 * (nd nodes, depth[0] = 0, dry) and log10 of the drainage time (nt nodes), on the nv x nT x np
 * nodes of the friction table it is given to (tf_tire_set_wet; the axes and dT_flash are
 * that table's):
 * mu[(((id * nv + iv) * nT + iT) * np + ip) * 4 + k], k = cold and hot with the adhesive term
 * off (w = 0) and on (w = 1): cold_w0, cold_w1, hot_w0, hot_w1 (all >= 0);
 * w_dry[(((id * nt + it) * nv + iv) * nT + iT) * np + ip], the dry share of the real contact.
 * Read: mu = (1 - w) mu_w0 + w mu_w1, w clipped to [0, 1], multilinear in (depth, log10 t)
 * at the nodes. The drainage time is drain_scale times the time the water film spends under
 * the footprint, 2a / U at the entrainment speed U = (|vx| + |V_r|) / 2
 * (tire_brush.wet_friction; drain_scale = (D / 2R)^2, 1 for draining over D / 2). Hydroplaning
 * (Horne, NASA TN D-2056): the water carries the share s(d) min(1, (|vx| / V_p)^2) of the
 * load, V_p = 6.35 sqrt(p_inflation / kPa) km/h, s rising linearly from 0 at the depth the
 * grooves and the road's texture hold (void_ratio tread_depth + texture_depth,
 * tf_tire_set_wet) to 1 d_full above.
 * Copies the data; NULL on bad input. */
TF_API tf_wet *tf_wet_new(int nv, int nT, int np, int nd, int nt, const double *depth,
                          const double *log10_t, const double *mu, const double *w_dry,
                          double d_full, double drain_scale);
TF_API void tf_wet_free(tf_wet *w);

/* A tire on a table (the table must outlive the tire). NULL on bad parameters. */
TF_API tf_tire *tf_tire_new(const tf_params *p, const tf_table *t);
TF_API void tf_tire_free(tf_tire *tire);
/* Undeflected tire at rest; tread temperature T_tread [K] (NaN: the next step's T_surface). */
TF_API void tf_tire_reset(tf_tire *tire, double T_tread);
/* Advance by dt [s] with the TF_NIN inputs held (dt < TF_DT_FLOOR: only the clock advances).
 * Writes TF_NOUT outputs. Returns 0, or -1 for inputs it refuses (non-finite, dt < 0,
 * T_surface <= 0, mu_scale < 0, |gamma| >= pi/2, water_depth < 0, a step of more outer steps
 * than an int counts), leaving the state unchanged. The work of each outer step is bounded
 * (TF_BUDGET); tf_tire_flags says what the step reported. */
TF_API int tf_tire_step(tf_tire *tire, double dt, const double *in, double *out);
/* Rolling resistance (optional; NULL removes it): a table on (log10 |V_r| [m/s], T_tread [K],
 * log10 Fz [N]) whose node values are (f_r, tread_share, unused): the coefficient F_r / Fz
 * and the share of the loss dissipated in the tread (heat into T_tread). My = f_r Fz R_e,
 * falling linearly to 0 below the first speed node (a viscoelastic solid's loss modulus is
 * linear in frequency at low frequency). The table must outlive the tire. Returns 0 or -1. */
TF_API int tf_tire_set_rolling(tf_tire *tire, const tf_table *rr);
/* Wet branch (or NULL: every water depth reads the dry table) and the road's mean texture
 * depth [m] (the water it holds, hydroplaning); the branch must have the nodes of the tire's
 * friction table and outlive the tire. Returns 0 or -1. */
TF_API int tf_tire_set_wet(tf_tire *tire, const tf_wet *w, double texture_depth);
/* Fidelity (docs/realtime.md): with a patch table (tirert.h; NULL: the full model again) the
 * tire steps in the real-time fidelity: the patch quasi-steady, read from the table, on the
 * belt's translation and yaw with the tread's transit lag, the same tread temperature, outputs,
 * flags and state vector (its lattice unused; the belt slip velocity slots hold the patch's
 * slip velocity). Sub-steps no longer than dt_internal. The wet branch is not read in this
 * fidelity (hydroplaning's lift of the load is). The table must outlive the tire. Returns 0
 * or -1. */
TF_API int tf_tire_set_patch(tf_tire *tire, const tf_patch *pt);
/* Lattice size, doubles in the state, and the state itself (copy out / in). */
TF_API int tf_tire_lattice(const tf_tire *tire);
TF_API int tf_tire_state_size(const tf_tire *tire);
TF_API void tf_tire_get_state(const tf_tire *tire, double *buf);
TF_API int tf_tire_set_state(tf_tire *tire, const double *buf);
/* Sub-steps taken by the elements since creation (a work counter for benchmarks). */
TF_API double tf_tire_work(const tf_tire *tire);
/* Work budget of one outer step (docs/tire-core.md, "work budget"): at most TF_BUDGET element
 * sub-step attempts (accepted or rejected SDIRK steps, event steps) per element of the nominal
 * patch (n_elements); once spent, every element still to integrate in that outer step finishes
 * it with one implicit Euler stage. An outer step thus solves at most
 * 2 TF_BUDGET n_elements + (lattice size) stages, each with a bounded number of residual
 * evaluations. */
#define TF_BUDGET 24
/* Flags of the last step (tf_tire_flags): the work budget of an outer step was spent; the
 * friction was read at a temperature (the tread's, or T_surface without the thermal state)
 * outside the table's temperature axis (at its edge's values). */
#define TF_FLAG_BUDGET 1
#define TF_FLAG_T_RANGE 2
TF_API int tf_tire_flags(const tf_tire *tire);
/* Counters since creation: element sub-steps taken (tf_tire_work), stage solves (two per SDIRK
 * attempt, one per event step or budget fallback), budget fallbacks (TF_NCOUNT doubles). */
#define TF_NCOUNT 3
TF_API void tf_tire_counters(const tf_tire *tire, double *out);

/* Steady state of n operating points (one element marched through the patch over n_cells
 * cells, belt at rest), at background temperature T [K] and friction scale mu_scale:
 * in[i * TF_STEADY_IN + ...], out[i * TF_STEADY_OUT + ...]. Returns 0 or -1. */
TF_API int tf_steady(const tf_params *p, const tf_table *t, int n_cells, int n, const double *in,
                     double T, double mu_scale, double *out);

#ifdef __cplusplus
}
#endif
#endif
