/*
 * Internal header of the native FMU (not part of its API): the instance and snapshot records
 * shared by the FMI glue (fmu_wrapper.c), the model callbacks (tfn_model.c: parameters, the
 * core tire, the input guard, axes, outputs) and the resource readers (tfn_files.c: the
 * friction, wet and rolling-resistance tables). The split follows the Reference FMUs of the
 * Modelica Association: FMI glue in one file, the model behind a few callbacks.
 */
#ifndef TFN_MODEL_H
#define TFN_MODEL_H
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "tirecore.h"
#include "tirert.h"
#include "tfn_config.h"
#include "tfn_interface.h"

/* the inputs, outputs, status bits and guard conditions: tfn_interface.h, generated from the
 * one interface table (fmu_src/make/native_header.py) */
#define TFN_NCOND (TFN_NGUARD + TFN_NMODEL)
#define TFN_MAX_SUBSTEPS 100000.0
#define TFN_TABLE_MAGIC "TIREFRIC-TABLE\0\0" /* 16 bytes */
#define TFN_STATE_MAGIC "TFNSTATE"           /* 8 bytes */
#define TFN_STATE_VERSION 3u

/* the core and the table agree on the inputs and outputs (a compile error otherwise) */
typedef char tfn_check_nin[TFN_NIN == TF_NIN ? 1 : -1];
typedef char tfn_check_nout[TFN_NOUT == TF_NOUT ? 1 : -1];

enum { PH_INSTANTIATED, PH_INIT, PH_STEP, PH_TERMINATED, PH_ERROR };

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
    tf_patch *patch;           /* the real-time fidelity's patch table (NULL: none) */
    tf_tire *tire;
    double built[TFN_NV];      /* values the tire was built from (parameters compared) */
    double *buf;               /* core state scratch */
    int nbuf;
} comp;


/* -- logging (tfn_model.c) --------------------------------------------------------------------- */
void logf_(comp *c, fmi2Status st, const char *fmt, ...);

/* -- resource files (tfn_files.c) ----------------------------------------------------------- */
uint64_t fnv1a(const unsigned char *p, size_t n);
int resource_path(const char *loc, const char *file, char *out, size_t n);
int load_table(comp *c, const char *path);
int load_wet(comp *c, const char *loc);
int load_rolling(comp *c, const char *loc);
int load_patch(comp *c, const char *loc);

/* -- the model (tfn_model.c) --------------------------------------------------------------- */
int make_core(comp *c, const double *v, tf_table **tab, tf_tire **tire);
void adopt_core(comp *c, const double *v, tf_table *tab, tf_tire *tire);
int same_params(const double *a, const double *b);
int guard_apply(comp *c, const double *u, double *x, const char *when);
int model_conditions(comp *c, int fl, double T, const char *when);
void guard_reset(comp *c);
double axis_sign(const comp *c, int quantity);
void outputs_to_axes(const comp *c, double *o);
void initial_outputs(comp *c, const double *x);
int build_model(comp *c);

#endif
