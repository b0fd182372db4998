/* The incident wave field away from the origin, for the nonlinear Froude-Krylov force
 * (hydro_fmu.nonlinear_hydrostatics._IncidentPressure): with c_k = r(t) a_k exp(i phi_k) and the wave vectors
 * (k_x, k_y) of spreading.c,
 *
 *     eta(x, y, t) = Re sum_k c_k exp(i (omega_k t - k_x x - k_y y)),
 *     p_d(x, y, z, t) = rho g Re sum_k c_k E_k(z) exp(i (omega_k t - k_x x - k_y y)),
 *
 * E_k(z) = exp(k z) in deep water and cosh(k (z + h)) / cosh(k h) at depth h, z clipped at 0 above the still
 * water level (constant extrapolation of the linear pressure into crests). The finite-depth factor is evaluated
 * as exp(k z) (1 + exp(-2 k (z + h))) / (1 + exp(-2 k h)), equal to the ratio of cosines and free of their
 * overflow for large k h. */
#include <math.h>

#include "hydro_internal.h"

double incident_elevation(const hydro_shared *s, double ramp, double t, double x, double y)
{
    double sum = 0.0;
    for (size_t k = 0; k < s->k; k++) {
        double phase = s->omega[k] * t - (x * s->kx[k] + y * s->ky[k]);
        sum += cos(phase) * (s->amp_re[k] * ramp) - sin(phase) * (s->amp_im[k] * ramp);
    }
    return sum;
}

double incident_pressure(const hydro_shared *s, double ramp, double t, const double *p)
{
    double z = p[2] < 0.0 ? p[2] : 0.0;
    double sum = 0.0;
    int deep = isinf(s->depth);
    for (size_t k = 0; k < s->k; k++) {
        double kk = s->wavenumber[k];
        double factor = exp(kk * z);
        if (!deep)
            factor = factor * (1.0 + exp(-2.0 * kk * (z + s->depth))) / (1.0 + exp(-2.0 * kk * s->depth));
        double phase = s->omega[k] * t - (p[0] * s->kx[k] + p[1] * s->ky[k]);
        sum += factor * (cos(phase) * (s->amp_re[k] * ramp) - sin(phase) * (s->amp_im[k] * ramp));
    }
    return s->rho * s->g * sum;
}
