/* An imported elevation record at the origin (hydro_fmu.wave_records.ElevationRecord): samples eta_j at j dt,
 * time 0 the first sample, linear interpolation between samples, periodic extension outside [0, N dt) (the record
 * is one period of its Fourier series, whose components the preparation gives the superposition). */
#include <math.h>

#include "hydro_internal.h"

int hydro_load_record(hydro_shared *s, const wec_data *d, char *msg)
{
    const wec_array *dt, *eta;
    int st = wec_data_get(d, "record.eta", WEC_F64, 1, NULL, 0, 1, &eta, msg, HYDRO_MSG_SIZE);
    if (st != WEC_OK || eta == NULL)
        return st;
    if ((st = wec_data_get(d, "record.dt", WEC_F64, 0, NULL, 1, 1, &dt, msg, HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    s->samples = (size_t)eta->shape[0];
    s->record_dt = wec_array_f64(dt, 0);
    if (s->samples < 2)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'record.eta' needs at least two samples");
    if (!(s->record_dt > 0))
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'record.dt' is %g, must be positive",
                        s->record_dt);
    if (!(s->record = wec_array_copy_f64(eta)))
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    return WEC_OK;
}

double record_elevation(const hydro_shared *s, double t)
{
    double tt = t / s->record_dt;
    double j = floor(tt);
    if (!isfinite(j))
        return NAN;
    double frac = tt - j;
    double n = (double)s->samples;
    double wrapped = fmod(j, n); /* exact for |j| < 2^53 */
    if (wrapped < 0)
        wrapped += n;
    size_t j0 = (size_t)wrapped;
    if (j0 >= s->samples)
        j0 = 0;
    size_t j1 = j0 + 1 == s->samples ? 0 : j0 + 1;
    return (1 - frac) * s->record[j0] + frac * s->record[j1];
}
