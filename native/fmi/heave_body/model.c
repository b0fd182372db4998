/* A one-body heave integrator behind the FMI glue (cosimulation.h): what a third-party multibody code does.
 *
 *     (m + A_inf) x'' = F0 + F0_rate (t - t_n) - c x' + dF_dx x + dF_dv x'
 *
 * over each communication step [t_n, t_n + h], with the hydro FMU's linearised force held for the step, integrated
 * by the trapezoidal rule (implicit, second order, A-stable) on SUBSTEPS equal sub-steps: the coupling is then
 * implicit in the hydrostatic stiffness and the instantaneous radiation damping. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config.h"
#include "cosimulation.h"

typedef struct {
    double x, v, time, anchor, step, start;
    uint64_t count;
} body_state;

struct fmu_model {
    double mass, added_mass, damping;
    double f0, f0_rate, dfdx, dfdv;
    body_state s;
};

fmu_status model_instantiate(fmu_instance *instance)
{
    fmu_model *m = calloc(1, sizeof *m);
    if (m == NULL)
        return FMU_ERROR;
    instance->model = m;
    return model_reset(instance);
}

fmu_status model_check_token(fmu_instance *instance, const char *token)
{
    if (token != NULL && strcmp(token, HEAVE_BODY_TOKEN) == 0)
        return FMU_OK;
    fmu_log(instance, FMU_ERROR, "logError", "GUID %s is not this FMU's (%s)", token != NULL ? token : "(null)",
            HEAVE_BODY_TOKEN);
    return FMU_ERROR;
}

void model_free(fmu_instance *instance)
{
    free(instance->model);
    instance->model = NULL;
}

/* The parameters' start values (the model description's), from resources/parameters.txt: "mass A_inf c". */
fmu_status model_reset(fmu_instance *instance)
{
    fmu_model *m = instance->model;
    memset(m, 0, sizeof *m);
    size_t size = 0;
    char *text = (char *)fmu_read_resource(instance, PARAMETER_RESOURCE, &size);
    if (text == NULL)
        return FMU_ERROR;
    char *terminated = realloc(text, size + 1);
    if (terminated == NULL) {
        free(text);
        return FMU_ERROR;
    }
    terminated[size] = '\0';
    int read = sscanf(terminated, "%lf %lf %lf", &m->mass, &m->added_mass, &m->damping);
    free(terminated);
    if (read != 3) {
        fmu_log(instance, FMU_ERROR, "logError", "resources/%s: expected three numbers (mass, A_inf, pto_damping)",
                PARAMETER_RESOURCE);
        return FMU_ERROR;
    }
    return FMU_OK;
}

fmu_status model_exit_initialization(fmu_instance *instance)
{
    fmu_model *m = instance->model;
    if (!(m->mass + m->added_mass > 0) || !(m->damping >= 0)) {
        fmu_log(instance, FMU_ERROR, "logError", "mass + added_mass must be positive and pto_damping >= 0 (got %g, "
                "%g, %g)", m->mass, m->added_mass, m->damping);
        return FMU_ERROR;
    }
    return FMU_OK;
}

static double *slot(fmu_model *m, uint32_t vr)
{
    switch (vr) {
    case VR_MASS: return &m->mass;
    case VR_ADDED_MASS: return &m->added_mass;
    case VR_DAMPING: return &m->damping;
    case VR_F0: return &m->f0;
    case VR_F0_RATE: return &m->f0_rate;
    case VR_DF_DX: return &m->dfdx;
    case VR_DF_DV: return &m->dfdv;
    case VR_X: return &m->s.x;
    case VR_V: return &m->s.v;
    default: return NULL;
    }
}

fmu_status model_get_float64(fmu_instance *instance, uint32_t vr, double *value)
{
    fmu_model *m = instance->model;
    if (vr == VR_POWER) {
        *value = m->damping * m->s.v * m->s.v;
        return FMU_OK;
    }
    double *p = slot(m, vr);
    if (p == NULL) {
        fmu_log(instance, FMU_ERROR, "logError", "value reference %u is not a variable of this FMU", (unsigned)vr);
        return FMU_ERROR;
    }
    *value = *p;
    return FMU_OK;
}

fmu_status model_set_float64(fmu_instance *instance, uint32_t vr, double value)
{
    fmu_model *m = instance->model;
    double *p = vr == VR_X || vr == VR_V ? NULL : slot(m, vr);
    int parameter = vr == VR_MASS || vr == VR_ADDED_MASS || vr == VR_DAMPING;
    if (p == NULL || (parameter && instance->phase == FMU_STEPPING)) {
        fmu_log(instance, FMU_ERROR, "logError", "value reference %u is not settable now", (unsigned)vr);
        return FMU_ERROR;
    }
    if (!isfinite(value)) {
        fmu_log(instance, FMU_ERROR, "logError", "value reference %u set to %g: values must be finite", (unsigned)vr,
                value);
        return FMU_ERROR;
    }
    *p = value;
    return FMU_OK;
}

fmu_status model_float64_elements(fmu_instance *instance, uint32_t vr, uint32_t *first, size_t *count)
{
    double value;
    if (model_get_float64(instance, vr, &value) != FMU_OK)
        return FMU_ERROR;
    *first = vr;
    *count = 1;
    return FMU_OK;
}

fmu_status model_do_step(fmu_instance *instance, double h)
{
    fmu_model *m = instance->model;
    double total = m->mass + m->added_mass;
    double k = m->dfdx / total, d = (m->dfdv - m->damping) / total, hs = h / SUBSTEPS, a = hs / 2;
    /* (I - a J) y1 = (I + a J) y0 + a (g0 + g1), J = [[0, 1], [k, d]], g(s) = [0, (F0 + F0_rate s) / total] */
    double a00 = 1.0, a01 = -a, a10 = -a * k, a11 = 1.0 - a * d, det = a00 * a11 - a01 * a10;
    double x = m->s.x, v = m->s.v;
    for (int j = 0; j < SUBSTEPS; j++) {
        double g = (2.0 * m->f0 + m->f0_rate * hs * (2.0 * j + 1.0)) / total;
        double r0 = x + a * v, r1 = v + a * (k * x + d * v) + a * g;
        x = (r0 * a11 - a01 * r1) / det;
        v = (a00 * r1 - a10 * r0) / det;
    }
    if (!isfinite(x) || !isfinite(v)) {
        fmu_log(instance, FMU_ERROR, "logError", "step at t = %g s: the motion is no longer finite", instance->time);
        return FMU_ERROR;
    }
    m->s.x = x;
    m->s.v = v;
    return FMU_OK;
}

fmu_status model_partial(fmu_instance *instance, uint32_t unknown, uint32_t known, double *value)
{
    (void)known;
    (void)value;
    fmu_log(instance, FMU_ERROR, "logError", "no directional derivative of %u: x and v depend on no input at the "
            "same instant", (unsigned)unknown);
    return FMU_ERROR;
}

/* ---- FMU state: the motion and the clock ---- */

fmu_status model_state_get(fmu_instance *instance, void **state)
{
    body_state *s = *state != NULL ? (body_state *)*state : malloc(sizeof *s);
    if (s == NULL)
        return FMU_ERROR;
    *s = instance->model->s;
    s->time = instance->time;
    s->anchor = instance->anchor;
    s->step = instance->step;
    s->start = instance->start_time;
    s->count = instance->count;
    *state = s;
    return FMU_OK;
}

fmu_status model_state_set(fmu_instance *instance, const void *state)
{
    const body_state *s = (const body_state *)state;
    instance->model->s = *s;
    instance->time = s->time;
    instance->anchor = s->anchor;
    instance->step = s->step;
    instance->start_time = s->start;
    instance->count = s->count;
    return FMU_OK;
}

void model_state_free(void *state) { free(state); }

fmu_status model_state_size(fmu_instance *instance, const void *state, size_t *size)
{
    (void)instance;
    (void)state;
    *size = sizeof(body_state);
    return FMU_OK;
}

fmu_status model_state_serialize(fmu_instance *instance, const void *state, unsigned char *bytes, size_t size)
{
    if (size != sizeof(body_state)) {
        fmu_log(instance, FMU_ERROR, "logError", "serialised state: %zu bytes, expected %zu", size,
                sizeof(body_state));
        return FMU_ERROR;
    }
    memcpy(bytes, state, size);
    return FMU_OK;
}

fmu_status model_state_deserialize(fmu_instance *instance, const unsigned char *bytes, size_t size, void **state)
{
    if (size != sizeof(body_state)) {
        fmu_log(instance, FMU_ERROR, "logError", "serialised state: %zu bytes, expected %zu", size,
                sizeof(body_state));
        return FMU_ERROR;
    }
    body_state *s = *state != NULL ? (body_state *)*state : malloc(sizeof *s);
    if (s == NULL)
        return FMU_ERROR;
    memcpy(s, bytes, size);
    *state = s;
    return FMU_OK;
}
