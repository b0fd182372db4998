/* Wave excitation by convolution of the excitation impulse response with the elevation at the origin
 * (seed paper 000; hydro_fmu.excitation.ExcitationConvolution):
 *
 *     F_exc(t) = r(t) sum_j W_j eta(t - tau_j),   W_j = w_j K_ex(tau_j),   tau_j in [-T, T]
 *
 * with the trapezoidal weights w_j already in the prepared kernel (L, n): second order in the step for a smooth
 * elevation; non-causal (it reads the elevation up to T ahead, which is known for records and synthetic seas).
 * eta is unramped: the imported record (linear interpolation, periodic), or the sum of the components. For the
 * components the sum over j is taken per component once, at creation, as the transfer of the weighted kernel
 *
 *     H_k = sum_j W_j exp(-i omega_k tau_j),   F_exc(t) = r(t) Re sum_k a_k exp(i phi_k) H_k exp(i omega_k t),
 *
 * the same products summed in the other order (equal to round-off), so a point costs K products instead of L K
 * exponentials. The rate is the central difference (F(t + d) - F(t - d)) / (2 d), d = 1e-4 s, as the Python model
 * takes it (error d^2/6 F''', about 1e-8 of F for wave periods above 1 s). */
#include <math.h>

#include "hydro_internal.h"

int hydro_load_excitation_convolution(hydro_shared *s, const wec_data *d, char *msg)
{
    if (s->excitation != EXCITATION_CONVOLUTION)
        return WEC_OK;
    const wec_array *tau, *kernel;
    int st = wec_data_get(d, "excitation.tau", WEC_F64, 1, NULL, 1, 1, &tau, msg, HYDRO_MSG_SIZE);
    if (st != WEC_OK)
        return st;
    s->taus = (size_t)tau->shape[0];
    if (s->taus < 1)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'excitation.tau' is empty");
    int64_t shape[2] = {(int64_t)s->taus, (int64_t)s->n};
    if ((st = wec_data_get(d, "excitation.kernel", WEC_F64, 2, shape, 1, 1, &kernel, msg, HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    s->tau = wec_array_copy_f64(tau);
    s->kernel_ex = wec_array_copy_f64(kernel);
    if (!s->tau || !s->kernel_ex)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    for (size_t j = 1; j < s->taus; j++)
        if (!(s->tau[j] > s->tau[j - 1]))
            return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'excitation.tau' must increase "
                            "strictly (element %zu)", j);
    return WEC_OK;
}

int excitation_convolution_prepare(hydro_shared *s, char *msg)
{
    if (s->excitation != EXCITATION_CONVOLUTION || s->samples > 0)
        return WEC_OK;
    size_t n = s->n, kn = s->k * n;
    s->transfer_re = wec_alloc_f64(kn);
    s->transfer_im = wec_alloc_f64(kn);
    if (!s->transfer_re || !s->transfer_im)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    for (size_t k = 0; k < s->k; k++) {
        double *re = s->transfer_re + k * n, *im = s->transfer_im + k * n;
        for (size_t j = 0; j < s->taus; j++) {
            double phase = -s->omega[k] * s->tau[j], c = cos(phase), sn = sin(phase);
            const double *w = s->kernel_ex + j * n;
            for (size_t i = 0; i < n; i++) {
                re[i] += w[i] * c;
                im[i] += w[i] * sn;
            }
        }
        /* times the component's complex amplitude */
        for (size_t i = 0; i < n; i++) {
            double a = re[i], b = im[i];
            re[i] = s->amp_re[k] * a - s->amp_im[k] * b;
            im[i] = s->amp_re[k] * b + s->amp_im[k] * a;
        }
    }
    return WEC_OK;
}

/* sum_j W_j eta(t - tau_j) of the record, unramped, into out (n) */
static void record_sum(const hydro_shared *s, double t, double *eta_window, double *out)
{
    size_t n = s->n;
    for (size_t j = 0; j < s->taus; j++)
        eta_window[j] = record_elevation(s, t - s->tau[j]);
    for (size_t i = 0; i < n; i++) {
        double sum = 0.0;
        for (size_t j = 0; j < s->taus; j++)
            sum += eta_window[j] * s->kernel_ex[j * n + i];
        out[i] = sum;
    }
}

/* Re sum_k T_k exp(i omega_k t) exp(i omega_k shift) per DOF, unramped, into out (n) */
static void transfer_sum(const hydro_shared *s, double t, double shift, double *out)
{
    size_t n = s->n;
    for (size_t i = 0; i < n; i++)
        out[i] = 0.0;
    for (size_t k = 0; k < s->k; k++) {
        double phase = s->omega[k] * t + s->omega[k] * shift, c = cos(phase), sn = sin(phase);
        const double *re = s->transfer_re + k * n, *im = s->transfer_im + k * n;
        for (size_t i = 0; i < n; i++)
            out[i] += c * re[i] - sn * im[i];
    }
}

static void unramped(const hydro_shared *s, double t, double shift, double *eta_window, double *out)
{
    if (s->samples > 0)
        record_sum(s, t + shift, eta_window, out);
    else
        transfer_sum(s, t, shift, out);
}

void excitation_convolution(const hydro_shared *s, double t, double *eta_window, double *exc)
{
    unramped(s, t, 0.0, eta_window, exc);
    double r = hydro_ramp(s->ramp, t);
    for (size_t i = 0; i < s->n; i++)
        exc[i] = r * exc[i];
}

void excitation_convolution_rate(const hydro_shared *s, double t, double *eta_window, double *rate, double *tmp)
{
    unramped(s, t, RATE_DELTA, eta_window, tmp);
    unramped(s, t, -RATE_DELTA, eta_window, rate);
    double ahead = hydro_ramp(s->ramp, t + RATE_DELTA), behind = hydro_ramp(s->ramp, t - RATE_DELTA);
    for (size_t i = 0; i < s->n; i++)
        rate[i] = (ahead * tmp[i] - behind * rate[i]) / (2 * RATE_DELTA);
}
