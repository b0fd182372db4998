/* The FMI-version-independent part of wec-cosim's native co-simulation FMUs (after the Modelica Reference-FMUs:
 * fmi2Functions.c and fmi3Functions.c translate the FMI calls onto this, each FMU's model.c supplies the physics).
 *
 * An instance holds the host's callbacks (through a logger function set by the FMI glue), the resource folder, the
 * FMU's own clock (communication points t = anchor + count * step counted from the last change of step: no
 * accumulated round-off, the same in every host that passes the same steps) and the model's data. */
#ifndef WEC_FMI_COSIMULATION_H
#define WEC_FMI_COSIMULATION_H

#include <stddef.h>
#include <stdint.h>

#define FMU_PATH_SIZE 4096
#define FMU_MESSAGE_SIZE 1024

/* Status of the glue and the model: the FMI status values shared by FMI 2.0 and 3.0. */
typedef enum { FMU_OK = 0, FMU_WARNING = 1, FMU_ERROR = 3, FMU_FATAL = 4 } fmu_status;

typedef enum {
    FMU_INSTANTIATED,       /* after instantiate: parameters may be set */
    FMU_INITIALIZATION,     /* between enter and exit initialisation mode */
    FMU_STEPPING,           /* step mode */
    FMU_TERMINATED,
    FMU_FAILED              /* a step failed: only getters, reset and free are allowed */
} fmu_phase;

typedef struct fmu_instance fmu_instance;
typedef void (*fmu_log_function)(fmu_instance *instance, fmu_status status, const char *category,
                                 const char *message);

typedef struct fmu_model fmu_model; /* defined by each FMU's model.c */

struct fmu_instance {
    char name[256];
    char resources[FMU_PATH_SIZE]; /* the resource folder as a plain path, with a trailing '/' */
    fmu_log_function log;          /* set by the FMI glue */
    void (*host_logger)(void);     /* the host's logger (cast to its FMI type by the glue) and environment */
    void *host_environment;
    int logging_on;
    int fmi_version;               /* 2 or 3 */
    fmu_phase phase;
    double start_time;
    double anchor, step;           /* the clock: time = anchor + count * step */
    uint64_t count;
    double time;
    fmu_model *model;
};

/* Logs a message (printf format) with the instance's logger; category "logError" for errors, "logStatusWarning",
 * "logEvents" (debug, only when logging is on). */
void fmu_log(fmu_instance *instance, fmu_status status, const char *category, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* The resource folder of a file URI ("file:///a/b", "file:/a/b", "file://localhost/a/b"; %xx decoded) or of a
 * plain path into instance->resources; FMU_ERROR with a logged reason otherwise. */
fmu_status fmu_set_resources(fmu_instance *instance, const char *location);

/* The bytes of the file `name` in the resource folder (malloc'd; *size set) or NULL with a logged reason. */
unsigned char *fmu_read_resource(fmu_instance *instance, const char *name, size_t *size);

/* Sets the clock to the start time. */
void fmu_clock_start(fmu_instance *instance, double start_time);

/* The decision on a step request from the host at current_time with step h:
 * FMU_OK with *take = 1: a regular step to take from instance->time;
 * FMU_OK with *take = 0: a final step shorter than 1e-9 of the last regular step (the floating-point remainder of a
 *     host's time, e.g. OMSimulator's), accepted without moving the model;
 * FMU_ERROR with a logged reason: a step that cannot be taken (not positive, not finite, or not starting at the
 *     FMU's current time). */
fmu_status fmu_step_request(fmu_instance *instance, double current_time, double h, int *take);

/* Moves the clock on by h after a regular step. */
void fmu_clock_advance(fmu_instance *instance, double h);

/* ---- The model (each FMU's model.c) ---- */

/* Reads the resources, makes the model (instance->model); FMU_ERROR with a logged reason. */
fmu_status model_instantiate(fmu_instance *instance);
void model_free(fmu_instance *instance);
/* Checks the host's GUID (FMI 2.0) or instantiation token (FMI 3.0) against the one the resources were built with:
 * the model description and the resources must come from the same build. */
fmu_status model_check_token(fmu_instance *instance, const char *token);
/* Back to the state right after instantiate (parameters to their start values). */
fmu_status model_reset(fmu_instance *instance);
/* At the end of initialisation: the model starts at instance->time. */
fmu_status model_exit_initialization(fmu_instance *instance);

/* Scalar float64 access by value reference; FMU_ERROR with a logged reason for an unknown or read-only reference. */
fmu_status model_get_float64(fmu_instance *instance, uint32_t vr, double *value);
fmu_status model_set_float64(fmu_instance *instance, uint32_t vr, double value);
/* FMI 3.0: the scalar references first .. first + count - 1 behind the (array or scalar) variable vr. */
fmu_status model_float64_elements(fmu_instance *instance, uint32_t vr, uint32_t *first, size_t *count);

/* A regular step from instance->time by h (the clock is moved on by the glue); FMU_ERROR with a logged reason. */
fmu_status model_do_step(fmu_instance *instance, double h);

/* d(unknown)/d(known) for a float64 output and a float64 input (0 where the output does not depend on it);
 * FMU_ERROR for references outside the model's directional derivatives. */
fmu_status model_partial(fmu_instance *instance, uint32_t unknown, uint32_t known, double *value);

/* The FMU state (model and clock) as an opaque object: get (new or into *state), set, free, serialise. */
fmu_status model_state_get(fmu_instance *instance, void **state);
fmu_status model_state_set(fmu_instance *instance, const void *state);
void model_state_free(void *state);
fmu_status model_state_size(fmu_instance *instance, const void *state, size_t *size);
fmu_status model_state_serialize(fmu_instance *instance, const void *state, unsigned char *bytes, size_t size);
fmu_status model_state_deserialize(fmu_instance *instance, const unsigned char *bytes, size_t size, void **state);

#endif
