/* The linearised force interface (hydro_fmu.linearisation): over the next step about (t_n, x_n, v_n),
 *
 *     F(t, x, v) ~ F0 + F0_rate (t - t_n) + dF_dx x + dF_dv v,
 *
 * dF_dx = -C (linear hydrostatics, exact) plus the tangent of the nonlinear pressure forces (central differences
 * of step 1e-6 within each body); dF_dv = minus the current velocity's weight in the radiation memory (exact
 * derivative of the discrete memory) plus the viscous tangent -(b + 2 q |v|); F0 = F(t_n, x_n, v_n) - dF_dx x_n -
 * dF_dv v_n with the masked matrices (an entry left out keeps its share in F0, treated explicitly); F0_rate = the
 * excitation's rate (exact for the superposition, central difference for the convolution and the nonlinear
 * Froude-Krylov force) minus the backward difference of the memory's motion-independent part mu - D v between
 * the last two points at which the interface was evaluated (the memory rate, part of the state). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hydro_internal.h"

int memory_rate_init(memory_rate *r, size_t n)
{
    memset(r, 0, sizeof(*r));
    r->previous = wec_alloc_f64(n);
    r->latest = wec_alloc_f64(n);
    return r->previous && r->latest ? WEC_OK : WEC_ERR_MEMORY;
}

void memory_rate_free(memory_rate *r)
{
    free(r->previous);
    free(r->latest);
}

void memory_rate_copy(memory_rate *to, const memory_rate *from, size_t n)
{
    to->has_previous = from->has_previous;
    to->has_latest = from->has_latest;
    to->t_previous = from->t_previous;
    to->t_latest = from->t_latest;
    memcpy(to->previous, from->previous, n * sizeof(double));
    memcpy(to->latest, from->latest, n * sizeof(double));
}

/* the pair shifts at a new time, the newest value is replaced at the same time; rate 0 until two times were seen */
static void memory_rate_update(memory_rate *r, double t, const double *value, size_t n, double *rate)
{
    double scale = fabs(t) > 1.0 ? fabs(t) : 1.0;
    if (r->has_latest && t > r->t_latest + 1e-12 * scale) {
        memcpy(r->previous, r->latest, n * sizeof(double));
        r->t_previous = r->t_latest;
        r->has_previous = 1;
    }
    memcpy(r->latest, value, n * sizeof(double));
    r->t_latest = t;
    r->has_latest = 1;
    for (size_t i = 0; i < n; i++)
        rate[i] = r->has_previous ? (r->latest[i] - r->previous[i]) / (r->t_latest - r->t_previous) : 0.0;
}

/* d(F_hs + F_FK)/dx of the nonlinear pressure forces by central differences within each body, added to dfdx */
static void pressure_tangent(wec_hydro *h, double t, const double *x, double *dfdx)
{
    const hydro_shared *s = h->shared;
    size_t n = s->n;
    double *xp = h->scratch_n, *plus = h->scratch_n + n, *minus = h->scratch_n + 2 * n, *other = h->scratch_n + 3 * n;
    size_t start = 0;
    while (start < n) {
        size_t end = start;
        while (end < n && s->body_of[end] == s->body_of[start])
            end++;
        for (size_t j = start; j < end; j++) {
            memcpy(xp, x, n * sizeof(double));
            xp[j] = x[j] + TANGENT_DELTA;
            pressure_forces(h, t, xp, plus, other);
            for (size_t i = 0; i < n; i++)
                plus[i] = (0.0 + plus[i]) + other[i];
            xp[j] = x[j] - TANGENT_DELTA;
            pressure_forces(h, t, xp, minus, other);
            for (size_t i = 0; i < n; i++)
                minus[i] = (0.0 + minus[i]) + other[i];
            for (size_t i = start; i < end; i++)
                dfdx[i * n + j] += (plus[i] - minus[i]) / (2 * TANGENT_DELTA);
        }
        start = end;
    }
}

int hydro_linearise(wec_hydro *h, double t, const double *x, const double *v, const unsigned char *stiffness_mask,
                    const unsigned char *damping_mask, double *f0, double *rate, double *dfdx, double *dfdv)
{
    const hydro_shared *s = h->shared;
    size_t n = s->n;
    if (!h->cached || h->cache_t != t || memcmp(h->cache_x, x, n * sizeof(double)) != 0 ||
        memcmp(h->cache_v, v, n * sizeof(double)) != 0) {
        int st = hydro_evaluate(h, t, x, v, h->error);
        if (st != WEC_OK)
            return st;
    }
    int nonlinear = s->hydrostatics == HYDROSTATICS_NONLINEAR || s->froude_krylov;
    memset(dfdx, 0, n * n * sizeof(double));
    memset(dfdv, 0, n * n * sizeof(double));
    if (s->hydrostatics == HYDROSTATICS_LINEAR)
        for (size_t i = 0; i < n * n; i++)
            dfdx[i] = s->restoring[i];
    if (nonlinear)
        pressure_tangent(h, t, x, dfdx);
    if (s->excitation == EXCITATION_SUPERPOSITION) {
        phasor_clock_at(&h->clock, s->omega, s->k, t);
        excitation_superposition_rate(s, &h->clock, t, rate);
    } else if (s->excitation == EXCITATION_CONVOLUTION) {
        excitation_convolution_rate(s, t, h->eta_window, rate, h->scratch_n);
    } else {
        memset(rate, 0, n * sizeof(double));
    }
    if (s->froude_krylov) {
        double *ahead = h->scratch_n + n, *behind = h->scratch_n + 2 * n, *unused = h->scratch_n;
        pressure_forces(h, t + RATE_DELTA, x, unused, ahead);
        pressure_forces(h, t - RATE_DELTA, x, unused, behind);
        for (size_t i = 0; i < n; i++)
            rate[i] = rate[i] + (ahead[i] - behind[i]) / (2 * RATE_DELTA);
    }
    if (s->radiation != RADIATION_NONE) {
        double *d = h->scratch_nn, *known = h->scratch_n, *memory = h->scratch_n + n;
        if (s->radiation == RADIATION_CONVOLUTION) {
            conv_memory_damping(&h->conv, s, d);
        } else {
            int st = ss_memory_damping(&h->ss, s, d, h->error);
            if (st != WEC_OK)
                return st;
        }
        const double *rad = h->block + 2 * n;
        for (size_t i = 0; i < n; i++) {
            double dv = 0.0;
            for (size_t j = 0; j < n; j++) {
                dfdv[i * n + j] -= d[i * n + j];
                dv += d[i * n + j] * v[j];
            }
            known[i] = -rad[i] - dv;
        }
        memory_rate_update(&h->rate, t, known, n, memory);
        for (size_t i = 0; i < n; i++)
            rate[i] = rate[i] - memory[i];
    }
    if (s->viscous)
        for (size_t i = 0; i < n; i++)
            dfdv[i * n + i] += viscous_tangent(s, i, v[i]);
    for (size_t i = 0; i < n * n; i++) {
        if (stiffness_mask != NULL && !stiffness_mask[i])
            dfdx[i] = 0.0;
        if (damping_mask != NULL && !damping_mask[i])
            dfdv[i] = 0.0;
    }
    for (size_t i = 0; i < n; i++) {
        double sx = 0.0, sv = 0.0;
        for (size_t j = 0; j < n; j++) {
            sx += dfdx[i * n + j] * x[j];
            sv += dfdv[i * n + j] * v[j];
        }
        f0[i] = (h->block[i] - sx) - sv;
    }
    return WEC_OK;
}
