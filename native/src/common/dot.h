/* Dot products for the runtimes' long sums, with independent partial sums in fixed lanes.
 *
 * sum_f a[f] b[f] is taken as eight interleaved partial sums (element f into lane f % 8) combined in a fixed order
 * at the end, then the tail. Each lane is a plain sequential sum, so the result is the same bits whatever the
 * vector width the compiler maps the lanes onto (no reassociation beyond this fixed order, no fused multiply-add in
 * ISO C mode): deterministic across machines and builds, while the lanes need no loop-carried dependency on one
 * accumulator (the compiler keeps them in vector registers). Round-off: that of a sum of len / 8 terms per lane
 * plus the combination, about as good as the sequential sum. */
#ifndef WEC_DOT_H
#define WEC_DOT_H

#include <stddef.h>

static inline double wec_dot(const double *a, const double *b, size_t len)
{
    double s[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    size_t f = 0;
    for (; f + 8 <= len; f += 8)
        for (int l = 0; l < 8; l++)
            s[l] += a[f + l] * b[f + l];
    double total = ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
    for (; f < len; f++)
        total += a[f] * b[f];
    return total;
}

/* the four sums sum_f a[f] b_j[f] in one pass over a (four lanes each) */
static inline void wec_dot4(const double *a, const double *b0, const double *b1, const double *b2, const double *b3,
                            size_t len, double out[4])
{
    double s0[4] = {0, 0, 0, 0}, s1[4] = {0, 0, 0, 0}, s2[4] = {0, 0, 0, 0}, s3[4] = {0, 0, 0, 0};
    size_t f = 0;
    for (; f + 4 <= len; f += 4)
        for (int l = 0; l < 4; l++) {
            double x = a[f + l];
            s0[l] += x * b0[f + l];
            s1[l] += x * b1[f + l];
            s2[l] += x * b2[f + l];
            s3[l] += x * b3[f + l];
        }
    out[0] = (s0[0] + s0[1]) + (s0[2] + s0[3]);
    out[1] = (s1[0] + s1[1]) + (s1[2] + s1[3]);
    out[2] = (s2[0] + s2[1]) + (s2[2] + s2[3]);
    out[3] = (s3[0] + s3[1]) + (s3[2] + s3[3]);
    for (; f < len; f++) {
        double x = a[f];
        out[0] += x * b0[f];
        out[1] += x * b1[f];
        out[2] += x * b2[f];
        out[3] += x * b3[f];
    }
}

#endif
