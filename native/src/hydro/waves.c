/* The sea's components at the world origin: omega_k (rad/s) and complex amplitude a_k exp(i phi_k) (m), exp(+i
 * omega t) convention; elevation eta(t) = r(t) Re sum_k a_k exp(i phi_k) exp(i omega_k t) (hydro_fmu.waves). The
 * components are prepared in Python (regular wave, spectrum discretisation and seeded phases, the Fourier
 * components of an imported record, directional spreading). */
#include "hydro_internal.h"

int hydro_load_waves(hydro_shared *s, const wec_data *d, char *msg)
{
    const wec_array *omega, *amp;
    int st = wec_data_get(d, "waves.omega", WEC_F64, 1, NULL, 1, 1, &omega, msg, HYDRO_MSG_SIZE);
    if (st != WEC_OK)
        return st;
    s->k = (size_t)omega->shape[0];
    int64_t shape[2] = {(int64_t)s->k, 2};
    if ((st = wec_data_get(d, "waves.amplitude", WEC_F64, 2, shape, 1, 1, &amp, msg, HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    s->omega = wec_array_copy_f64(omega);
    s->amp_re = wec_alloc_f64(s->k);
    s->amp_im = wec_alloc_f64(s->k);
    if (!s->omega || !s->amp_re || !s->amp_im)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    for (size_t i = 0; i < s->k; i++) {
        s->amp_re[i] = wec_array_f64(amp, 2 * i);
        s->amp_im[i] = wec_array_f64(amp, 2 * i + 1);
    }
    return WEC_OK;
}
