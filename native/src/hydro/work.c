/* The work done on the bodies by each force component (hydro_fmu.work): power P_c = F_c . v at a point, work by
 * the trapezoidal rule over the committed communication points, W(t) = W_c + (t - t_c) (P_c + P(t)) / 2 (second
 * order in the step for smooth motion). With the multibody side's energies it closes the wave-to-wire account. */
#include "hydro_internal.h"

void work_powers(const double *block, const double *v, size_t n, double *power)
{
    for (size_t c = 0; c < WEC_HYDRO_COMPONENTS; c++) {
        double p = 0.0;
        for (size_t i = 0; i < n; i++)
            p += block[(c + 1) * n + i] * v[i];
        power[c] = p;
    }
}

void work_value(const work_account *w, double t, const double *power, double *out)
{
    for (size_t c = 0; c < WEC_HYDRO_COMPONENTS; c++)
        out[c] = w->has_last ? (w->last_power[c] + power[c]) * (0.5 * (t - w->last_time)) + w->committed[c]
                             : w->committed[c];
}

void work_commit(work_account *w, double t, const double *power, const double *value)
{
    for (size_t c = 0; c < WEC_HYDRO_COMPONENTS; c++) {
        w->committed[c] = value[c];
        w->last_power[c] = power[c];
    }
    w->last_time = t;
    w->has_last = 1;
}
