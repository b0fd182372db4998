/* A plain C FMI 2.0 host that drives the native hydro FMU through a forced oscillation: what a third-party tool
 * does with no Python anywhere (tests/test_native_hydro_fmu.py runs it under `env -i`).
 *
 *   forced_motion_host UNZIPPED_DIR GUID DOF AMPLITUDE OMEGA STEP STEPS OUT
 *
 * Loads UNZIPPED_DIR/binaries/linux64/wec_hydro_native.so with dlopen, instantiates it (resources from
 * UNZIPPED_DIR/resources), and at every communication point t_k = k STEP sets the displacement and velocity of the
 * selected degree of freedom DOF (0-based index among the FMU's inputs; the others stay 0) to
 *     x = AMPLITUDE sin(OMEGA t),  v = AMPLITUDE OMEGA cos(OMEGA t),
 * reads the outputs and steps. OUT gets one line per point: t x v F F_exc F_rad F_hs elevation (%.17g) for DOF.
 * Exit status 0 when every call succeeded; 1 otherwise (the FMU's log on stderr). Value references follow
 * native/fmi/hydro/config.h. */
#include <dlfcn.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status, fmi2String category,
                   fmi2String message, ...)
{
    (void)env;
    va_list args;
    va_start(args, message);
    fprintf(stderr, "[%s %d %s] ", instance, (int)status, category);
    vfprintf(stderr, message, args);
    fputc('\n', stderr);
    va_end(args);
}

#define LOAD(name)                                                                                                 \
    name##TYPE *name = (name##TYPE *)dlsym(lib, #name);                                                           \
    if (name == NULL) {                                                                                            \
        fprintf(stderr, "missing %s\n", #name);                                                                    \
        return 1;                                                                                                  \
    }

int main(int argc, char **argv)
{
    if (argc != 9) {
        fprintf(stderr, "usage: %s UNZIPPED_DIR GUID DOF AMPLITUDE OMEGA STEP STEPS OUT\n", argv[0]);
        return 2;
    }
    const char *dir = argv[1], *guid = argv[2];
    unsigned dof = (unsigned)atoi(argv[3]);
    double amplitude = atof(argv[4]), omega = atof(argv[5]), h = atof(argv[6]);
    long steps = atol(argv[7]);
    char path[4096], resources[4200];
    snprintf(path, sizeof path, "%s/binaries/linux64/wec_hydro_native.so", dir);
    snprintf(resources, sizeof resources, "file://%s/resources", dir);
    void *lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        fprintf(stderr, "dlopen %s: %s\n", path, dlerror());
        return 1;
    }
    LOAD(fmi2Instantiate)
    LOAD(fmi2SetupExperiment)
    LOAD(fmi2EnterInitializationMode)
    LOAD(fmi2ExitInitializationMode)
    LOAD(fmi2SetReal)
    LOAD(fmi2GetReal)
    LOAD(fmi2DoStep)
    LOAD(fmi2Terminate)
    LOAD(fmi2FreeInstance)
    fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};
    fmi2Component c = fmi2Instantiate("hydro", fmi2CoSimulation, guid, resources, &callbacks, fmi2False, fmi2False);
    if (c == NULL)
        return 1;
    FILE *out = fopen(argv[8], "w");
    if (out == NULL)
        return 1;
    const fmi2ValueReference in[2] = {1000u + dof, 2000u + dof};
    const fmi2ValueReference outs[5] = {3000u + dof, 4000u + dof, 5000u + dof, 6000u + dof, 1u};
    int ok = fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0) == fmi2OK &&
             fmi2EnterInitializationMode(c) == fmi2OK && fmi2ExitInitializationMode(c) == fmi2OK;
    for (long k = 0; ok && k <= steps; k++) {
        double t = (double)k * h;
        double motion[2] = {amplitude * sin(omega * t), amplitude * omega * cos(omega * t)}, y[5];
        ok = fmi2SetReal(c, in, 2, motion) == fmi2OK && fmi2GetReal(c, outs, 5, y) == fmi2OK;
        if (ok)
            fprintf(out, "%.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", t, motion[0], motion[1], y[0], y[1],
                    y[2], y[3], y[4]);
        if (ok && k < steps)
            ok = fmi2DoStep(c, t, h, fmi2True) == fmi2OK;
    }
    fclose(out);
    ok = ok && fmi2Terminate(c) == fmi2OK;
    fmi2FreeInstance(c);
    dlclose(lib);
    return ok ? 0 : 1;
}
