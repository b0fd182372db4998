/* The model: creation from the runtime data (every concept loads and checks its own arrays), clones sharing the
 * read-only data, the memory budget, freeing, and the handle checks of the public API. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hydro_internal.h"

#define MAX_DOFS 6000    /* 1000 bodies of 6 DOFs */
#define MAX_BODIES 1000

static WEC_THREAD_LOCAL char create_error[HYDRO_MSG_SIZE];

const char *wec_hydro_create_error(void) { return create_error; }

static int read_scalar_i64(const wec_data *d, const char *name, int64_t low, int64_t high, int64_t fallback,
                           int required, int64_t *out, char *msg)
{
    const wec_array *a;
    int st = wec_data_get(d, name, WEC_I64, 0, NULL, required, 0, &a, msg, HYDRO_MSG_SIZE);
    if (st != WEC_OK)
        return st;
    *out = a ? wec_array_i64(a, 0) : fallback;
    if (*out < low || *out > high)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: '%s' is %lld, expected %lld to %lld", name,
                        (long long)*out, (long long)low, (long long)high);
    return WEC_OK;
}

int hydro_load_model(hydro_shared *s, const wec_data *d, char *msg)
{
    const wec_array *dofs, *a;
    int64_t shape2[2] = {-1, 2};
    int st = wec_data_get(d, "model.dofs", WEC_I64, 2, shape2, 1, 0, &dofs, msg, HYDRO_MSG_SIZE);
    if (st != WEC_OK)
        return st;
    if (dofs->shape[0] < 1 || dofs->shape[0] > MAX_DOFS)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'model.dofs' lists %llu degrees of "
                        "freedom, expected 1 to %d", (unsigned long long)dofs->shape[0], MAX_DOFS);
    int64_t bodies;
    if ((st = read_scalar_i64(d, "model.bodies", 1, MAX_BODIES, 0, 1, &bodies, msg)) != WEC_OK)
        return st;
    s->n = (size_t)dofs->shape[0];
    s->bodies = (size_t)bodies;
    s->body_of = wec_alloc_i64(s->n);
    s->dof_of = wec_alloc_i64(s->n);
    if (!s->body_of || !s->dof_of)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    for (size_t i = 0; i < s->n; i++) {
        int64_t b = wec_array_i64(dofs, 2 * i), k = wec_array_i64(dofs, 2 * i + 1);
        if (b < 0 || b >= bodies || k < 0 || k > 5)
            return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'model.dofs' row %zu is (%lld, %lld): "
                            "expected a body index below %lld and a degree of freedom 0 to 5", i, (long long)b,
                            (long long)k, (long long)bodies);
        if (i > 0 && b < s->body_of[i - 1])
            return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'model.dofs' must list the degrees of "
                            "freedom body by body (row %zu goes back to body %lld)", i, (long long)b);
        for (size_t j = 0; j < i; j++)
            if (s->body_of[j] == b && s->dof_of[j] == k)
                return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'model.dofs' lists degree of "
                                "freedom %lld of body %lld twice", (long long)k, (long long)b);
        s->body_of[i] = b;
        s->dof_of[i] = k;
    }
    if ((st = wec_data_get(d, "model.dt", WEC_F64, 0, NULL, 1, 1, &a, msg, HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    s->dt = wec_array_f64(a, 0);
    if (!(s->dt > 0))
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'model.dt' is %g, must be positive", s->dt);
    if ((st = wec_data_get(d, "ramp.duration", WEC_F64, 0, NULL, 1, 1, &a, msg, HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    s->ramp = wec_array_f64(a, 0);
    int64_t method;
    if ((st = read_scalar_i64(d, "excitation.method", 0, 2, 0, 1, &method, msg)) != WEC_OK)
        return st;
    s->excitation = (int)method;
    if ((st = read_scalar_i64(d, "radiation.method", 0, 2, 0, 1, &method, msg)) != WEC_OK)
        return st;
    s->radiation = (int)method;
    if ((st = read_scalar_i64(d, "hydrostatics.method", 0, 2, 0, 1, &method, msg)) != WEC_OK)
        return st;
    s->hydrostatics = (int)method;
    if ((st = read_scalar_i64(d, "froude_krylov.nonlinear", 0, 1, 0, 1, &method, msg)) != WEC_OK)
        return st;
    s->froude_krylov = (int)method;
    if (s->froude_krylov && s->excitation == EXCITATION_CONVOLUTION)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: the excitation convolution cannot be "
                        "combined with a nonlinear Froude-Krylov force");
    int64_t shape_nn[2] = {(int64_t)s->n, (int64_t)s->n};
    if ((st = wec_data_get(d, "model.added_mass_inf", WEC_F64, 2, shape_nn, 0, 1, &a, msg, HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    if (a != NULL && !(s->added_mass_inf = wec_array_copy_f64(a)))
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    return WEC_OK;
}

void hydro_shared_free(hydro_shared *s)
{
    if (s == NULL)
        return;
    void *owned[] = {s->body_of, s->dof_of, s->added_mass_inf, s->omega, s->amp_re, s->amp_im, s->kx, s->ky,
                     s->wavenumber, s->table_re, s->table_im, s->tau, s->kernel_ex, s->transfer_re, s->transfer_im,
                     s->record, s->weights, s->ss_a, s->ss_b, s->ss_c, s->restoring, s->linear, s->quadratic,
                     s->cg, s->corners, s->first_face, s->equilibrium};
    for (size_t i = 0; i < sizeof(owned) / sizeof(owned[0]); i++)
        free(owned[i]);
    free(s);
}

/* Bytes the model needs beyond the data-sized arrays (and the transfer table of a convolution on a synthetic
 * sea): refused above 256 MiB + 8 times the data, so that hostile sizes cannot exhaust memory. */
static int memory_needed(const hydro_shared *s, size_t *bytes)
{
    size_t n = s->n, total = 0, t, q = s->r + 2 * n, qq;
    int ok = wec_mul(q, q, &qq);
#define ADD(expr) (ok = ok && (expr) && wec_add(total, t, &total))
    ADD(wec_mul(4 * 8, s->k, &t));                                                   /* clock */
    ADD(wec_mul(2 * s->m + 1 + s->blocks, n, &t) && wec_mul(t, 8, &t));             /* ring, last, history */
    if (s->radiation == RADIATION_STATE_SPACE) {
        ADD(wec_mul(qq, 8 * (2 + 8), &t));                                           /* expm */
        ADD(wec_mul(s->r + n, q, &t) && wec_mul(t, 8 * STATE_SPACE_CACHE, &t));      /* cached steps */
    }
    ADD(wec_mul(n, n, &t) && wec_mul(t, 2 * 8, &t));                                  /* scratch n x n */
    ADD(wec_mul(n, 8 * 16, &t));                                                     /* vectors of n */
    ADD(wec_mul(s->taus, 8, &t));                                                    /* elevation window */
    ADD(wec_mul(s->faces, 30 * 8, &t));                                              /* pressure scratch */
    if (s->excitation == EXCITATION_CONVOLUTION && s->samples == 0)
        ADD(wec_mul(s->k, n, &t) && wec_mul(t, 2 * 8, &t));                          /* transfer table */
#undef ADD
    *bytes = total;
    return ok;
}

static hydro_shared *load(const void *buffer, size_t size, char *msg)
{
    wec_data d;
    if (wec_data_open(&d, buffer, size, "hydro", msg, HYDRO_MSG_SIZE) != WEC_OK)
        return NULL;
    hydro_shared *s = calloc(1, sizeof(hydro_shared));
    if (s == NULL) {
        wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
        wec_data_close(&d);
        return NULL;
    }
    s->refs = 1;
    int (*loaders[])(hydro_shared *, const wec_data *, char *) = {
        hydro_load_model, hydro_load_waves, hydro_load_spreading, hydro_load_excitation,
        hydro_load_excitation_convolution, hydro_load_record, hydro_load_radiation_convolution,
        hydro_load_state_space, hydro_load_hydrostatics, hydro_load_viscous, hydro_load_pressure};
    int st = WEC_OK;
    for (size_t i = 0; i < sizeof(loaders) / sizeof(loaders[0]) && st == WEC_OK; i++)
        st = loaders[i](s, &d, msg);
    size_t needed = 0, limit = (size_t)256 << 20, scaled;
    if (st == WEC_OK) {
        if (!wec_mul(size, 8, &scaled) || !wec_add(limit, scaled, &limit))
            limit = SIZE_MAX;
        if (!memory_needed(s, &needed) || needed > limit)
            st = wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: the sizes it gives (%zu degrees of "
                          "freedom, %zu wave components, %zu kernel samples, state-space order %zu, %zu mesh faces) "
                          "would need more working memory than this runtime allows for %zu bytes of data",
                          s->n, s->k, s->m, s->r, s->faces, size);
    }
    if (st == WEC_OK)
        st = excitation_convolution_prepare(s, msg);
    if (st == WEC_OK && s->faces > 0) {
        pressure_scratch scratch;
        if (pressure_scratch_init(&scratch, s) != WEC_OK)
            st = wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
        else
            pressure_equilibrium(s, &scratch);
        pressure_scratch_free(&scratch);
    }
    if (st == WEC_OK)
        s->hash = wec_data_hash(buffer, size);
    wec_data_close(&d);
    if (st != WEC_OK) {
        hydro_shared_free(s);
        return NULL;
    }
    return s;
}

int hydro_instance_init(wec_hydro *h, hydro_shared *s)
{
    size_t n = s->n;
    h->magic = HYDRO_MAGIC;
    h->shared = s;
    h->error[0] = '\0';
    int ok = phasor_clock_init(&h->clock, s->k) == WEC_OK;
    ok = ok && conv_memory_init(&h->conv, s) == WEC_OK;
    ok = ok && ss_memory_init(&h->ss, s) == WEC_OK;
    ok = ok && memory_rate_init(&h->rate, n) == WEC_OK;
    ok = ok && pressure_scratch_init(&h->pressure, s) == WEC_OK;
    h->cache_x = wec_alloc_f64(n);
    h->cache_v = wec_alloc_f64(n);
    h->block = wec_alloc_f64(WEC_HYDRO_ROWS * n);
    h->scratch_n = wec_alloc_f64(4 * n);
    h->scratch_nn = wec_alloc_f64(2 * n * n);
    h->eta_window = wec_alloc_f64(s->taus);
    ok = ok && h->cache_x && h->cache_v && h->block && h->scratch_n && h->scratch_nn && h->eta_window;
    return ok ? WEC_OK : WEC_ERR_MEMORY;
}

void hydro_instance_free(wec_hydro *h)
{
    phasor_clock_free(&h->clock);
    conv_memory_free(&h->conv);
    ss_memory_free(&h->ss);
    memory_rate_free(&h->rate);
    pressure_scratch_free(&h->pressure);
    free(h->cache_x);
    free(h->cache_v);
    free(h->block);
    free(h->scratch_n);
    free(h->scratch_nn);
    free(h->eta_window);
}

wec_hydro *wec_hydro_create(const void *data, size_t size)
{
    create_error[0] = '\0';
    hydro_shared *s = load(data, size, create_error);
    if (s == NULL)
        return NULL;
    wec_hydro *h = calloc(1, sizeof(wec_hydro));
    if (h == NULL || hydro_instance_init(h, s) != WEC_OK) {
        if (h != NULL)
            hydro_instance_free(h);
        free(h);
        hydro_shared_free(s);
        wec_fail(create_error, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory creating the model");
        return NULL;
    }
    return h;
}

wec_hydro *wec_hydro_clone(const wec_hydro *model)
{
    create_error[0] = '\0';
    if (!hydro_live(model)) {
        wec_fail(create_error, HYDRO_MSG_SIZE, WEC_ERR_HANDLE, "wec_hydro_clone: not a live model handle");
        return NULL;
    }
    wec_hydro *h = calloc(1, sizeof(wec_hydro));
    if (h == NULL || hydro_instance_init(h, model->shared) != WEC_OK) {
        if (h != NULL)
            hydro_instance_free(h);
        free(h);
        wec_fail(create_error, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory cloning the model");
        return NULL;
    }
    model->shared->refs++;
    wec_hydro_copy_state(h, (wec_hydro *)model);
    return h;
}

void wec_hydro_free(wec_hydro *model)
{
    if (!hydro_live(model))
        return;
    hydro_shared *s = model->shared;
    hydro_instance_free(model);
    model->magic = HYDRO_DEAD;
    free(model);
    if (--s->refs == 0)
        hydro_shared_free(s);
}

const char *wec_hydro_last_error(const wec_hydro *model)
{
    if (!hydro_live(model))
        return "not a live wec_hydro handle (NULL, freed or foreign)";
    return model->error;
}

int wec_hydro_dofs(wec_hydro *model, size_t *n)
{
    if (!hydro_live(model))
        return WEC_ERR_HANDLE;
    if (n == NULL)
        return wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_dofs: n is NULL");
    *n = model->shared->n;
    return WEC_OK;
}

int wec_hydro_added_mass_inf(wec_hydro *model, double *a, size_t size)
{
    if (!hydro_live(model))
        return WEC_ERR_HANDLE;
    const hydro_shared *s = model->shared;
    if (s->added_mass_inf == NULL)
        return wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_added_mass_inf: the runtime data "
                        "hold no infinite-frequency added mass");
    if (a == NULL || size < s->n * s->n)
        return wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_added_mass_inf: room for %zu "
                        "values given, %zu needed", a == NULL ? (size_t)0 : size, s->n * s->n);
    memcpy(a, s->added_mass_inf, s->n * s->n * sizeof(double));
    return WEC_OK;
}

int wec_hydro_copy_state(wec_hydro *to, wec_hydro *from)
{
    if (!hydro_live(to) || !hydro_live(from))
        return WEC_ERR_HANDLE;
    if (to->shared != from->shared && to->shared->hash != from->shared->hash)
        return wec_fail(to->error, HYDRO_MSG_SIZE, WEC_ERR_STATE, "wec_hydro_copy_state: the two models were made "
                        "from different data");
    const hydro_shared *s = to->shared;
    if (to == from)
        return WEC_OK;
    to->start_time = from->start_time;
    to->elapsed = from->elapsed;
    to->elapsed_error = from->elapsed_error;
    phasor_clock_copy(&to->clock, &from->clock, s->k);
    conv_memory_copy(&to->conv, &from->conv, s);
    ss_memory_copy(&to->ss, &from->ss, s);
    to->work = from->work;
    memory_rate_copy(&to->rate, &from->rate, s->n);
    to->cached = from->cached;
    to->cache_t = from->cache_t;
    memcpy(to->cache_x, from->cache_x, s->n * sizeof(double));
    memcpy(to->cache_v, from->cache_v, s->n * sizeof(double));
    memcpy(to->block, from->block, WEC_HYDRO_ROWS * s->n * sizeof(double));
    memcpy(to->power, from->power, sizeof(to->power));
    memcpy(to->work_value, from->work_value, sizeof(to->work_value));
    to->eta = from->eta;
    return WEC_OK;
}
