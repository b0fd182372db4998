/* Viscous forces per degree of freedom (hydro_fmu.drag): F_i = -b_i v_i - q_i |v_i| v_i, linear damping b and
 * quadratic drag q = rho Cd A / 2 on the body velocity (WEC-Sim's per-DOF convention; the orbital velocity of the
 * wave is not subtracted). An explicit function of the current velocity (direct feedthrough); its tangent is
 * dF_i/dv_i = -(b_i + 2 q_i |v_i|). */
#include <math.h>

#include "hydro_internal.h"

int hydro_load_viscous(hydro_shared *s, const wec_data *d, char *msg)
{
    const wec_array *linear, *quadratic;
    int64_t shape[1] = {(int64_t)s->n};
    int st = wec_data_get(d, "viscous.linear", WEC_F64, 1, shape, 0, 1, &linear, msg, HYDRO_MSG_SIZE);
    if (st != WEC_OK)
        return st;
    if ((st = wec_data_get(d, "viscous.quadratic", WEC_F64, 1, shape, linear != NULL, 1, &quadratic, msg,
                           HYDRO_MSG_SIZE)) != WEC_OK)
        return st;
    if (quadratic != NULL && linear == NULL)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_DATA, "runtime data: 'viscous.quadratic' without "
                        "'viscous.linear'");
    if (linear == NULL)
        return WEC_OK;
    s->viscous = 1;
    s->linear = wec_array_copy_f64(linear);
    s->quadratic = wec_array_copy_f64(quadratic);
    if (!s->linear || !s->quadratic)
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    return WEC_OK;
}

double viscous_force(const hydro_shared *s, size_t i, double v)
{
    return -s->linear[i] * v - s->quadratic[i] * fabs(v) * v;
}

double viscous_tangent(const hydro_shared *s, size_t i, double v)
{
    return -s->linear[i] - 2.0 * s->quadratic[i] * fabs(v);
}
