/* exp(i omega_k t) for a sequence of times, cheap when the times advance by a repeated step
 * (hydro_fmu.waves.PhasorClock, the same rules so that both give the same values): a new step delta costs one
 * table exp(i omega delta); each later time at the same step one complex product per component instead of an
 * exponential; the exact exponential again every PHASOR_REFRESH products, so that the error stays within that
 * many round-offs of omega t itself. A step counts as repeated when it matches to 8 ulps of t. The clock's
 * values therefore depend on the times it was asked for: they are part of the model state. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hydro_internal.h"

int phasor_clock_init(phasor_clock *c, size_t k)
{
    c->t = NAN;
    c->delta = NAN;
    c->count = 0;
    c->re = wec_alloc_f64(k);
    c->im = wec_alloc_f64(k);
    c->rot_re = wec_alloc_f64(k);
    c->rot_im = wec_alloc_f64(k);
    if (!c->re || !c->im || !c->rot_re || !c->rot_im)
        return WEC_ERR_MEMORY;
    for (size_t i = 0; i < k; i++) {
        c->re[i] = 1.0;
        c->rot_re[i] = 1.0;
    }
    return WEC_OK;
}

void phasor_clock_free(phasor_clock *c)
{
    free(c->re);
    free(c->im);
    free(c->rot_re);
    free(c->rot_im);
}

void phasor_clock_copy(phasor_clock *to, const phasor_clock *from, size_t k)
{
    to->t = from->t;
    to->delta = from->delta;
    to->count = from->count;
    memcpy(to->re, from->re, k * sizeof(double));
    memcpy(to->im, from->im, k * sizeof(double));
    memcpy(to->rot_re, from->rot_re, k * sizeof(double));
    memcpy(to->rot_im, from->rot_im, k * sizeof(double));
}

void phasor_clock_at(phasor_clock *c, const double *omega, size_t k, double t)
{
    if (t == c->t)
        return;
    double delta = t - c->t;
    double scale = fabs(t) > 1.0 ? fabs(t) : 1.0;
    if (c->count < PHASOR_REFRESH && fabs(delta - c->delta) <= 8 * 2.2e-16 * scale) {
        for (size_t i = 0; i < k; i++) {
            double a = c->re[i], b = c->im[i], x = c->rot_re[i], y = c->rot_im[i];
            c->re[i] = a * x - b * y;
            c->im[i] = a * y + b * x;
        }
        c->count++;
    } else {
        for (size_t i = 0; i < k; i++) {
            double phase = omega[i] * t;
            c->re[i] = cos(phase);
            c->im[i] = sin(phase);
        }
        c->count = 0;
        if (isfinite(delta) && delta != c->delta) {
            c->delta = delta;
            for (size_t i = 0; i < k; i++) {
                double phase = omega[i] * delta;
                c->rot_re[i] = cos(phase);
                c->rot_im[i] = sin(phase);
            }
        }
    }
    c->t = t;
}
