/*
 * FMI 2.0 co-simulation wrapper of the tirefric transient brush tire (the "native" FMU): the FMI
 * glue (life cycle, variables, stepping, FMU state). The model sits behind the callbacks of
 * tfn_model.c, the resource files are read by tfn_files.c (internal header tfn_model.h).
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

#include "tfn_model.h"

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
        load_wet(c, resourceLocation) != 0 || load_patch(c, resourceLocation) != 0) {
        free(c->axes);
        free(c->values);
        if (c->rr) tf_table_free(c->rr);
        if (c->wet) tf_wet_free(c->wet);
        if (c->patch) tf_patch_free(c->patch);
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
    if (c->patch) tf_patch_free(c->patch);
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
    x[TFN_IN_VY] *= axis_sign(c, 0);
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
    x[TFN_IN_VY] *= axis_sign(c, 0);
    int ok = tf_tire_step(c->tire, h, x, out) == 0;
    for (int k = 0; ok && k < TF_NOUT; k++) ok = isfinite(out[k]);
    c->time = t + h;
    if (ok) {
        st |= model_conditions(c, tf_tire_flags(c->tire), out[TFN_OUT_T_TREAD], when);
        outputs_to_axes(c, out);
        memcpy(c->v + TFN_VR_OUTPUT0, out, sizeof out);
        c->v[TFN_VR_STATUS] = st;
        return st ? fmi2Warning : fmi2OK;
    }
    tf_tire_reset(c->tire, NAN);
    initial_outputs(c, x);
    c->v[TFN_VR_STATUS] = st | TFN_BIT_MODEL_RESET;
    char inputs[512];
    size_t used = 0;
    for (int i = 0; i < TFN_NIN && used < sizeof inputs; i++)
        used += (size_t)snprintf(inputs + used, sizeof inputs - used, "%s%s = %g",
                                 i ? ", " : "", TFN_IN_NAME[i], x[i]);
    logf_(c, fmi2Discard, "doStep at t = %.6g s: the tire model failed with inputs %s; it was "
          "reset to an undeflected tire at rest (input_status bit %d)", t, inputs,
          TFN_BIT_MODEL_RESET);
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
