/* Wave excitation by superposition on the phasor clock (hydro_fmu.excitation.ExcitationForce):
 *
 *     F_exc(t) = r(t) Re sum_k c_k exp(i omega_k t),   c_k = a_k exp(i phi_k) X(omega_k, beta_k)
 *
 * exact for the given components (no time-stepping error). The coefficients c_k are prepared in Python
 * (excitation interpolated in frequency and heading, zero above the database's range; the diffraction part only
 * when the Froude-Krylov force is nonlinear). One pass of the clock's phasors over a combined table gives the n
 * forces and, in its last column, the elevation at the origin. The rate dF/dt is exact:
 * r' Re sum c e^(i w t) + r Re sum i w c e^(i w t). */
#include "hydro_internal.h"

int hydro_load_excitation(hydro_shared *s, const wec_data *d, char *msg)
{
    const wec_array *coef = NULL;
    size_t n = s->n;
    if (s->excitation == EXCITATION_SUPERPOSITION) {
        int64_t shape[3] = {(int64_t)s->k, (int64_t)n, 2};
        int st = wec_data_get(d, "excitation.coefficients", WEC_F64, 3, shape, 1, 1, &coef, msg, HYDRO_MSG_SIZE);
        if (st != WEC_OK)
            return st;
    }
    s->columns = coef != NULL ? n + 1 : 1;
    s->table_re = wec_alloc_f64(s->k * s->columns);
    s->table_im = wec_alloc_f64(s->k * s->columns);
    if (!s->table_re || !s->table_im)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    for (size_t k = 0; k < s->k; k++) {
        double *re = s->table_re + k * s->columns, *im = s->table_im + k * s->columns;
        if (coef != NULL)
            for (size_t i = 0; i < n; i++) {
                re[i] = wec_array_f64(coef, 2 * (k * n + i));
                im[i] = wec_array_f64(coef, 2 * (k * n + i) + 1);
            }
        re[s->columns - 1] = s->amp_re[k];
        im[s->columns - 1] = s->amp_im[k];
    }
    return WEC_OK;
}

void excitation_superposition(const hydro_shared *s, const phasor_clock *c, double ramp, double *exc, double *eta)
{
    size_t cols = s->columns, used = eta != NULL ? cols : cols - 1;
    for (size_t col = 0; col < used; col++) {
        double sum = 0.0;
        for (size_t k = 0; k < s->k; k++)
            sum += c->re[k] * s->table_re[k * cols + col] - c->im[k] * s->table_im[k * cols + col];
        if (col + 1 < cols)
            exc[col] = sum * ramp;
        else
            *eta = sum * ramp;
    }
}

void excitation_superposition_rate(const hydro_shared *s, const phasor_clock *c, double t, double *rate)
{
    size_t cols = s->columns, n = s->n;
    double r = hydro_ramp(s->ramp, t), dr = hydro_ramp_rate(s->ramp, t);
    for (size_t i = 0; i < n; i++) {
        double value = 0.0, slope = 0.0;
        for (size_t k = 0; k < s->k; k++) {
            double a = s->table_re[k * cols + i], b = s->table_im[k * cols + i];
            value += c->re[k] * a - c->im[k] * b;
            /* Re[i w (p_re + i p_im)(a + i b)] = -w (p_re b + p_im a) */
            slope += -s->omega[k] * (c->re[k] * b + c->im[k] * a);
        }
        rate[i] = dr * value + r * slope;
    }
}
