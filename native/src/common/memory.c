/* Checked size arithmetic and zeroed allocation. */
#include <stdlib.h>

#include "wec_common.h"

int wec_mul(size_t a, size_t b, size_t *out)
{
    if (a != 0 && b > SIZE_MAX / a)
        return 0;
    *out = a * b;
    return 1;
}

int wec_add(size_t a, size_t b, size_t *out)
{
    if (b > SIZE_MAX - a)
        return 0;
    *out = a + b;
    return 1;
}

double *wec_alloc_f64(size_t count) { return calloc(count ? count : 1, sizeof(double)); }

int64_t *wec_alloc_i64(size_t count) { return calloc(count ? count : 1, sizeof(int64_t)); }
