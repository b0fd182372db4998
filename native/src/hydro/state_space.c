/* Radiation memory by the fitted state space (hydro_fmu.state_space.StateSpaceMemory):
 *
 *     z' = A z + B v,   mu = C z,
 *
 * stepped exactly for a velocity linear between two communication points (first-order hold):
 * z_{n+1} = Phi(h) z_n + G0(h) v_n + G1(h) (v_{n+1} - v_n), with Phi, G0, G1 from one matrix exponential of the
 * augmented matrix [[A h, B h, 0], [0, 0, I], [0, 0, 0]] per distinct step h. Any step size, no stability limit
 * (the fit's poles are stable); the force at a point uses the current velocity through the G1 term (direct
 * feedthrough): mu = C [Phi, G0 - G1, G1] w with w = (z at the last committed point, v there, v now). The fit
 * (ERA, order chosen by a tolerance) is prepared in Python; the discretisations of the last STATE_SPACE_CACHE
 * step sizes are kept (they are functions of A, B, C and h only, not state). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hydro_internal.h"

int hydro_load_state_space(hydro_shared *s, const wec_data *d, char *msg)
{
    if (s->radiation != RADIATION_STATE_SPACE)
        return WEC_OK;
    const wec_array *a, *b, *c;
    int64_t shape_a[2] = {-1, -1};
    int st = wec_data_get(d, "radiation.a", WEC_F64, 2, shape_a, 1, 1, &a, msg, HYDRO_MSG_SIZE);
    if (st != WEC_OK)
        return st;
    if (a->shape[0] != a->shape[1])
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'radiation.a' is not square");
    s->r = (size_t)a->shape[0];
    int64_t shape_b[2] = {(int64_t)s->r, (int64_t)s->n}, shape_c[2] = {(int64_t)s->n, (int64_t)s->r};
    if ((st = wec_data_get(d, "radiation.b", WEC_F64, 2, shape_b, 1, 1, &b, msg, HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    if ((st = wec_data_get(d, "radiation.c", WEC_F64, 2, shape_c, 1, 1, &c, msg, HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    s->ss_a = wec_array_copy_f64(a);
    s->ss_b = wec_array_copy_f64(b);
    s->ss_c = wec_array_copy_f64(c);
    if (!s->ss_a || !s->ss_b || !s->ss_c)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    return WEC_OK;
}

int ss_memory_init(ss_memory *m, const hydro_shared *s)
{
    memset(m, 0, sizeof(*m));
    if (s->radiation != RADIATION_STATE_SPACE)
        return WEC_OK;
    size_t q = s->r + 2 * s->n;
    m->w = wec_alloc_f64(q);
    m->aug = wec_alloc_f64(q * q);
    m->expm_out = wec_alloc_f64(q * q);
    m->expm_work = wec_alloc_f64(wec_expm_workspace_size(q));
    m->pivots = wec_alloc_i64(q);
    return m->w && m->aug && m->expm_out && m->expm_work && m->pivots ? WEC_OK : WEC_ERR_MEMORY;
}

void ss_memory_free(ss_memory *m)
{
    free(m->w);
    free(m->aug);
    free(m->expm_out);
    free(m->expm_work);
    free(m->pivots);
    for (size_t i = 0; i < STATE_SPACE_CACHE; i++) {
        free(m->cache[i].update);
        free(m->cache[i].output);
    }
}

void ss_memory_copy(ss_memory *to, const ss_memory *from, const hydro_shared *s)
{
    to->pending = from->pending;
    if (s->radiation == RADIATION_STATE_SPACE)
        memcpy(to->w, from->w, (s->r + 2 * s->n) * sizeof(double));
}

/* the cached (update, output) matrices of step h, computed if new */
static ss_entry *discretisation(ss_memory *m, const hydro_shared *s, double h, char *msg)
{
    for (size_t i = 0; i < STATE_SPACE_CACHE; i++)
        if (m->cache[i].used && m->cache[i].h == h)
            return &m->cache[i];
    size_t r = s->r, n = s->n, q = r + 2 * n;
    ss_entry *e = &m->cache[m->next];
    m->next = (m->next + 1) % STATE_SPACE_CACHE;
    e->used = 0;
    if (e->update == NULL) {
        e->update = wec_alloc_f64(r * q);
        e->output = wec_alloc_f64(n * q);
        if (!e->update || !e->output) {
            free(e->update);
            free(e->output);
            e->update = e->output = NULL;
            wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory discretising the state space");
            return NULL;
        }
    }
    if (h == 0.0) {
        memset(e->update, 0, r * q * sizeof(double));
        for (size_t i = 0; i < r; i++)
            e->update[i * q + i] = 1.0;
    } else {
        double *aug = m->aug;
        memset(aug, 0, q * q * sizeof(double));
        for (size_t i = 0; i < r; i++) {
            for (size_t j = 0; j < r; j++)
                aug[i * q + j] = s->ss_a[i * r + j] * h;
            for (size_t j = 0; j < n; j++)
                aug[i * q + r + j] = s->ss_b[i * n + j] * h;
        }
        for (size_t i = 0; i < n; i++)
            aug[(r + i) * q + r + n + i] = 1.0;
        if (wec_expm(aug, q, m->expm_out, m->expm_work, m->pivots)) {
            wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_STEP, "state-space radiation: the matrix exponential of the step "
                     "%g s is not finite", h);
            return NULL;
        }
        const double *ex = m->expm_out;
        for (size_t i = 0; i < r; i++) {
            for (size_t j = 0; j < r; j++)
                e->update[i * q + j] = ex[i * q + j];
            for (size_t j = 0; j < n; j++) {
                double g0 = ex[i * q + r + j], g1 = ex[i * q + r + n + j];
                e->update[i * q + r + j] = g0 - g1;
                e->update[i * q + r + n + j] = g1;
            }
        }
    }
    for (size_t i = 0; i < n; i++)
        for (size_t j = 0; j < q; j++) {
            double sum = 0.0;
            for (size_t k = 0; k < r; k++)
                sum += s->ss_c[i * r + k] * e->update[k * q + j];
            e->output[i * q + j] = sum;
        }
    e->h = h;
    e->used = 1;
    return e;
}

int ss_memory_force(ss_memory *m, const hydro_shared *s, const double *v, double *mu, char *msg)
{
    size_t r = s->r, n = s->n, q = r + 2 * n;
    memcpy(m->w + r + n, v, n * sizeof(double));
    ss_entry *e = discretisation(m, s, m->pending, msg);
    if (e == NULL)
        return WEC_ERR_STEP;
    for (size_t i = 0; i < n; i++) {
        double sum = 0.0;
        for (size_t j = 0; j < q; j++)
            sum += e->output[i * q + j] * m->w[j];
        mu[i] = sum;
    }
    return WEC_OK;
}

int ss_memory_damping(ss_memory *m, const hydro_shared *s, double *d, char *msg)
{
    size_t r = s->r, n = s->n, q = r + 2 * n;
    ss_entry *e = discretisation(m, s, m->pending, msg);
    if (e == NULL)
        return WEC_ERR_STEP;
    for (size_t i = 0; i < n; i++)
        for (size_t j = 0; j < n; j++)
            d[i * n + j] = e->output[i * q + r + n + j];
    return WEC_OK;
}

int ss_memory_step(ss_memory *m, const hydro_shared *s, const double *v, double h, char *msg)
{
    if (!(h > 0))
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_STEP, "a step must be positive (got %g)", h);
    size_t r = s->r, n = s->n, q = r + 2 * n;
    memcpy(m->w + r + n, v, n * sizeof(double));
    ss_entry *e = discretisation(m, s, m->pending, msg);
    if (e == NULL)
        return WEC_ERR_STEP;
    double *z = m->aug; /* workspace: the new state, then copied */
    for (size_t i = 0; i < r; i++) {
        double sum = 0.0;
        for (size_t j = 0; j < q; j++)
            sum += e->update[i * q + j] * m->w[j];
        z[i] = sum;
    }
    memcpy(m->w, z, r * sizeof(double));
    memcpy(m->w + r, v, n * sizeof(double));
    m->pending = h;
    return WEC_OK;
}
