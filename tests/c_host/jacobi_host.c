/* A plain fixed-step FMI 2.0 co-simulation host in C: what the simplest third-party tool does.
 *
 * Loads each FMU's shared library with dlopen, instantiates it, sets parameters in initialisation
 * mode, then steps every FMU from the same outputs (Jacobi order), zero-order hold, no iteration,
 * no rollback: before each step every input gets the value its source output had after the
 * previous step (or after initialisation), then all FMUs step, then the outputs are read.
 *
 *   jacobi_host PLAN OUT
 *
 * PLAN is a text file, one directive per line (blank lines and lines starting with '#' ignored):
 *   fmu NAME UNZIPPED_DIR MODEL_IDENTIFIER GUID   an FMU (unzipped; binaries/linux64/ID.so)
 *   param NAME VR VALUE                           a Real set in initialisation mode
 *   connect SRC VR_OUT DST VR_IN                  output of SRC feeds input of DST
 *   record NAME VR                                a Real written to OUT after every step
 *   step H                                        communication step (s)
 *   steps N                                       number of steps
 * OUT gets one line per communication point after each step: time, then the recorded values
 * (%.17g). Exit status 0 when every call succeeded and every instance was freed; 1 otherwise.
 * Compiled by the test suite (tests/test_c_host.py) against the FMI 2.0 headers fmpy ships.
 */
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#define MAX_FMUS 8
#define MAX_LINKS 4096

typedef struct {
    char name[64];
    void *lib;
    fmi2Component c;
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *freeInstance;
    fmi2SetupExperimentTYPE *setupExperiment;
    fmi2EnterInitializationModeTYPE *enterInitializationMode;
    fmi2ExitInitializationModeTYPE *exitInitializationMode;
    fmi2TerminateTYPE *terminate;
    fmi2SetRealTYPE *setReal;
    fmi2GetRealTYPE *getReal;
    fmi2DoStepTYPE *doStep;
} Fmu;

typedef struct { int fmu; fmi2ValueReference vr; double value; } Param;
typedef struct { int src; fmi2ValueReference out; int dst; fmi2ValueReference in; double held; } Link;
typedef struct { int fmu; fmi2ValueReference vr; } Record;

static Fmu fmus[MAX_FMUS];
static int n_fmus = 0;
static Param params[MAX_LINKS];
static int n_params = 0;
static Link links[MAX_LINKS];
static int n_links = 0;
static Record records[MAX_LINKS];
static int n_records = 0;

static void logger(fmi2ComponentEnvironment env, fmi2String instance, fmi2Status status, fmi2String category,
                   fmi2String message, ...) {
    (void)env;
    va_list args;
    va_start(args, message);
    fprintf(stderr, "[%s] %s (status %d): ", instance ? instance : "?", category ? category : "", (int)status);
    vfprintf(stderr, message, args);
    fputc('\n', stderr);
    va_end(args);
}

static int find_fmu(const char *name) {
    for (int i = 0; i < n_fmus; i++)
        if (strcmp(fmus[i].name, name) == 0) return i;
    fprintf(stderr, "plan: unknown FMU %s\n", name);
    exit(2);
}

static void *symbol(Fmu *f, const char *name) {
    void *p = dlsym(f->lib, name);
    if (!p) {
        fprintf(stderr, "%s: missing symbol %s\n", f->name, name);
        exit(2);
    }
    return p;
}

static int check(fmi2Status s, const Fmu *f, const char *what) {
    if (s > fmi2Warning) {
        fprintf(stderr, "%s: %s returned status %d\n", f->name, what, (int)s);
        return 1;
    }
    return 0;
}

static const fmi2CallbackFunctions callbacks = {logger, calloc, free, NULL, NULL};

static int load(Fmu *f, const char *dir, const char *id, const char *guid) {
    char path[8400], resources[8400];
    snprintf(path, sizeof path, "%s/binaries/linux64/%s.so", dir, id);
    f->lib = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!f->lib) {
        fprintf(stderr, "%s: dlopen failed: %s\n", f->name, dlerror());
        return 1;
    }
    f->instantiate = (fmi2InstantiateTYPE *)symbol(f, "fmi2Instantiate");
    f->freeInstance = (fmi2FreeInstanceTYPE *)symbol(f, "fmi2FreeInstance");
    f->setupExperiment = (fmi2SetupExperimentTYPE *)symbol(f, "fmi2SetupExperiment");
    f->enterInitializationMode = (fmi2EnterInitializationModeTYPE *)symbol(f, "fmi2EnterInitializationMode");
    f->exitInitializationMode = (fmi2ExitInitializationModeTYPE *)symbol(f, "fmi2ExitInitializationMode");
    f->terminate = (fmi2TerminateTYPE *)symbol(f, "fmi2Terminate");
    f->setReal = (fmi2SetRealTYPE *)symbol(f, "fmi2SetReal");
    f->getReal = (fmi2GetRealTYPE *)symbol(f, "fmi2GetReal");
    f->doStep = (fmi2DoStepTYPE *)symbol(f, "fmi2DoStep");
    snprintf(resources, sizeof resources, "file://%s/resources", dir);
    f->c = f->instantiate(f->name, fmi2CoSimulation, guid, resources, &callbacks, fmi2False, fmi2True);
    if (!f->c) {
        fprintf(stderr, "%s: fmi2Instantiate returned NULL\n", f->name);
        return 1;
    }
    return 0;
}

static int read_outputs(void) {
    for (int k = 0; k < n_links; k++) {
        Fmu *f = &fmus[links[k].src];
        if (check(f->getReal(f->c, &links[k].out, 1, &links[k].held), f, "fmi2GetReal")) return 1;
    }
    return 0;
}

int main(int argc, char **argv) {
    if (argc != 3) {
        fprintf(stderr, "usage: %s PLAN OUT\n", argv[0]);
        return 2;
    }
    FILE *plan = fopen(argv[1], "r");
    if (!plan) {
        perror(argv[1]);
        return 2;
    }
    double h = 0.0;
    long steps = 0;
    char line[8192];
    int failed = 0;
    while (fgets(line, sizeof line, plan)) {
        char name[64], a[4096], b[4096], c[4096], d[4096];
        double x;
        unsigned u, v;
        if (line[0] == '#' || line[0] == '\n') continue;
        if (sscanf(line, "fmu %63s %4095s %4095s %4095s", name, b, c, d) == 4) {
            Fmu *f = &fmus[n_fmus++];
            memcpy(f->name, name, sizeof f->name);
            if (load(f, b, c, d)) return 1;
        } else if (sscanf(line, "param %4095s %u %lf", a, &u, &x) == 3) {
            params[n_params++] = (Param){find_fmu(a), u, x};
        } else if (sscanf(line, "connect %4095s %u %4095s %u", a, &u, b, &v) == 4) {
            links[n_links++] = (Link){find_fmu(a), u, find_fmu(b), v, 0.0};
        } else if (sscanf(line, "record %4095s %u", a, &u) == 2) {
            records[n_records++] = (Record){find_fmu(a), u};
        } else if (sscanf(line, "step %lf", &x) == 1) {
            h = x;
        } else if (sscanf(line, "steps %ld", &steps) == 1) {
        } else {
            fprintf(stderr, "plan: cannot read line: %s", line);
            return 2;
        }
    }
    fclose(plan);
    FILE *out = fopen(argv[2], "w");
    if (!out) {
        perror(argv[2]);
        return 2;
    }
    for (int i = 0; i < n_fmus && !failed; i++) {
        Fmu *f = &fmus[i];
        failed |= check(f->setupExperiment(f->c, fmi2False, 0.0, 0.0, fmi2True, h * steps), f, "fmi2SetupExperiment");
        failed |= check(f->enterInitializationMode(f->c), f, "fmi2EnterInitializationMode");
    }
    for (int k = 0; k < n_params && !failed; k++) {
        Fmu *f = &fmus[params[k].fmu];
        failed |= check(f->setReal(f->c, &params[k].vr, 1, &params[k].value), f, "fmi2SetReal (parameter)");
    }
    for (int i = 0; i < n_fmus && !failed; i++)
        failed |= check(fmus[i].exitInitializationMode(fmus[i].c), &fmus[i], "fmi2ExitInitializationMode");
    if (!failed) failed |= read_outputs();
    double t = 0.0;
    for (long n = 0; n < steps && !failed; n++) {
        for (int k = 0; k < n_links && !failed; k++) {
            Fmu *f = &fmus[links[k].dst];
            failed |= check(f->setReal(f->c, &links[k].in, 1, &links[k].held), f, "fmi2SetReal");
        }
        for (int i = 0; i < n_fmus && !failed; i++)
            failed |= check(fmus[i].doStep(fmus[i].c, t, h, fmi2True), &fmus[i], "fmi2DoStep");
        t = (n + 1) * h;
        if (!failed) failed |= read_outputs();
        fprintf(out, "%.17g", t);
        for (int k = 0; k < n_records && !failed; k++) {
            Fmu *f = &fmus[records[k].fmu];
            double value;
            failed |= check(f->getReal(f->c, &records[k].vr, 1, &value), f, "fmi2GetReal");
            fprintf(out, " %.17g", value);
        }
        fputc('\n', out);
    }
    fclose(out);
    for (int i = 0; i < n_fmus; i++) {
        Fmu *f = &fmus[i];
        if (f->c) {
            failed |= check(f->terminate(f->c), f, "fmi2Terminate");
            f->freeInstance(f->c);
            f->c = NULL;
        }
    }
    for (int i = n_fmus - 1; i >= 0; i--) dlclose(fmus[i].lib);
    fprintf(stderr, "jacobi_host: %s\n", failed ? "failed" : "done");
    return failed ? 1 : 0;
}
