/* The per-point entry points of the public API (wec_hydro.h): argument checks, then the concepts. */
#include <math.h>
#include <string.h>

#include "hydro_internal.h"

static int check_inputs(wec_hydro *h, const char *call, double t, const double *x, int need_x, const double *v,
                        size_t n)
{
    if (!isfinite(t))
        return wec_fail(h->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "%s: the time %g is not finite", call, t);
    if (n != h->shared->n)
        return wec_fail(h->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "%s: %zu inputs given, the model has %zu degrees "
                        "of freedom", call, n, h->shared->n);
    if ((x == NULL && need_x) || v == NULL)
        return wec_fail(h->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "%s: an input pointer is NULL", call);
    return WEC_OK;
}

static int same_point(const wec_hydro *h, double t, const double *x, const double *v)
{
    size_t n = h->shared->n;
    return h->cached && h->cache_t == t && memcmp(h->cache_x, x, n * sizeof(double)) == 0 &&
           memcmp(h->cache_v, v, n * sizeof(double)) == 0;
}

static int point(wec_hydro *h, double t, const double *x, const double *v)
{
    return same_point(h, t, x, v) ? WEC_OK : hydro_evaluate(h, t, x, v, h->error);
}

int wec_hydro_set_start_time(wec_hydro *model, double start_time)
{
    if (!hydro_live(model))
        return WEC_ERR_HANDLE;
    if (!isfinite(start_time))
        return wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_set_start_time: %g is not finite",
                        start_time);
    model->start_time = start_time;
    return WEC_OK;
}

int wec_hydro_outputs(wec_hydro *model, double t, const double *x, const double *v, size_t n, const int64_t *rows,
                      size_t n_rows, double *forces, double *power, double *work, double *elevation)
{
    if (!hydro_live(model))
        return WEC_ERR_HANDLE;
    int st = check_inputs(model, "wec_hydro_outputs", t, x, 1, v, n);
    if (st != WEC_OK)
        return st;
    if (rows == NULL && n_rows != WEC_HYDRO_ROWS && n_rows != 0)
        return wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_outputs: without rows, n_rows "
                        "must be %d (all rows) or 0 (none)", WEC_HYDRO_ROWS);
    if (n_rows > 0 && forces == NULL)
        return wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_outputs: forces is NULL");
    for (size_t k = 0; rows != NULL && k < n_rows; k++)
        if (rows[k] < 0 || rows[k] >= WEC_HYDRO_ROWS)
            return wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_outputs: row %lld does not "
                            "exist (0 total, 1 excitation, 2 radiation, 3 hydrostatic, 4 viscous)",
                            (long long)rows[k]);
    if ((st = point(model, t, x, v)) != WEC_OK)
        return st;
    for (size_t k = 0; k < n_rows; k++) {
        size_t row = rows != NULL ? (size_t)rows[k] : k;
        memcpy(forces + k * n, model->block + row * n, n * sizeof(double));
    }
    if (power != NULL)
        memcpy(power, model->power, sizeof(model->power));
    if (work != NULL)
        memcpy(work, model->work_value, sizeof(model->work_value));
    if (elevation != NULL)
        *elevation = model->eta;
    return WEC_OK;
}

int wec_hydro_elevation(wec_hydro *model, double t, double *elevation)
{
    if (!hydro_live(model))
        return WEC_ERR_HANDLE;
    if (!isfinite(t) || elevation == NULL)
        return wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_elevation: the time must be finite "
                        "and elevation not NULL");
    *elevation = hydro_elevation(model, t);
    return WEC_OK;
}

int wec_hydro_linearise(wec_hydro *model, double t, const double *x, const double *v, size_t n,
                        const unsigned char *stiffness_mask, const unsigned char *damping_mask, double *f0,
                        double *f0_rate, double *df_dx, double *df_dv)
{
    if (!hydro_live(model))
        return WEC_ERR_HANDLE;
    int st = check_inputs(model, "wec_hydro_linearise", t, x, 1, v, n);
    if (st != WEC_OK)
        return st;
    if (f0 == NULL || f0_rate == NULL || df_dx == NULL || df_dv == NULL)
        return wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_linearise: an output pointer is "
                        "NULL");
    return hydro_linearise(model, t, x, v, stiffness_mask, damping_mask, f0, f0_rate, df_dx, df_dv);
}

static int advance(wec_hydro *h, double t, double step, const double *v)
{
    const hydro_shared *s = h->shared;
    double expected = h->start_time + h->elapsed;
    double unit = s->dt > fabs(step) ? s->dt : fabs(step);
    if (!isfinite(step))
        return wec_fail(h->error, HYDRO_MSG_SIZE, WEC_ERR_STEP, "the step %g s is not finite", step);
    if (fabs(t - expected) > 1e-6 * unit)
        return wec_fail(h->error, HYDRO_MSG_SIZE, WEC_ERR_STEP, "step starts at t = %g s but the radiation history "
                        "is at t = %g s", t, expected);
    int st = WEC_OK;
    if (s->radiation == RADIATION_CONVOLUTION)
        st = conv_memory_step(&h->conv, s, v, step, h->error);
    else if (s->radiation == RADIATION_STATE_SPACE)
        st = ss_memory_step(&h->ss, s, v, step, h->error);
    else if (!(step > 0))
        st = wec_fail(h->error, HYDRO_MSG_SIZE, WEC_ERR_STEP, "a step must be positive (got %g)", step);
    if (st != WEC_OK)
        return st;
    /* compensated (Kahan) sum of the steps: a plain sum of ~1e6 steps drifts by ~n u t; this by ~2 u t */
    double y = step - h->elapsed_error;
    double total = h->elapsed + y;
    h->elapsed_error = (total - h->elapsed) - y;
    h->elapsed = total;
    h->cached = 0;
    return WEC_OK;
}

int wec_hydro_advance(wec_hydro *model, double t, double h, const double *v, size_t n)
{
    if (!hydro_live(model))
        return WEC_ERR_HANDLE;
    int st = check_inputs(model, "wec_hydro_advance", t, NULL, 0, v, n);
    return st != WEC_OK ? st : advance(model, t, h, v);
}

int wec_hydro_commit_work(wec_hydro *model, double t, const double *x, const double *v, size_t n)
{
    if (!hydro_live(model))
        return WEC_ERR_HANDLE;
    int st = check_inputs(model, "wec_hydro_commit_work", t, x, 1, v, n);
    if (st != WEC_OK || (st = point(model, t, x, v)) != WEC_OK)
        return st;
    work_commit(&model->work, t, model->power, model->work_value);
    return WEC_OK;
}

int wec_hydro_do_step(wec_hydro *model, double t, double h, const double *x, const double *v, size_t n)
{
    if (!hydro_live(model))
        return WEC_ERR_HANDLE;
    int st = check_inputs(model, "wec_hydro_do_step", t, x, 1, v, n);
    if (st != WEC_OK || (st = point(model, t, x, v)) != WEC_OK)
        return st;
    work_account saved = model->work;
    work_commit(&model->work, t, model->power, model->work_value);
    st = advance(model, t, h, v);
    if (st != WEC_OK)
        model->work = saved; /* a refused step changes nothing */
    return st;
}

int wec_hydro_state_size(wec_hydro *model, size_t *size)
{
    if (!hydro_live(model))
        return WEC_ERR_HANDLE;
    if (size == NULL)
        return wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_state_size: size is NULL");
    *size = hydro_state_size(model);
    return WEC_OK;
}

int wec_hydro_state_save(wec_hydro *model, void *buffer, size_t size)
{
    if (!hydro_live(model))
        return WEC_ERR_HANDLE;
    size_t needed = hydro_state_size(model);
    if (buffer == NULL || size != needed)
        return wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_state_save: a buffer of %zu bytes "
                        "given, the state takes %zu", buffer == NULL ? (size_t)0 : size, needed);
    wec_writer w = {buffer, size, 0, 0};
    return hydro_state_write(model, &w) == WEC_OK
               ? WEC_OK
               : wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_state_save: buffer too small");
}

int wec_hydro_state_load(wec_hydro *model, const void *buffer, size_t size)
{
    if (!hydro_live(model))
        return WEC_ERR_HANDLE;
    if (buffer == NULL)
        return wec_fail(model->error, HYDRO_MSG_SIZE, WEC_ERR_ARGUMENT, "wec_hydro_state_load: buffer is NULL");
    wec_reader r = {buffer, size, 0, 0};
    return hydro_state_read(model, &r, model->error);
}
