/* The native hydrodynamics FMU's model: the compiled runtime (wec_hydro.h) behind the FMI glue (cosimulation.h).
 *
 * Inputs x, v of the n selected degrees of freedom; outputs the force rows, the elevation and the work account
 * (one wec_hydro_outputs call per communication point, made when the first output is read after the inputs or the
 * time changed), the linearised force interface and the directional derivatives (one wec_hydro_linearise call,
 * made when first asked for at a point). A step commits the work at the point and the velocity to the memory
 * (wec_hydro_do_step) at the FMU's own clock; a step the runtime refuses is an error with the runtime's reason. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "config.h"
#include "cosimulation.h"
#include "wec_data.h"
#include "wec_hydro.h"

struct fmu_model {
    unsigned char *data; /* the runtime input (kept for reset) */
    size_t data_size;
    wec_hydro *hydro;
    size_t n;
    double *x, *v;                      /* inputs */
    double *block;                      /* WEC_HYDRO_ROWS x n force rows */
    double power[WEC_HYDRO_COMPONENTS], work[WEC_HYDRO_COMPONENTS], eta;
    double *f0, *rate, *dfdx, *dfdv;    /* linearised force */
    double *a_inf;
    double *constants;                  /* values fixed at build time (fmu.constants) */
    size_t n_constants;
    char token[128];                    /* the GUID / instantiation token of the build (fmu.token) */
    int outputs_fresh, linear_fresh, started;
};

static fmu_status runtime_error(fmu_instance *instance, const char *what)
{
    fmu_log(instance, FMU_ERROR, "logError", "%s at t = %.15g s: %s", what, instance->time,
            wec_hydro_last_error(instance->model->hydro));
    return FMU_ERROR;
}

static void release(fmu_model *m)
{
    wec_hydro_free(m->hydro);
    free(m->data);
    free(m->x);
    free(m->v);
    free(m->block);
    free(m->f0);
    free(m->rate);
    free(m->dfdx);
    free(m->dfdv);
    free(m->a_inf);
    free(m->constants);
    free(m);
}

static fmu_status read_constants(fmu_instance *instance, fmu_model *m)
{
    wec_data data;
    char message[WEC_MESSAGE_SIZE];
    if (wec_data_open(&data, m->data, m->data_size, "hydro", message, sizeof message) != WEC_OK) {
        fmu_log(instance, FMU_ERROR, "logError", "resources/%s: %s", HYDRO_RESOURCE, message);
        return FMU_ERROR;
    }
    const int64_t any[1] = {-1};
    const wec_array *array = NULL;
    fmu_status status = FMU_OK;
    if (wec_data_get(&data, "fmu.constants", WEC_F64, 1, any, 0, 0, &array, message, sizeof message) != WEC_OK) {
        fmu_log(instance, FMU_ERROR, "logError", "resources/%s: %s", HYDRO_RESOURCE, message);
        status = FMU_ERROR;
    } else if (array != NULL) {
        m->n_constants = (size_t)array->count;
        m->constants = wec_array_copy_f64(array);
        if (m->constants == NULL)
            status = FMU_ERROR;
    }
    const int64_t token_shape[1] = {-1};
    if (status == FMU_OK && wec_data_get(&data, "fmu.token", WEC_U8, 1, token_shape, 1, 0, &array, message,
                                         sizeof message) != WEC_OK) {
        fmu_log(instance, FMU_ERROR, "logError", "resources/%s: %s (the file was not written by the FMU builder)",
                HYDRO_RESOURCE, message);
        status = FMU_ERROR;
    } else if (status == FMU_OK) {
        size_t length = array->nbytes < sizeof m->token - 1 ? array->nbytes : sizeof m->token - 1;
        memcpy(m->token, array->bytes, length);
        m->token[length] = '\0';
    }
    wec_data_close(&data);
    return status;
}

fmu_status model_instantiate(fmu_instance *instance)
{
    fmu_model *m = calloc(1, sizeof *m);
    if (m == NULL)
        return FMU_ERROR;
    instance->model = m;
    m->data = fmu_read_resource(instance, HYDRO_RESOURCE, &m->data_size);
    if (m->data == NULL)
        return FMU_ERROR;
    m->hydro = wec_hydro_create(m->data, m->data_size);
    if (m->hydro == NULL) {
        fmu_log(instance, FMU_ERROR, "logError", "resources/%s refused: %s", HYDRO_RESOURCE,
                wec_hydro_create_error());
        return FMU_ERROR;
    }
    if (wec_hydro_dofs(m->hydro, &m->n) != WEC_OK || m->n == 0 || m->n >= VR_BLOCK || m->n * m->n >= VR_MATRIX) {
        fmu_log(instance, FMU_ERROR, "logError", "resources/%s: %zu degrees of freedom (this FMU takes 1 to 99)",
                HYDRO_RESOURCE, m->n);
        return FMU_ERROR;
    }
    size_t n = m->n;
    m->x = calloc(n, sizeof(double));
    m->v = calloc(n, sizeof(double));
    m->block = calloc(WEC_HYDRO_ROWS * n, sizeof(double));
    m->f0 = calloc(n, sizeof(double));
    m->rate = calloc(n, sizeof(double));
    m->dfdx = calloc(n * n, sizeof(double));
    m->dfdv = calloc(n * n, sizeof(double));
    m->a_inf = calloc(n * n, sizeof(double));
    if (!m->x || !m->v || !m->block || !m->f0 || !m->rate || !m->dfdx || !m->dfdv || !m->a_inf) {
        fmu_log(instance, FMU_ERROR, "logError", "out of memory");
        return FMU_ERROR;
    }
    if (wec_hydro_added_mass_inf(m->hydro, m->a_inf, n * n) != WEC_OK)
        return runtime_error(instance, "added mass");
    return read_constants(instance, m);
}

fmu_status model_check_token(fmu_instance *instance, const char *token)
{
    if (token != NULL && strcmp(token, instance->model->token) == 0)
        return FMU_OK;
    fmu_log(instance, FMU_ERROR, "logError", "%s %s does not match this FMU's resources (%s): modelDescription.xml "
            "and resources/%s come from different builds", instance->fmi_version == 3 ? "instantiation token" : "GUID",
            token != NULL ? token : "(null)", instance->model->token, HYDRO_RESOURCE);
    return FMU_ERROR;
}

void model_free(fmu_instance *instance)
{
    if (instance->model != NULL)
        release(instance->model);
    instance->model = NULL;
}

fmu_status model_reset(fmu_instance *instance)
{
    fmu_model *m = instance->model;
    wec_hydro *fresh = wec_hydro_create(m->data, m->data_size);
    if (fresh == NULL) {
        fmu_log(instance, FMU_ERROR, "logError", "reset: %s", wec_hydro_create_error());
        return FMU_ERROR;
    }
    wec_hydro_free(m->hydro);
    m->hydro = fresh;
    memset(m->x, 0, m->n * sizeof(double));
    memset(m->v, 0, m->n * sizeof(double));
    m->outputs_fresh = m->linear_fresh = m->started = 0;
    return FMU_OK;
}

static fmu_status start(fmu_instance *instance)
{
    fmu_model *m = instance->model;
    if (m->started)
        return FMU_OK;
    if (wec_hydro_set_start_time(m->hydro, instance->start_time) != WEC_OK)
        return runtime_error(instance, "start time");
    m->started = 1;
    return FMU_OK;
}

fmu_status model_exit_initialization(fmu_instance *instance)
{
    instance->model->started = 0; /* the start time may have changed since outputs were read */
    return start(instance);
}

static fmu_status refresh_outputs(fmu_instance *instance)
{
    fmu_model *m = instance->model;
    if (m->outputs_fresh)
        return FMU_OK;
    if (instance->phase != FMU_STEPPING && instance->phase != FMU_FAILED && instance->phase != FMU_TERMINATED)
        m->started = 0;
    if (start(instance) != FMU_OK)
        return FMU_ERROR;
    if (wec_hydro_outputs(m->hydro, instance->time, m->x, m->v, m->n, NULL, WEC_HYDRO_ROWS, m->block, m->power,
                          m->work, &m->eta) != WEC_OK)
        return runtime_error(instance, "forces");
    m->outputs_fresh = 1;
    return FMU_OK;
}

static fmu_status refresh_linear(fmu_instance *instance)
{
    fmu_model *m = instance->model;
    if (m->linear_fresh)
        return FMU_OK;
    if (refresh_outputs(instance) != FMU_OK)
        return FMU_ERROR;
    if (wec_hydro_linearise(m->hydro, instance->time, m->x, m->v, m->n, NULL, NULL, m->f0, m->rate, m->dfdx,
                            m->dfdv) != WEC_OK)
        return runtime_error(instance, "linearised force");
    m->linear_fresh = 1;
    return FMU_OK;
}

static fmu_status unknown_reference(fmu_instance *instance, uint32_t vr, const char *what)
{
    fmu_log(instance, FMU_ERROR, "logError", "value reference %u is not %s of this FMU", (unsigned)vr, what);
    return FMU_ERROR;
}

fmu_status model_get_float64(fmu_instance *instance, uint32_t vr, double *value)
{
    fmu_model *m = instance->model;
    size_t n = m->n;
    if (vr >= VR_X && vr < VR_X + n) {
        *value = m->x[vr - VR_X];
        return FMU_OK;
    }
    if (vr >= VR_V && vr < VR_V + n) {
        *value = m->v[vr - VR_V];
        return FMU_OK;
    }
    if (vr >= VR_A_INF && vr < VR_A_INF + n * n) {
        *value = m->a_inf[vr - VR_A_INF];
        return FMU_OK;
    }
    if (vr >= VR_CONSTANT && vr < VR_CONSTANT + m->n_constants) {
        *value = m->constants[vr - VR_CONSTANT];
        return FMU_OK;
    }
    if (vr >= VR_F && vr < VR_F_VISC + n && (vr - VR_F) % VR_BLOCK < n) {
        if (refresh_outputs(instance) != FMU_OK)
            return FMU_ERROR;
        uint32_t row = (vr - VR_F) / VR_BLOCK, i = (vr - VR_F) % VR_BLOCK;
        *value = m->block[row * n + i];
        return FMU_OK;
    }
    if (vr == VR_ELEVATION || (vr >= VR_WORK && vr < VR_WORK + WEC_HYDRO_COMPONENTS)) {
        if (refresh_outputs(instance) != FMU_OK)
            return FMU_ERROR;
        *value = vr == VR_ELEVATION ? m->eta : m->work[vr - VR_WORK];
        return FMU_OK;
    }
    int f0 = vr >= VR_F0 && vr < VR_F0 + n, rate = vr >= VR_F0_RATE && vr < VR_F0_RATE + n;
    int dx = vr >= VR_DF_DX && vr < VR_DF_DX + n * n, dv = vr >= VR_DF_DV && vr < VR_DF_DV + n * n;
    if (f0 || rate || dx || dv) {
        if (refresh_linear(instance) != FMU_OK)
            return FMU_ERROR;
        *value = f0 ? m->f0[vr - VR_F0] : rate ? m->rate[vr - VR_F0_RATE] : dx ? m->dfdx[vr - VR_DF_DX]
                                                                                 : m->dfdv[vr - VR_DF_DV];
        return FMU_OK;
    }
    return unknown_reference(instance, vr, "a Real variable");
}

fmu_status model_float64_elements(fmu_instance *instance, uint32_t vr, uint32_t *first, size_t *count)
{
    fmu_model *m = instance->model;
    size_t n = m->n;
    static const struct { uint32_t vr3, first; int kind; } arrays[] = {
        {VR3_X, VR_X, 1},       {VR3_V, VR_V, 1},           {VR3_F, VR_F, 1},         {VR3_F_EXC, VR_F_EXC, 1},
        {VR3_F_RAD, VR_F_RAD, 1}, {VR3_F_HS, VR_F_HS, 1},     {VR3_F_VISC, VR_F_VISC, 1}, {VR3_F0, VR_F0, 1},
        {VR3_F0_RATE, VR_F0_RATE, 1}, {VR3_DF_DX, VR_DF_DX, 2}, {VR3_DF_DV, VR_DF_DV, 2}, {VR3_A_INF, VR_A_INF, 2},
        {VR3_WORK, VR_WORK, 0}};
    for (size_t k = 0; k < sizeof arrays / sizeof arrays[0]; k++)
        if (arrays[k].vr3 == vr) {
            *first = arrays[k].first;
            *count = arrays[k].kind == 0 ? WEC_HYDRO_COMPONENTS : arrays[k].kind == 1 ? n : n * n;
            return FMU_OK;
        }
    if (vr == VR_ELEVATION || (vr >= VR_CONSTANT && vr < VR_CONSTANT + m->n_constants)) {
        *first = vr;
        *count = 1;
        return FMU_OK;
    }
    return unknown_reference(instance, vr, "a Float64 variable");
}

fmu_status model_set_float64(fmu_instance *instance, uint32_t vr, double value)
{
    fmu_model *m = instance->model;
    size_t n = m->n;
    double *target = vr >= VR_X && vr < VR_X + n ? &m->x[vr - VR_X] : vr >= VR_V && vr < VR_V + n ? &m->v[vr - VR_V]
                                                                                                 : NULL;
    if (target == NULL)
        return unknown_reference(instance, vr, "an input (x, v)");
    if (!isfinite(value)) {
        fmu_log(instance, FMU_ERROR, "logError", "input %s[%u] set to %g at t = %.17g s: inputs must be finite",
                vr < VR_V ? "x" : "v", (unsigned)(vr % VR_BLOCK) + 1u, value, instance->time);
        return FMU_ERROR;
    }
    if (*target != value) {
        *target = value;
        m->outputs_fresh = m->linear_fresh = 0;
    }
    return FMU_OK;
}

fmu_status model_do_step(fmu_instance *instance, double h)
{
    fmu_model *m = instance->model;
    if (start(instance) != FMU_OK)
        return FMU_ERROR;
    if (wec_hydro_do_step(m->hydro, instance->time, h, m->x, m->v, m->n) != WEC_OK)
        return runtime_error(instance, "step refused");
    m->outputs_fresh = m->linear_fresh = 0;
    return FMU_OK;
}

fmu_status model_partial(fmu_instance *instance, uint32_t unknown, uint32_t known, double *value)
{
    fmu_model *m = instance->model;
    size_t n = m->n;
    if (!(unknown >= VR_F && unknown < VR_F + n))
        return unknown_reference(instance, unknown, "a total force F (the outputs with directional derivatives)");
    if (!((known >= VR_X && known < VR_X + n) || (known >= VR_V && known < VR_V + n)))
        return unknown_reference(instance, known, "an input (x, v)");
    if (refresh_linear(instance) != FMU_OK)
        return FMU_ERROR;
    size_t i = unknown - VR_F;
    *value = known < VR_V ? m->dfdx[i * n + (known - VR_X)] : m->dfdv[i * n + (known - VR_V)];
    return FMU_OK;
}

/* ---- FMU state: the runtime model (a clone) and the instance's clock and inputs ---- */

typedef struct {
    uint64_t magic;
    wec_hydro *hydro;
    size_t n;
    double start_time, anchor, step, time;
    uint64_t count;
    int phase;
    double *x, *v;
} hydro_state;

#define STATE_MAGIC 0x3153554d46434557ULL /* "WECFMUS1" */
#define STATE_HEADER (8 + 8 + 4 * 8 + 8 + 8)

static void state_release(hydro_state *s)
{
    if (s == NULL)
        return;
    wec_hydro_free(s->hydro);
    free(s->x);
    free(s->v);
    free(s);
}

void model_state_free(void *state) { state_release((hydro_state *)state); }

static hydro_state *state_new(size_t n)
{
    hydro_state *s = calloc(1, sizeof *s);
    if (s == NULL)
        return NULL;
    s->magic = STATE_MAGIC;
    s->n = n;
    s->x = calloc(n, sizeof(double));
    s->v = calloc(n, sizeof(double));
    if (s->x == NULL || s->v == NULL) {
        state_release(s);
        return NULL;
    }
    return s;
}

static void state_clock_from(hydro_state *s, const fmu_instance *instance)
{
    s->start_time = instance->start_time;
    s->anchor = instance->anchor;
    s->step = instance->step;
    s->time = instance->time;
    s->count = instance->count;
    s->phase = instance->phase;
}

static fmu_status check_state(fmu_instance *instance, const void *state)
{
    const hydro_state *s = (const hydro_state *)state;
    if (s == NULL || s->magic != STATE_MAGIC || s->n != instance->model->n) {
        fmu_log(instance, FMU_ERROR, "logError", "the FMU state is not a state of this FMU");
        return FMU_ERROR;
    }
    return FMU_OK;
}

fmu_status model_state_get(fmu_instance *instance, void **state)
{
    fmu_model *m = instance->model;
    hydro_state *s = (hydro_state *)*state;
    if (s != NULL) {
        if (check_state(instance, s) != FMU_OK)
            return FMU_ERROR;
        if (wec_hydro_copy_state(s->hydro, m->hydro) != WEC_OK)
            return runtime_error(instance, "FMU state");
    } else {
        s = state_new(m->n);
        if (s == NULL || (s->hydro = wec_hydro_clone(m->hydro)) == NULL) {
            fmu_log(instance, FMU_ERROR, "logError", "FMU state: %s", wec_hydro_create_error());
            state_release(s);
            return FMU_ERROR;
        }
    }
    state_clock_from(s, instance);
    memcpy(s->x, m->x, m->n * sizeof(double));
    memcpy(s->v, m->v, m->n * sizeof(double));
    *state = s;
    return FMU_OK;
}

fmu_status model_state_set(fmu_instance *instance, const void *state)
{
    fmu_model *m = instance->model;
    if (check_state(instance, state) != FMU_OK)
        return FMU_ERROR;
    const hydro_state *s = (const hydro_state *)state;
    if (wec_hydro_copy_state(m->hydro, s->hydro) != WEC_OK)
        return runtime_error(instance, "FMU state");
    instance->start_time = s->start_time;
    instance->anchor = s->anchor;
    instance->step = s->step;
    instance->time = s->time;
    instance->count = s->count;
    memcpy(m->x, s->x, m->n * sizeof(double));
    memcpy(m->v, s->v, m->n * sizeof(double));
    m->outputs_fresh = m->linear_fresh = 0;
    m->started = 1;
    return FMU_OK;
}

fmu_status model_state_size(fmu_instance *instance, const void *state, size_t *size)
{
    if (check_state(instance, state) != FMU_OK)
        return FMU_ERROR;
    const hydro_state *s = (const hydro_state *)state;
    size_t bytes = 0;
    if (wec_hydro_state_size(s->hydro, &bytes) != WEC_OK)
        return runtime_error(instance, "FMU state size");
    *size = STATE_HEADER + 2 * s->n * sizeof(double) + 8 + bytes;
    return FMU_OK;
}

static unsigned char *put(unsigned char *p, const void *value, size_t size)
{
    memcpy(p, value, size);
    return p + size;
}

fmu_status model_state_serialize(fmu_instance *instance, const void *state, unsigned char *bytes, size_t size)
{
    size_t expected = 0;
    if (model_state_size(instance, state, &expected) != FMU_OK)
        return FMU_ERROR;
    if (size != expected) {
        fmu_log(instance, FMU_ERROR, "logError", "serialise FMU state: buffer of %zu bytes, the state takes %zu",
                size, expected);
        return FMU_ERROR;
    }
    const hydro_state *s = (const hydro_state *)state;
    uint64_t n = s->n, count = s->count, model_size = expected - STATE_HEADER - 2 * s->n * sizeof(double) - 8;
    int64_t phase = s->phase;
    unsigned char *p = put(bytes, &s->magic, 8);
    p = put(p, &n, 8);
    p = put(p, &s->start_time, 8);
    p = put(p, &s->anchor, 8);
    p = put(p, &s->step, 8);
    p = put(p, &s->time, 8);
    p = put(p, &count, 8);
    p = put(p, &phase, 8);
    p = put(p, s->x, s->n * sizeof(double));
    p = put(p, s->v, s->n * sizeof(double));
    p = put(p, &model_size, 8);
    if (wec_hydro_state_save(s->hydro, p, (size_t)model_size) != WEC_OK)
        return runtime_error(instance, "serialise FMU state");
    return FMU_OK;
}

fmu_status model_state_deserialize(fmu_instance *instance, const unsigned char *bytes, size_t size, void **state)
{
    fmu_model *m = instance->model;
    size_t fixed = STATE_HEADER + 2 * m->n * sizeof(double) + 8;
    uint64_t magic = 0, n = 0, model_size = 0, count = 0;
    int64_t phase = 0;
    if (size >= fixed) {
        memcpy(&magic, bytes, 8);
        memcpy(&n, bytes + 8, 8);
        memcpy(&model_size, bytes + fixed - 8, 8);
    }
    if (size < fixed || magic != STATE_MAGIC || n != m->n || model_size != size - fixed) {
        fmu_log(instance, FMU_ERROR, "logError", "deserialise FMU state: %zu bytes are not a serialised state of "
                "this FMU (%zu degrees of freedom)", size, m->n);
        return FMU_ERROR;
    }
    hydro_state *s = state_new(m->n);
    if (s == NULL || (s->hydro = wec_hydro_clone(m->hydro)) == NULL) {
        state_release(s);
        fmu_log(instance, FMU_ERROR, "logError", "deserialise FMU state: out of memory");
        return FMU_ERROR;
    }
    const unsigned char *p = bytes + 16;
    memcpy(&s->start_time, p, 8);
    memcpy(&s->anchor, p + 8, 8);
    memcpy(&s->step, p + 16, 8);
    memcpy(&s->time, p + 24, 8);
    memcpy(&count, p + 32, 8);
    memcpy(&phase, p + 40, 8);
    s->count = count;
    s->phase = (int)phase;
    p += 48;
    memcpy(s->x, p, m->n * sizeof(double));
    memcpy(s->v, p + m->n * sizeof(double), m->n * sizeof(double));
    if (wec_hydro_state_load(s->hydro, bytes + fixed, (size_t)model_size) != WEC_OK) {
        fmu_log(instance, FMU_ERROR, "logError", "deserialise FMU state: %s", wec_hydro_last_error(s->hydro));
        state_release(s);
        return FMU_ERROR;
    }
    if (*state != NULL)
        state_release((hydro_state *)*state);
    *state = s;
    return FMU_OK;
}
