/* wec_dot (dot.h): eight fixed lanes, the same bits on every machine; an AVX2 clone where GCC can make one. */
#include "dot.h"

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && defined(__linux__) && \
    !defined(__SANITIZE_ADDRESS__) && !defined(WEC_NO_CLONES)
#define WEC_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define WEC_CLONES
#endif

WEC_CLONES double wec_dot(const double *a, const double *b, size_t len)
{
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0, s4 = 0, s5 = 0, s6 = 0, s7 = 0;
    size_t f = 0;
    for (; f + 8 <= len; f += 8) {
        s0 += a[f] * b[f];
        s1 += a[f + 1] * b[f + 1];
        s2 += a[f + 2] * b[f + 2];
        s3 += a[f + 3] * b[f + 3];
        s4 += a[f + 4] * b[f + 4];
        s5 += a[f + 5] * b[f + 5];
        s6 += a[f + 6] * b[f + 6];
        s7 += a[f + 7] * b[f + 7];
    }
    double total = ((s0 + s1) + (s2 + s3)) + ((s4 + s5) + (s6 + s7));
    for (; f < len; f++)
        total += a[f] * b[f];
    return total;
}
