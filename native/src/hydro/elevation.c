/* The incident wave elevation at the world origin (m): the imported record if there is one, else the sum of the
 * components (on the phasor clock), times the ramp. */
#include "hydro_internal.h"

double hydro_elevation(wec_hydro *h, double t)
{
    const hydro_shared *s = h->shared;
    double r = hydro_ramp(s->ramp, t);
    if (s->samples > 0)
        return record_elevation(s, t) * r;
    phasor_clock_at(&h->clock, s->omega, s->k, t);
    double sum = 0.0;
    size_t col = s->columns - 1;
    for (size_t k = 0; k < s->k; k++)
        sum += h->clock.re[k] * s->table_re[k * s->columns + col] - h->clock.im[k] * s->table_im[k * s->columns + col];
    return sum * r;
}
