/* Dot products for the runtimes' long sums, with independent partial sums in fixed lanes.
 *
 * sum_f a[f] b[f] is taken as interleaved partial sums (element f into lane f % lanes) combined in a fixed order at
 * the end, then the tail. Each lane is a plain sequential sum, so the result is the same bits whatever the vector
 * width the compiler maps the lanes onto (no reassociation beyond this fixed order, no fused multiply-add in ISO C
 * mode): deterministic across machines and builds, while no loop-carried dependency on one accumulator limits the
 * speed (the lanes are written as separate variables so that they stay in registers). Round-off: that of a sum of
 * len / lanes terms per lane plus the combination, about as good as the sequential sum. */
#ifndef WEC_DOT_H
#define WEC_DOT_H

#include <stddef.h>

static inline double wec_dot(const double *a, const double *b, size_t len)
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

/* the four sums sum_f a[f] b_j[f] in one pass over a (four lanes each) */
static inline void wec_dot4(const double *a, const double *b0, const double *b1, const double *b2, const double *b3,
                            size_t len, double out[4])
{
    double p0 = 0, p1 = 0, p2 = 0, p3 = 0, q0 = 0, q1 = 0, q2 = 0, q3 = 0;
    double r0 = 0, r1 = 0, r2 = 0, r3 = 0, u0 = 0, u1 = 0, u2 = 0, u3 = 0;
    size_t f = 0;
    for (; f + 4 <= len; f += 4) {
        double x0 = a[f], x1 = a[f + 1], x2 = a[f + 2], x3 = a[f + 3];
        p0 += x0 * b0[f];
        p1 += x1 * b0[f + 1];
        p2 += x2 * b0[f + 2];
        p3 += x3 * b0[f + 3];
        q0 += x0 * b1[f];
        q1 += x1 * b1[f + 1];
        q2 += x2 * b1[f + 2];
        q3 += x3 * b1[f + 3];
        r0 += x0 * b2[f];
        r1 += x1 * b2[f + 1];
        r2 += x2 * b2[f + 2];
        r3 += x3 * b2[f + 3];
        u0 += x0 * b3[f];
        u1 += x1 * b3[f + 1];
        u2 += x2 * b3[f + 2];
        u3 += x3 * b3[f + 3];
    }
    out[0] = (p0 + p1) + (p2 + p3);
    out[1] = (q0 + q1) + (q2 + q3);
    out[2] = (r0 + r1) + (r2 + r3);
    out[3] = (u0 + u1) + (u2 + u3);
    for (; f < len; f++) {
        double x = a[f];
        out[0] += x * b0[f];
        out[1] += x * b1[f];
        out[2] += x * b2[f];
        out[3] += x * b3[f];
    }
}

#endif
