/*
 * A host on the FMI import layer of the Modelica Reference FMUs (src/FMI.c, src/FMI2.c: the
 * library their fmusim is built on; not shipped here, see tests/test_fmu_native_hosts.py).
 * Loads the native FMU, steps it with a rollback through serialize/deserialize and prints the
 * forces of the first run and of the replay (they must be equal).
 * argv: binary, resources URI, GUID, steps.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "FMI2.h"

static void log_message(FMIInstance *i, FMIStatus s, const char *c, const char *m) {
    (void)i; (void)c;
    if (s > FMIOK) fprintf(stderr, "[%d] %s\n", (int)s, m);
}

#define CHECK(x) do { if ((x) > FMIWarning) { fprintf(stderr, "failed: %s\n", #x); return 4; } } while (0)

int main(int argc, char **argv) {
    if (argc < 5) return 1;
    FMIInstance *S = FMICreateInstance("tire", log_message, NULL);
    if (!S || FMILoadPlatformBinary(S, argv[1]) != FMIOK) return 2;
    CHECK(FMI2Instantiate(S, argv[2], fmi2CoSimulation, argv[3], fmi2False, fmi2False));
    CHECK(FMI2SetupExperiment(S, fmi2False, 0.0, 0.0, fmi2False, 0.0));
    CHECK(FMI2EnterInitializationMode(S));
    CHECK(FMI2ExitInitializationMode(S));
    int n = atoi(argv[4]);
    const fmi2ValueReference vin[8] = {0, 1, 2, 3, 4, 5, 6, 7}, vout[3] = {8, 9, 10};
    double u[8] = {20.0, 0.3, 20.0 * 0.95 / 0.31, 4000.0, 293.15, 1.0, 0.0, 0.0}, y[3],
           first[3];
    fmi2FMUstate st = NULL;
    size_t size = 0;
    fmi2Byte *blob = NULL;
    for (int k = 0; k < n; k++) {
        if (k == n / 2) {
            CHECK(FMI2GetFMUstate(S, &st));
            CHECK(FMI2SerializedFMUstateSize(S, st, &size));
            blob = malloc(size);
            CHECK(FMI2SerializeFMUstate(S, st, blob, size));
        }
        CHECK(FMI2SetReal(S, vin, 8, u));
        CHECK(FMI2DoStep(S, k * 1e-3, 1e-3, fmi2True));
    }
    CHECK(FMI2GetReal(S, vout, 3, first));
    fmi2FMUstate st2 = NULL;
    CHECK(FMI2DeSerializeFMUstate(S, blob, size, &st2));
    CHECK(FMI2SetFMUstate(S, st2));
    for (int k = n / 2; k < n; k++) {
        CHECK(FMI2SetReal(S, vin, 8, u));
        CHECK(FMI2DoStep(S, k * 1e-3, 1e-3, fmi2True));
    }
    CHECK(FMI2GetReal(S, vout, 3, y));
    printf("%.17g %.17g %.17g\n%.17g %.17g %.17g\n", first[0], first[1], first[2], y[0], y[1],
           y[2]);
    FMI2FreeFMUstate(S, &st);
    FMI2FreeFMUstate(S, &st2);
    free(blob);
    FMI2Terminate(S);
    FMI2FreeInstance(S);
    FMIFreeInstance(S);
    return 0;
}
