/* Directional spreading as the Python model does it (hydro_fmu.spectra, hydro_fmu.waves): every (frequency,
 * direction) pair of a spread sea is a component of its own, travelling at its own heading beta_k, with its own
 * amplitude and phase; the excitation of each component is interpolated in heading by the preparation. What the
 * runtime needs of the headings is the field of the incident wave away from the origin (the nonlinear
 * Froude-Krylov force): the wave vector (k_x, k_y) = k (cos beta_k, sin beta_k) of each component, k its
 * wavenumber from the dispersion relation (prepared in Python). */
#include <math.h>

#include "hydro_internal.h"

int hydro_load_spreading(hydro_shared *s, const wec_data *d, char *msg)
{
    const wec_array *heading, *wavenumber;
    int64_t shape[1] = {(int64_t)s->k};
    int needed = s->froude_krylov != 0;
    int st = wec_data_get(d, "waves.heading", WEC_F64, 1, shape, needed, 1, &heading, msg, HYDRO_MSG_SIZE);
    if (st != WEC_OK)
        return st;
    if ((st = wec_data_get(d, "waves.wavenumber", WEC_F64, 1, shape, needed, 1, &wavenumber, msg,
                           HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    if (heading == NULL || wavenumber == NULL)
        return WEC_OK;
    s->kx = wec_alloc_f64(s->k);
    s->ky = wec_alloc_f64(s->k);
    s->wavenumber = wec_array_copy_f64(wavenumber);
    if (!s->kx || !s->ky || !s->wavenumber)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    for (size_t i = 0; i < s->k; i++) {
        double k = s->wavenumber[i], beta = wec_array_f64(heading, i);
        if (k < 0)
            return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'waves.wavenumber' is negative at "
                            "component %zu", i);
        s->kx[i] = k * cos(beta);
        s->ky[i] = k * sin(beta);
    }
    return WEC_OK;
}
