/* One communication point: the force rows (total, excitation, radiation, hydrostatic, viscous) for inputs x, v at
 * time t, the elevation at the origin and the powers, in one pass (hydro_fmu.model.HydroModel.evaluate):
 * excitation (superposition on the phasor clock, whose last column gives the elevation too, or the convolution),
 * the radiation memory (-mu), linear hydrostatics -C x or the nonlinear pressure forces (which add the
 * Froude-Krylov force to the excitation), viscous forces, and the total ((exc + rad) + hs) + visc. Explicit
 * evaluation of given data: no stability limit of its own. The point is kept (its inputs bit for bit) so that
 * reading it again, linearising it or stepping from it does not evaluate it again. */
#include <string.h>

#include "hydro_internal.h"

int hydro_evaluate(wec_hydro *h, double t, const double *x, const double *v, char *msg)
{
    const hydro_shared *s = h->shared;
    size_t n = s->n;
    double *exc = h->block + n, *rad = h->block + 2 * n, *hs = h->block + 3 * n, *visc = h->block + 4 * n;
    double r = hydro_ramp(s->ramp, t);
    int table = s->excitation == EXCITATION_SUPERPOSITION;
    double eta = 0.0;
    h->cached = 0;
    if (table) {
        phasor_clock_at(&h->clock, s->omega, s->k, t);
        excitation_superposition(s, &h->clock, r, exc, s->samples > 0 ? NULL : &eta);
    } else if (s->excitation == EXCITATION_CONVOLUTION) {
        excitation_convolution(s, t, h->eta_window, exc);
    } else {
        memset(exc, 0, n * sizeof(double));
    }
    if (!table || s->samples > 0)
        eta = hydro_elevation(h, t);
    if (s->radiation == RADIATION_CONVOLUTION) {
        conv_memory_force(&h->conv, s, v, rad);
    } else if (s->radiation == RADIATION_STATE_SPACE) {
        int st = ss_memory_force(&h->ss, s, v, rad, msg);
        if (st != WEC_OK)
            return st;
    }
    for (size_t i = 0; i < n; i++) {
        rad[i] = s->radiation != RADIATION_NONE ? -rad[i] : 0.0;
        visc[i] = s->viscous ? viscous_force(s, i, v[i]) : 0.0;
    }
    if (s->hydrostatics == HYDROSTATICS_LINEAR)
        hydrostatics_linear(s, x, hs);
    else
        memset(hs, 0, n * sizeof(double));
    if (s->hydrostatics == HYDROSTATICS_NONLINEAR || s->froude_krylov) {
        double *hs_nl = h->scratch_n, *fk = h->scratch_n + n;
        pressure_forces(h, t, x, hs_nl, fk);
        for (size_t i = 0; i < n; i++) {
            if (s->hydrostatics == HYDROSTATICS_NONLINEAR)
                hs[i] = hs_nl[i];
            if (s->froude_krylov)
                exc[i] += fk[i];
        }
    }
    for (size_t i = 0; i < n; i++)
        h->block[i] = ((exc[i] + rad[i]) + hs[i]) + visc[i];
    work_powers(h->block, v, n, h->power);
    work_value(&h->work, t, h->power, h->work_value);
    h->eta = eta;
    h->cache_t = t;
    memcpy(h->cache_x, x, n * sizeof(double));
    memcpy(h->cache_v, v, n * sizeof(double));
    h->cached = 1;
    return WEC_OK;
}
