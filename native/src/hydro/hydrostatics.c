/* Linear hydrostatic restoring force about equilibrium (hydro_fmu.hydrostatics.LinearHydrostatics):
 * F_hs = -C x, C the block-diagonal restoring matrix of the bodies about their centres of gravity (buoyancy only;
 * weight and mean buoyancy balance at equilibrium and are left out). Exact; no time discretisation. */
#include "hydro_internal.h"

int hydro_load_hydrostatics(hydro_shared *s, const wec_data *d, char *msg)
{
    if (s->hydrostatics != HYDROSTATICS_LINEAR)
        return WEC_OK;
    const wec_array *c;
    int64_t shape[2] = {(int64_t)s->n, (int64_t)s->n};
    int st = wec_data_get(d, "hydrostatics.stiffness", WEC_F64, 2, shape, 1, 1, &c, msg, HYDRO_MSG_SIZE);
    if (st != WEC_OK)
        return st;
    if (!(s->restoring = wec_alloc_f64(s->n * s->n)))
        return wec_fail(msg, HYDRO_MSG_SIZE, WEC_ERR_MEMORY, "out of memory");
    for (size_t i = 0; i < s->n * s->n; i++)
        s->restoring[i] = -wec_array_f64(c, i);
    return WEC_OK;
}

void hydrostatics_linear(const hydro_shared *s, const double *x, double *f)
{
    size_t n = s->n;
    for (size_t i = 0; i < n; i++) {
        double sum = 0.0;
        for (size_t j = 0; j < n; j++)
            sum += s->restoring[i * n + j] * x[j];
        f[i] = sum;
    }
}
